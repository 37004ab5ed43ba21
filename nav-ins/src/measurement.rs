//! The aiding measurements of an INS vehicle's log sensors (depth meter,
//! DVL, compass, USBL, GNSS fix, barometer, magnetometer) as scheduler
//! measurements: each computes its residual
//! from the nominal solution at the time it is applied (so a late measurement
//! replayed at its own time sees the nominal of that time).

use nav_runtime::attitude::euler_from_c_bn;
use nav_runtime::earth::{
    meridian_radius, normal_gravity_ned, transverse_radius, Geodetic, LocalNed,
};
use nav_runtime::ekf::FilterError;
use nav_runtime::math::wrap_angle;
use nav_runtime::nalgebra::{SVector, Vector2, Vector3};
use nav_runtime::recovery::Judgement;
use nav_runtime::scheduler::{FnMeasurement, Measurement, MeasurementOutcome};

use super::nominal::InsFilter;
use super::sensor::GnssFix;
use super::vehicle::{InsVehicle, Slot};

/// Which compass residual the filter uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CompassForm {
    /// Exact yaw of the perturbed attitude (`Sdins25Compass`).
    #[default]
    Exact,
    /// The paper's small-angle `-phi_D - b_psi` (`Sdins25CompassSmallAngle`).
    SmallAngle,
}

fn outcome<const M: usize>(
    r: Result<nav_runtime::ekf::UpdateReport<M>, FilterError>,
) -> Result<MeasurementOutcome, FilterError> {
    r.map(|rep| MeasurementOutcome::from(&rep))
}

/// [`Slot::update`] of slot `S`, then its recovery step
/// ([`Slot::recover`]) with the sensor's own `reading` and its noise. After
/// a recovery of a `velocity` sensor (a DVL: `M` = 3; the residual of
/// either DVL block, the INS velocity less the rotated reading, is in NED)
/// two more steps follow
/// (docs/lockout.md):
///
/// - eq. R3: the tilt sigmas (about north and east) are raised to at least
///   `|nu_k - nu_k-1| / (g dt)`, the tilt whose gravity error makes the
///   refused innovation grow as it did since the previous reading. Step R1
///   scales the tilt by the refused innovation's NIS, whose covariance the
///   sensor noise dominates: a tilt of degrees (a wrong initial attitude)
///   kept a sigma of hundredths of a degree, the next readings reset the
///   velocity, left the tilt, and were refused again. A velocity step (a
///   burst of wrong specific force) makes the innovation jump, not grow,
///   and is left to R1. Every tilt sigma is then held at most
///   [`MAX_RECOVERED_TILT_SIGMA`].
/// - eq. R4: the horizontal position covariance gains `d d^T` (the height
///   too without a vertical aid), `d` the position error
///   the refused readings' velocity errors built: each innovation joining
///   the run (in NED) times the time since the previous reading,
///   summed from the last accepted reading. R1 to R3 restore the velocity
///   and tilt; the position error built meanwhile stays, and a DVL does not
///   see it. Without R4 the position sigma stayed as it was (and the
///   velocity-position correlations R1 keeps made the readings after the
///   recovery lower it further), while the error had grown by metres.
fn update_and_recover<V, S, const N: usize, const M: usize>(
    f: &mut InsFilter<V, N>,
    z: &SVector<f64, M>,
    r: &SVector<f64, M>,
    aux: &[f64],
    reading: &[f64],
    sigma: &[f64],
    velocity: bool,
) -> Result<MeasurementOutcome, FilterError>
where
    V: InsVehicle<N>,
    S: Slot<V, N, M>,
{
    let mut result = S::update(f, z, r, aux);
    if let Ok(report) = result.as_mut() {
        let velocity = velocity && M == 3;
        // The innovation, the time since the previous reading (s) and the
        // innovation's growth over it (m/s per s).
        let mut nu = Vector3::zeros();
        let mut since = None;
        let mut growth = None;
        if velocity {
            let now = f.ekf().clock_s();
            nu = Vector3::from_fn(|i, _| report.innovation.get(i).copied().unwrap_or(0.0));
            if let Some((then, previous)) = f.nominal().dvl_innovation {
                if now > then {
                    since = Some(now - then);
                    growth = Some((nu - previous).norm() / (now - then));
                }
            }
            f.nominal_mut().dvl_innovation = Some((now, nu));
        }
        let judgement = S::recover(f, report, reading, sigma, aux);
        if velocity {
            let nominal = f.nominal_mut();
            if report.accepted {
                nominal.dvl_refused_drift = Vector3::zeros();
            } else if let (Judgement::Following | Judgement::Recover(_), Some(dt)) =
                (judgement, since)
            {
                // A reading that joined the run: its velocity error over
                // the interval before it. A miss (a glitch) adds nothing.
                nominal.dvl_refused_drift += nu * dt;
            }
        }
        if report.recovered.is_some() {
            if let Some(growth) = growth {
                // Eq. R3: the tilt whose gravity error builds that growth.
                let floor = growth / nav_runtime::earth::G0;
                if floor.is_finite() {
                    set_tilt_sigmas(f, |sigma| sigma.max(floor));
                }
            }
            set_tilt_sigmas(f, |sigma| sigma.min(MAX_RECOVERED_TILT_SIGMA));
            if velocity {
                // Eq. R4.
                let drift =
                    core::mem::replace(&mut f.nominal_mut().dvl_refused_drift, Vector3::zeros());
                add_position_drift(f, &drift);
            }
        }
    }
    outcome(result)
}

/// `P <- P + d d^T` on the horizontal position errors, `d` a position
/// error given in NED (m) and taken to the layout's latitude and longitude
/// errors (rad) at the nominal position, and `P <- P + d_D^2` on the height
/// error (m, up) only for a vehicle with no vertical aid (depth meter,
/// barometer, GNSS fix): eq. R4 of docs/lockout.md. A vertical aid's
/// readings were accepted all through the run, so the height error is not
/// the run's `d_D`; a Monte Carlo of IMU transients with it (and its
/// horizontal-vertical terms) lost up to 14 m of median final error, as
/// the next depth readings moved the velocity and horizontal position. A
/// covariance that would not be valid, or a `d` that is not finite, leaves
/// `P` as it was.
fn add_position_drift<V: InsVehicle<N>, const N: usize>(
    f: &mut InsFilter<V, N>,
    drift_ned: &Vector3<f64>,
) {
    if !drift_ned.iter().all(|v| v.is_finite()) || *drift_ned == Vector3::zeros() {
        return;
    }
    let s = &f.nominal().ins.state;
    let d = [
        drift_ned[0] / (meridian_radius(s.lat) + s.h),
        drift_ned[1] / ((transverse_radius(s.lat) + s.h) * s.lat.cos()),
        -drift_ned[2],
    ];
    // At a pole the longitude error has no size: leave `P` alone.
    if !d.iter().all(|v| v.is_finite()) {
        return;
    }
    let nav = f.nominal().layout().navigation();
    let mut p = *f.covariance();
    // A vehicle with a vertical aid had it accepted through the run.
    let vertical_aid = <V::Depth as Slot<V, N, 1>>::PRESENT
        || <V::Baro as Slot<V, N, 1>>::PRESENT
        || <V::Gnss as Slot<V, N, 3>>::PRESENT;
    let pairs: &[(usize, usize)] = if vertical_aid {
        &[(0, 0), (0, 1), (1, 0), (1, 1)]
    } else {
        &[(0, 0), (0, 1), (1, 0), (1, 1), (2, 2)]
    };
    for &(a, b) in pairs {
        p[(nav[a], nav[b])] += d[a] * d[b];
    }
    let _ = f.ekf_mut().set_covariance(p);
}

/// Largest tilt sigma (rad, about north and east) a lock-out recovery
/// leaves: 0.5 rad (29 deg). The recovery inflates the states a refused
/// sensor observes by the size of its innovation; an innovation of tens
/// of m/s (an INS fed rates in the wrong unit) would allot radians of tilt,
/// and the small-angle feedback of such a correction ends in a solution
/// that is not finite instead of the out-of-bounds error that names the
/// doubtful input.
pub const MAX_RECOVERED_TILT_SIGMA: f64 = 0.5;

/// `D P D`, with `D` setting each tilt sigma (rad, about north and east)
/// to `target(sigma)`; correlations are kept (symmetric and positive
/// semi-definite as `P` is).
fn set_tilt_sigmas<V: InsVehicle<N>, const N: usize>(
    f: &mut InsFilter<V, N>,
    target: impl Fn(f64) -> f64,
) {
    let nav = f.nominal().layout().navigation();
    let mut p = *f.covariance();
    let mut d = [1.0; N];
    let mut changed = false;
    for i in [nav[6], nav[7]] {
        let sigma = p[(i, i)].max(0.0).sqrt();
        let wanted = target(sigma);
        if sigma > 0.0 && wanted != sigma && wanted.is_finite() {
            d[i] = wanted / sigma;
            changed = true;
        }
    }
    if !changed {
        return;
    }
    for i in 0..N {
        for j in 0..N {
            p[(i, j)] *= d[i] * d[j];
        }
    }
    // A covariance that was valid stays valid; if not, it stays as it was.
    let _ = f.ekf_mut().set_covariance(p);
}

/// A depth-meter measurement (`depth`: m, positive down) with noise sigma (m),
/// for the `Depth` sensor of vehicle `V`.
pub fn depth_measurement<V: InsVehicle<N>, const N: usize>(
    depth: f64,
    sigma: f64,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    depth_measurement_at::<V, N>(depth, sigma, Vector3::zeros())
}

/// A depth reading of a sensor at lever arm `lever_arm` (body axes, m) from
/// the IMU, for a depth slot whose block takes the lever arm as its
/// auxiliary input (a pressure sensor): the INS height of the sensor is
/// `h - (C_b^n r)_D`. A block without that input takes the reading at the
/// IMU (the lever arm must then be zero: [`depth_measurement`]).
pub fn depth_measurement_at<V: InsVehicle<N>, const N: usize>(
    depth: f64,
    sigma: f64,
    lever_arm: Vector3<f64>,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let h_meas = -depth;
    let r = SVector::<f64, 1>::new(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[h_meas],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let s = &nom.ins.state;
            let sensor_h = s.h - (s.c_bn * lever_arm)[2];
            let z = SVector::<f64, 1>::new(sensor_h - (h_meas - nom.depth_bias));
            update_and_recover::<V, V::Depth, N, 1>(
                f,
                &z,
                &r,
                lever_arm.as_slice(),
                &[depth],
                &[sigma],
                false,
            )
        },
    ))
}

/// A DVL measurement (body velocity, m/s) with noise sigma per axis (m/s),
/// for the `Dvl` sensor of vehicle `V`.
pub fn dvl_measurement<V: InsVehicle<N>, const N: usize>(
    v: Vector3<f64>,
    sigma: f64,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    dvl_measurement_at::<V, N>(v, sigma, Vector3::zeros())
}

/// A DVL measurement (body axes, m/s) of a DVL at lever arm `lever_arm`
/// (body axes, m) from the IMU: the DVL moves at the IMU's velocity plus
/// `omega x r`, with `omega` the bias-corrected body rate of the IMU sample
/// at the reading's time ([`super::InsNominal::body_rate`]), so the residual
/// is `v_n - C (v - b - omega x r)`. The block's Jacobian leaves out the
/// gyro-bias error's share of `omega x r` (`r x delta b_g`: 0.1 mm/s for a
/// 1 m arm and a 1e-4 rad/s bias error, far below a DVL's noise).
///
/// For a vehicle whose DVL slot holds the `DvlCalibrated` block, the
/// residual is `v_n - C (v - b)` and the block's `h` predicts the reading
/// from the lever arm (given value plus its estimated error), the
/// misalignment and the scale states (docs/calibration.md).
pub fn dvl_measurement_at<V: InsVehicle<N>, const N: usize>(
    v: Vector3<f64>,
    sigma: f64,
    lever_arm: Vector3<f64>,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 3>::repeat(sigma.powi(2));
    Box::new(FnMeasurement::new(
        v.as_slice(),
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let s = &nom.ins.state;
            if <V::Dvl as Slot<V, N, 3>>::AUX_NAMES.is_empty() {
                let arm = nom.body_rate.cross(&lever_arm);
                let z = s.v_n - s.c_bn * (v - nom.dvl_bias - arm);
                return update_and_recover::<V, V::Dvl, N, 3>(
                    f,
                    &z,
                    &r,
                    &[],
                    v.as_slice(),
                    &[sigma; 3],
                    true,
                );
            }
            // A calibrated DVL block (`DvlCalibrated`): its `h` carries the
            // lever arm (given value plus its error state), the scale, the
            // misalignment and the clock lag, so the residual is the
            // reading's alone. The lag's input is the rate of change of
            // the body-axes velocity, `f + C^T g - w x C^T V` (Coriolis and
            // transport rate left out: 2e-4 m/s^2 at 1.5 m/s, 0.2 mm/s over
            // a lag of a second).
            let w = nom.body_rate;
            let c_nb = s.c_bn.transpose();
            let gravity = normal_gravity_ned(s.lat, s.h);
            let a = nom.specific_force + c_nb * gravity - w.cross(&(c_nb * s.v_n));
            let aux = [
                lever_arm.x,
                lever_arm.y,
                lever_arm.z,
                w.x,
                w.y,
                w.z,
                a.x,
                a.y,
                a.z,
            ];
            let z = s.v_n - s.c_bn * (v - nom.dvl_bias);
            update_and_recover::<V, V::Dvl, N, 3>(f, &z, &r, &aux, v.as_slice(), &[sigma; 3], true)
        },
    ))
}

/// A compass measurement (heading `psi`, rad) with noise sigma (rad), for the
/// `Compass` or `CompassSmallAngle` sensor of vehicle `V`.
pub fn heading_measurement<V: InsVehicle<N>, const N: usize>(
    psi: f64,
    sigma: f64,
    form: CompassForm,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 1>::new(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[psi],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let yaw = euler_from_c_bn(&nom.ins.state.c_bn).yaw;
            let z = SVector::<f64, 1>::new(wrap_angle(yaw - (psi - nom.compass_bias)));
            match form {
                CompassForm::Exact => update_and_recover::<V, V::Compass, N, 1>(
                    f,
                    &z,
                    &r,
                    &[],
                    &[psi],
                    &[sigma],
                    false,
                ),
                CompassForm::SmallAngle => update_and_recover::<V, V::CompassSmallAngle, N, 1>(
                    f,
                    &z,
                    &r,
                    &[],
                    &[psi],
                    &[sigma],
                    false,
                ),
            }
        },
    ))
}

/// A USBL fix (`lat`, `lon`: rad) with noise sigma per axis (m) from the
/// transducer at the origin of `frame`, for the `Usbl` sensor of vehicle `V`.
pub fn usbl_measurement<V: InsVehicle<N>, const N: usize>(
    lat: f64,
    lon: f64,
    sigma: f64,
    frame: LocalNed,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    usbl_measurement_at::<V, N>(lat, lon, sigma, frame, Vector3::zeros())
}

/// A USBL fix of a transponder at lever arm `transponder` (body axes, m)
/// from the IMU: the fix is compared with the INS position moved by
/// `C_b^n r` (north and east), and the array misalignment acts on the
/// transponder's position relative to the transducer. The block's Jacobian
/// leaves out the attitude error's share of `C_b^n r` (`|r| |psi|`: 2 mm for
/// a 2 m arm and a 1 mrad error, far below a USBL's metre-level noise).
pub fn usbl_measurement_at<V: InsVehicle<N>, const N: usize>(
    lat: f64,
    lon: f64,
    sigma: f64,
    frame: LocalNed,
    transponder: Vector3<f64>,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 2>::repeat(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[lat, lon],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let s = &nom.ins.state;
            let arm = s.c_bn * transponder;
            let rel = frame.geodetic_to_ned(&s.position()) + arm;
            let dn = (meridian_radius(s.lat) + s.h) * (s.lat - lat) + arm.x;
            let de =
                (transverse_radius(s.lat) + s.h) * s.lat.cos() * wrap_angle(s.lon - lon) + arm.y;
            let tilt = nom.usbl_misalignment.cross(&rel);
            let z = Vector2::new(dn, de) + nom.usbl_bias + Vector2::new(tilt.x, tilt.y);
            // The fix itself, in metres north and east of the transducer.
            let fix = frame.geodetic_to_ned(&Geodetic::new(lat, lon, s.h));
            update_and_recover::<V, V::Usbl, N, 2>(
                f,
                &z,
                &r,
                rel.as_slice(),
                &[fix.x, fix.y],
                &[sigma; 2],
                false,
            )
        },
    ))
}

/// A GNSS fix of the antenna at lever arm `antenna` (body axes, m) from the
/// IMU, with noise sigma `sigma` (m; a receiver accuracy larger than it is
/// used instead), for the `GnssFix` sensor of vehicle `V`: the residual is
/// the INS antenna position minus the fix, metres north and east and height,
/// `[(R_M + h)(L - L_fix) + (C r)_N, (R_N + h) cos L (l - l_fix) + (C r)_E,
/// h - (C r)_D - h_fix]`.
pub fn gnss_measurement<V: InsVehicle<N>, const N: usize>(
    fix: &GnssFix,
    sigma: f64,
    antenna: Vector3<f64>,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let GnssFix {
        lat, lon, height, ..
    } = *fix;
    let sh = fix.eph.map_or(sigma, |e| e.max(sigma));
    let sv = fix.epv.map_or(sigma, |e| e.max(sigma));
    let r = SVector::<f64, 3>::new(sh * sh, sh * sh, sv * sv);
    Box::new(FnMeasurement::new(
        &[lat, lon, height],
        move |f: &mut InsFilter<V, N>| {
            let s = &f.nominal().ins.state;
            let arm = s.c_bn * antenna;
            let z = SVector::<f64, 3>::new(
                (meridian_radius(s.lat) + s.h) * (s.lat - lat) + arm.x,
                (transverse_radius(s.lat) + s.h) * s.lat.cos() * wrap_angle(s.lon - lon) + arm.y,
                s.h - arm.z - height,
            );
            outcome(V::Gnss::update(f, &z, &r, antenna.as_slice()))
        },
    ))
}

/// A barometric altitude (m, up) of a port at lever arm `port` (body axes,
/// m) from the IMU, with noise sigma (m), for the `Barometer` sensor of
/// vehicle `V`: the residual is `(h - (C r)_D) - (h_baro - b^)`, the INS
/// height carried to the port minus the bias-corrected reading (a port 1 m
/// ahead of the IMU rises 17 mm per degree of pitch).
pub fn baro_measurement<V: InsVehicle<N>, const N: usize>(
    altitude: f64,
    sigma: f64,
    port: Vector3<f64>,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 1>::new(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[altitude],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let s = &nom.ins.state;
            let down = (s.c_bn * port).z;
            let z = SVector::<f64, 1>::new(s.h - down - (altitude - nom.baro_bias));
            outcome(V::Baro::update(f, &z, &r, &[]))
        },
    ))
}

/// A magnetometer sample (body field `m`, noise sigma per axis in the same
/// unit) with magnetic declination `declination` (rad), for the
/// `MagneticHeading` sensor of vehicle `V`: the sample is levelled with the
/// nominal roll and pitch of its time and read as a heading
/// ([`crate::heading::magnetic_heading`]); the residual is the nominal yaw
/// minus that heading, with sigma `atan(sigma / |m_horizontal|)`. A sample
/// without a horizontal field is refused.
pub fn mag_measurement<V: InsVehicle<N>, const N: usize>(
    m: Vector3<f64>,
    sigma: f64,
    declination: f64,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    Box::new(FnMeasurement::new(
        m.as_slice(),
        move |f: &mut InsFilter<V, N>| {
            let e = euler_from_c_bn(&f.nominal().ins.state.c_bn);
            let field = [m.x, m.y, m.z];
            // No heading (no horizontal field): a non-finite residual, which
            // the filter refuses.
            let psi = crate::heading::magnetic_heading(field, e.roll, e.pitch, declination)
                .unwrap_or(f64::NAN);
            let s = (sigma / crate::heading::horizontal_field(field, e.roll, e.pitch)).atan();
            let z = SVector::<f64, 1>::new(wrap_angle(e.yaw - psi));
            let r = SVector::<f64, 1>::new(s * s);
            outcome(V::Mag::update(f, &z, &r, &[]))
        },
    ))
}
