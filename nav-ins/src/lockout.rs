//! The gate lock-out release of the INS filters ([`nav_runtime::lockout`],
//! docs/lockout.md): the rule and the physical plausibility bound of each
//! aiding sensor's innovation.
//!
//! A bound is the largest filter error, seen through the sensor, that is
//! still physically possible for an AUV navigating on an aided INS; a run of
//! refused innovations beyond it is a sensor fault and never releases the
//! gate. The bounds are far above every lock-out seen in the simulations
//! (depth 1.5 m, compass 10 deg) and far below the gross faults they must
//! stop (a 100 m depth step, a 180 deg compass flip, a DVL reading 30 m/s, a
//! USBL fix 10 km off).
//!
//! Those bounds are on the innovation, so they also keep a filter that has
//! diverged (its error seen through the sensor beyond the bound) locked out
//! for good. The recovery rule of each sensor ([`nav_runtime::recovery`],
//! [`RecoveryRules`]) judges the sensor's *readings* instead and recovers
//! such a filter.

use nav_runtime::ekf::{Ekf, SetupError};
use nav_runtime::lockout::LockoutRelease;
use nav_runtime::recovery::RecoveryRule;

use super::vehicle::{InsVehicle, Slot};

/// Lock-out release settings of an INS filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockoutOptions {
    /// Run length and agreement probability.
    pub rule: LockoutRelease,
    /// Bound of the depth innovation (m): a vertical error of 20 m is not
    /// possible with a depth meter that was accepted before.
    pub depth_m: f64,
    /// Bound of each DVL velocity innovation component (m/s): 3 m/s is above
    /// the cruising speed of a survey AUV (about 1.5-2 m/s).
    pub dvl_m_s: f64,
    /// Bound of the compass innovation (rad): 45 deg.
    pub heading_rad: f64,
    /// Bound of each horizontal USBL innovation component (m): 500 m, about
    /// 14 times the Trackpoint II noise plus bias (18 m each) and 100 times
    /// the aided INS's drift over the 500 s survey.
    pub usbl_m: f64,
    /// Recovery from a lock-out into divergence (`None`: never).
    pub recovery: Option<RecoveryRules>,
    /// How far back a recovery may take the filter, s (0: never). A
    /// recovery of a sensor none of whose readings has been accepted yet
    /// (the run of refusals began with its first reading: `[initial]` is
    /// wrong) takes the filter back to the first of them and recovers
    /// there, so that the readings of the run correct it (docs/lockout.md,
    /// "Rollback"); a run that began longer ago recovers where it was
    /// found. The navigator keeps this much history.
    pub rollback_s: f64,
}

impl Default for LockoutOptions {
    fn default() -> Self {
        Self {
            rule: LockoutRelease::default(),
            depth_m: 20.0,
            dvl_m_s: 3.0,
            heading_rad: core::f64::consts::FRAC_PI_4,
            usbl_m: 500.0,
            recovery: Some(RecoveryRules::default()),
            rollback_s: 10.0,
        }
    }
}

/// The recovery rule of each aiding sensor ([`nav_runtime::recovery`];
/// docs/lockout.md, "Recovery"): how long its readings must be refused
/// while plausible and agreeing with one another before the filter is
/// taken to be wrong, how large a plausible reading is, and how fast the
/// vehicle can change it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecoveryRules {
    /// Depth meter (reading: depth, m): 5 s and 3 readings; plausible
    /// within 11 000 m (the deepest ocean); the depth changes by at most
    /// 3 m/s (an AUV dives at well under 1 m/s).
    pub depth: RecoveryRule,
    /// DVL (reading: body velocity, m/s): 2 s and 3 readings; plausible up to
    /// 5 m/s in magnitude (a survey AUV cruises at 1.5-2 m/s); each axis
    /// changes by at most 2 m/s per s. A recovery also scales the velocity
    /// and tilt errors (eq. R1; [`configure`] names them) and raises the
    /// tilt sigmas to the tilt that explains the refused innovation's growth
    /// since the previous reading (eq. R3): a velocity error the DVL cannot explain comes from a
    /// tilt error, which only the velocity's growth over the next readings
    /// shows. Not the heading error: without a compass nothing would hold
    /// it. The horizon was 5 s: an unaided INS with a tilt error of degrees
    /// gains about 1 m/s of velocity error a second (`g` times the tilt),
    /// tens of metres of position error before a 5-s horizon ended.
    pub dvl: RecoveryRule,
    /// Compass (reading: heading, rad): 5 s and 3 readings; any heading is
    /// plausible; the heading changes by at most 0.5 rad/s (29 deg/s).
    pub heading: RecoveryRule,
    /// USBL (reading: fix north and east of the transducer, m): 30 s and 3
    /// fixes; any position is plausible; each axis changes by at most 5 m/s.
    pub usbl: RecoveryRule,
}

impl Default for RecoveryRules {
    fn default() -> Self {
        // Every value below is valid (tested), so the fallback, a rule that
        // never recovers in practice, is not reached.
        let rule = |horizon_s, refusals, bound, rate| {
            RecoveryRule::new(horizon_s, refusals, bound, rate).unwrap_or(RecoveryRule {
                horizon_s: f64::MAX,
                min_refusals: u32::MAX,
                reading_bound: 0.0,
                rate_bound: 0.0,
                scaled_states: 0,
            })
        };
        Self {
            depth: rule(5.0, 3, 11_000.0, 3.0),
            dvl: rule(2.0, 3, 5.0, 2.0),
            heading: rule(5.0, 3, f64::INFINITY, 0.5),
            usbl: rule(30.0, 3, f64::INFINITY, 5.0),
        }
    }
}

/// `ekf` with the release rule of `options` and the bounds of the sensors
/// vehicle `V` has (`None`: no release, a refused sensor stays refused).
///
/// # Errors
/// [`SetupError::Invalid`] for a bound that is not positive.
pub fn configure<V: InsVehicle<N>, const N: usize>(
    ekf: Ekf<V, N>,
    options: Option<LockoutOptions>,
) -> Result<Ekf<V, N>, SetupError> {
    let Some(o) = options else {
        return Ok(ekf.with_lockout_release(None));
    };
    let mut ekf = ekf.with_lockout_release(Some(o.rule));
    let bounds = [
        (<V::Depth as Slot<V, N, 1>>::NAME, o.depth_m),
        (<V::Dvl as Slot<V, N, 3>>::NAME, o.dvl_m_s),
        (<V::Compass as Slot<V, N, 1>>::NAME, o.heading_rad),
        (<V::CompassSmallAngle as Slot<V, N, 1>>::NAME, o.heading_rad),
        (<V::Usbl as Slot<V, N, 2>>::NAME, o.usbl_m),
    ];
    for (name, bound) in bounds {
        // An absent sensor has no name and nothing to bound.
        if !name.is_empty() {
            ekf.set_lockout_bound(name, bound)?;
        }
    }
    if let Some(r) = o.recovery {
        let dvl_states = [
            "velocity_error[0]",
            "velocity_error[1]",
            "velocity_error[2]",
            "attitude_error[0]",
            "attitude_error[1]",
        ]
        .iter()
        .filter_map(|name| V::STATE_NAMES.iter().position(|s| s == name))
        .filter(|&j| j < 64)
        .fold(0u64, |mask, j| mask | (1u64 << j));
        let rules = [
            (<V::Depth as Slot<V, N, 1>>::NAME, r.depth),
            (
                <V::Dvl as Slot<V, N, 3>>::NAME,
                r.dvl.with_scaled_states(dvl_states),
            ),
            (<V::Compass as Slot<V, N, 1>>::NAME, r.heading),
            (<V::CompassSmallAngle as Slot<V, N, 1>>::NAME, r.heading),
            (<V::Usbl as Slot<V, N, 2>>::NAME, r.usbl),
        ];
        for (name, rule) in rules {
            if !name.is_empty() {
                ekf.set_recovery_rule(name, Some(rule))?;
            }
        }
    }
    Ok(ekf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_recovery_rules_are_valid() {
        let r = RecoveryRules::default();
        for rule in [r.depth, r.dvl, r.heading, r.usbl] {
            let again = RecoveryRule::new(
                rule.horizon_s,
                rule.min_refusals,
                rule.reading_bound,
                rule.rate_bound,
            );
            assert_eq!(again, Ok(rule));
        }
        assert_eq!((r.dvl.horizon_s, r.dvl.min_refusals), (2.0, 3));
    }
}
