//! The walk-through of docs/guide/building-a-vehicle.md: a new sensor block (a pressure
//! depth sensor mounted away from the IMU, with a bias), a vehicle using it, and
//! the vehicle's filter run from Rust through [`nav_runtime::ekf::Ekf`].

use nalgebra::{SMatrix, SVector};
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::model::{Model, Sensor};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

use nav_blocks::{Compass, Dvl, GnssFix, InsCore};

// Step 1: the sensor block.
nav_runtime::model! {
    /// A pressure depth sensor at a lever arm from the IMU, with a bias.
    pub block PressureDepth {
        states {
            /// Pressure-depth bias (in height, positive up), m.
            pressure_bias,
        }
        needs { position_error: 3, attitude_error: 3, c_bn: 3x3 }
        /// INS height of the sensor minus the measured height (`-depth`):
        /// `dh - ((C^ - C) r)_D - b`.
        sensor PressureDepth: 1 {
            inputs {
                /// Sensor position in body axes relative to the IMU, m.
                lever_arm: 3,
            }
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let arm_error = (c_bn - c_true) * lever_arm;
            h = [position_error[2] - arm_error[2] - pressure_bias];
        }
    }
}

// Step 2: the vehicle.
nav_runtime::model! {
    /// An AUV with INS, pressure sensor, DVL, compass and a GNSS fix at the surface.
    pub model PressureAuv = InsCore + PressureDepth + Dvl + Compass + GnssFix;
}

/// Step 4: the vehicle replays logs (`navsim replay DIR --model pressure-auv`,
/// or its own program with [`nav_replay::program::replay_main`]): its sensors in the
/// log's slots. `depth.csv` feeds the pressure sensor, whose lever arm comes
/// from `[sensors.depth] lever_arm`; the GNSS fix has no log file and stays
/// unused.
impl nav_ins::InsVehicle<20> for PressureAuv {
    const REPLAY_NAME: &'static str = "pressure-auv";
    const DESCRIPTION: &'static str = "the walk-through AUV: INS + pressure sensor at a lever arm ([sensors.depth] lever_arm) + DVL + compass";
    const DEPTH_SENSOR: &'static str = "PressureDepth";
    const DEPTH_BIAS: &'static str = "pressure_bias";
    type Depth = PressureAuvPressureDepth;
    type Dvl = PressureAuvDvl;
    type Compass = PressureAuvCompass;
    type CompassSmallAngle = PressureAuvCompassSmallAngle;
    type Usbl = nav_ins::Absent;
    type Gnss = nav_ins::Absent;
    type Baro = nav_ins::Absent;
    type Mag = nav_ins::Absent;
}

/// Number of states of [`PressureAuv`].
pub const N: usize = PressureAuv::N;

/// The outcome of [`simulate`]: the filter after the run and the true error state.
pub struct Run {
    /// The filter at the end of the run.
    pub filter: Ekf<PressureAuv, N>,
    /// The true error state at the end of the run.
    pub truth: SVector<f64, N>,
}

/// Step 3: runs the vehicle's filter over a synthetic run of `seconds` (IMU at
/// 100 Hz): the true error state starts with a pressure bias, attitude and
/// sensor errors and follows the model; every sensor measures it with noise.
/// GNSS fixes (with height) are available for the first `surface_seconds`.
pub fn simulate(seconds: f64, surface_seconds: f64, seed: u64) -> Result<Run, FilterError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = Normal::new(0.0, 1.0).expect("unit normal");
    let mut gauss = move |sigma: f64| sigma * normal.sample(&mut rng);

    // Nominal solution: heading 30 degrees, level, 1.5 m/s forward, 40 N.
    let c_bn = *nalgebra::Rotation3::from_euler_angles(0.0, 0.0, 30f64.to_radians()).matrix();
    let u = PressureAuvInput {
        latitude: 40f64.to_radians(),
        height: -20.0,
        velocity: c_bn * SVector::from([1.5, 0.0, 0.0]),
        c_bn,
        specific_force: SVector::from([0.0, 0.0, -9.80]),
    };
    let params = PressureAuvParams::default();
    let q = PressureAuvNoise {
        accel_noise: SVector::repeat(1e-6),
        gyro_noise: SVector::repeat(1e-11),
    };

    // The truth: a 0.4 m pressure bias, 2 mrad attitude errors, sensor biases.
    let mut truth = PressureAuvState {
        attitude_error: SVector::from([2e-3, -2e-3, 5e-3]),
        pressure_bias: 0.4,
        dvl_bias: SVector::from([0.02, -0.01, 0.005]),
        compass_bias: 0.01,
        ..Default::default()
    }
    .to_vector();

    // The filter: zero initial estimate, covariance from the initial uncertainty.
    let sigma = PressureAuvState {
        position_error: SVector::from([1e-6, 1e-6, 1.0]),
        velocity_error: SVector::repeat(0.05),
        attitude_error: SVector::from([5e-3, 5e-3, 2e-2]),
        accel_bias: SVector::repeat(1e-3),
        gyro_bias: SVector::repeat(1e-6),
        pressure_bias: 1.0,
        dvl_bias: SVector::repeat(0.05),
        compass_bias: 0.03,
    }
    .to_vector();
    let p0 = SMatrix::from_diagonal(&sigma.component_mul(&sigma));
    let mut filter = Ekf::<PressureAuv, N>::new(SVector::zeros(), p0, params, q)?;

    let lever = PressureAuvPressureDepthAux {
        lever_arm: SVector::from([-1.2, 0.0, 0.3]),
    };
    let antenna = PressureAuvGnssFixAux {
        antenna_lever_arm: SVector::from([0.5, 0.0, -1.0]),
    };
    let dt = 0.01;
    let steps = (seconds / dt).round() as usize;
    for k in 1..=steps {
        truth = PressureAuv::transition(&truth, &u, &params, dt);
        filter.predict(dt, &u)?;
        if k % 10 == 0 {
            let z = PressureAuvDvl::predict(&truth, &u, &params, &())
                + SVector::from_fn(|_, _| gauss(0.01));
            filter.update::<PressureAuvDvl, 3>(&z, &SMatrix::from_diagonal_element(1e-4), &())?;
            let z = PressureAuvPressureDepth::predict(&truth, &u, &params, &lever)
                .add_scalar(gauss(0.02));
            filter.update::<PressureAuvPressureDepth, 1>(
                &z,
                &SMatrix::from_element(4e-4),
                &lever,
            )?;
        }
        if k % 20 == 0 {
            let z = PressureAuvCompass::predict(&truth, &u, &params, &()).add_scalar(gauss(0.005));
            filter.update::<PressureAuvCompass, 1>(&z, &SMatrix::from_element(2.5e-5), &())?;
        }
        if k % 100 == 0 && k as f64 * dt <= surface_seconds {
            let z = PressureAuvGnssFix::predict(&truth, &u, &params, &antenna)
                + SVector::from_fn(|_, _| gauss(0.5));
            filter.update::<PressureAuvGnssFix, 3>(
                &z,
                &SMatrix::from_diagonal_element(0.25),
                &antenna,
            )?;
        }
    }
    Ok(Run { filter, truth })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::model::Record;

    #[test]
    fn the_vehicle_has_the_blocks_states() {
        assert_eq!(PressureAuv::N, 20);
        assert_eq!(PressureAuv::PRESSURE_BIAS, 15);
        assert_eq!(PressureAuv::UNUSED_STATES, &[] as &[&str]);
        assert_eq!(
            <PressureAuvPressureDepthAux as Record>::NAMES,
            ["lever_arm[0]", "lever_arm[1]", "lever_arm[2]"]
        );
        // The pressure sensor sees height, roll and pitch errors (through the lever arm) and its bias.
        let sparsity = <PressureAuvPressureDepth as Sensor<N, 1>>::JACOBIAN_SPARSITY[0];
        let seen: Vec<&str> = (0..N)
            .filter(|&j| sparsity[j])
            .map(|j| <PressureAuv as Model<N>>::STATE_NAMES[j])
            .collect();
        assert_eq!(
            seen,
            [
                "position_error[2]",
                "attitude_error[0]",
                "attitude_error[1]",
                "pressure_bias"
            ]
        );
    }

    #[test]
    fn surface_fixes_make_the_pressure_bias_observable() {
        let run = simulate(120.0, 60.0, 7).unwrap();
        let i = PressureAuv::PRESSURE_BIAS;
        let (est, truth) = (run.filter.state()[i], run.truth[i]);
        let sigma = run.filter.covariance()[(i, i)].sqrt();
        eprintln!("pressure bias: estimate {est:.4} m, truth {truth:.4} m, sigma {sigma:.4} m");
        assert!(sigma < 0.1, "sigma {sigma}");
        assert!(
            (est - truth).abs() < 4.0 * sigma.max(0.01),
            "{est} vs {truth} (sigma {sigma})"
        );
    }

    #[test]
    fn without_a_height_reference_the_bias_stays_uncertain() {
        let run = simulate(60.0, 0.0, 7).unwrap();
        let i = PressureAuv::PRESSURE_BIAS;
        let sigma = run.filter.covariance()[(i, i)].sqrt();
        assert!(sigma > 0.5, "sigma {sigma}");
    }
}
