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

use nav_runtime::ekf::{Ekf, SetupError};
use nav_runtime::lockout::LockoutRelease;

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
}

impl Default for LockoutOptions {
    fn default() -> Self {
        Self {
            rule: LockoutRelease::default(),
            depth_m: 20.0,
            dvl_m_s: 3.0,
            heading_rad: core::f64::consts::FRAC_PI_4,
            usbl_m: 500.0,
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
    Ok(ekf)
}
