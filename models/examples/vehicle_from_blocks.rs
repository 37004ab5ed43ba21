//! Compose a vehicle from the blocks of `nav-blocks` and run its filter: an AUV
//! with the INS error-state core, a depth meter, a DVL, a compass and a GNSS fix
//! at the surface (see `docs/guide/building-a-vehicle.md`).
//!
//! The true error state (a depth-meter bias, attitude errors, DVL and compass
//! biases) follows the vehicle's own model; every sensor measures it with seeded
//! noise; GNSS fixes come once a second during the first 60 s (at the surface).
//! The example prints the estimate of each bias against the truth.
//!
//! `cargo run --release -p models --example vehicle_from_blocks`

use nav_blocks::{Compass, Depth, Dvl, GnssFix, InsCore};
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::model::{Model, Sensor};
use nav_runtime::nalgebra::{self, SMatrix, SVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

nav_runtime::model! {
    /// A survey AUV: INS core, depth meter, DVL, compass and a surface GNSS fix.
    pub model SurveyAuv = InsCore + Depth + Dvl + Compass + GnssFix;
}

const N: usize = SurveyAuv::N;

fn main() -> Result<(), FilterError> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let normal = Normal::new(0.0, 1.0).expect("unit normal");
    let mut gauss = move |sigma: f64| sigma * normal.sample(&mut rng);

    // The nominal (INS) solution: heading 30 deg, level, 1.5 m/s, 20 m deep, 40 N.
    let c_bn = *nalgebra::Rotation3::from_euler_angles(0.0, 0.0, 30f64.to_radians()).matrix();
    let u = SurveyAuvInput {
        latitude: 40f64.to_radians(),
        height: -20.0,
        velocity: c_bn * SVector::from([1.5, 0.0, 0.0]),
        c_bn,
        specific_force: SVector::from([0.0, 0.0, -9.80]),
    };
    let params = SurveyAuvParams::default();
    let q = SurveyAuvNoise {
        accel_noise: SVector::repeat(1e-6),
        gyro_noise: SVector::repeat(1e-11),
    };

    // The truth of the error state.
    let mut truth = SurveyAuvState {
        attitude_error: SVector::from([2e-3, -2e-3, 5e-3]),
        depth_bias: 0.4,
        dvl_bias: SVector::from([0.02, -0.01, 0.005]),
        compass_bias: 0.01,
        ..Default::default()
    }
    .to_vector();

    // The filter: zero initial estimate, diagonal covariance.
    let sigma = SurveyAuvState {
        position_error: SVector::from([1e-6, 1e-6, 1.0]),
        velocity_error: SVector::repeat(0.05),
        attitude_error: SVector::from([5e-3, 5e-3, 2e-2]),
        accel_bias: SVector::repeat(1e-3),
        gyro_bias: SVector::repeat(1e-6),
        depth_bias: 1.0,
        dvl_bias: SVector::repeat(0.05),
        compass_bias: 0.03,
    }
    .to_vector();
    let p0 = SMatrix::from_diagonal(&sigma.component_mul(&sigma));
    let mut filter = Ekf::<SurveyAuv, N>::new(SVector::zeros(), p0, params, q)?;

    let antenna = SurveyAuvGnssFixAux {
        antenna_lever_arm: SVector::from([0.5, 0.0, -1.0]),
    };
    let (dt, seconds, surface_seconds) = (0.01, 120.0, 60.0);
    let steps = (seconds / dt) as usize;
    for k in 1..=steps {
        truth = SurveyAuv::transition(&truth, &u, &params, dt);
        filter.predict(dt, &u)?;
        if k % 10 == 0 {
            let z = SurveyAuvDvl::predict(&truth, &u, &params, &())
                + SVector::from_fn(|_, _| gauss(0.01));
            filter.update::<SurveyAuvDvl, 3>(&z, &SMatrix::from_diagonal_element(1e-4), &())?;
            let z = SurveyAuvDepth::predict(&truth, &u, &params, &()).add_scalar(gauss(0.02));
            filter.update::<SurveyAuvDepth, 1>(&z, &SMatrix::from_element(4e-4), &())?;
        }
        if k % 20 == 0 {
            let z = SurveyAuvCompass::predict(&truth, &u, &params, &()).add_scalar(gauss(0.005));
            filter.update::<SurveyAuvCompass, 1>(&z, &SMatrix::from_element(2.5e-5), &())?;
        }
        if k % 100 == 0 && k as f64 * dt <= surface_seconds {
            let z = SurveyAuvGnssFix::predict(&truth, &u, &params, &antenna)
                + SVector::from_fn(|_, _| gauss(0.5));
            filter.update::<SurveyAuvGnssFix, 3>(
                &z,
                &SMatrix::from_diagonal_element(0.25),
                &antenna,
            )?;
        }
    }

    println!("{} states: {:?}", N, SurveyAuv::STATE_NAMES);
    println!("after {seconds} s ({surface_seconds} s with GNSS fixes):");
    println!("  state              truth     estimate  sigma");
    let x = filter.state();
    let p = filter.covariance();
    for (name, i) in [
        ("depth_bias", SurveyAuv::DEPTH_BIAS),
        ("dvl_bias[0]", SurveyAuv::DVL_BIAS),
        ("compass_bias", SurveyAuv::COMPASS_BIAS),
        ("attitude_error[2]", SurveyAuv::ATTITUDE_ERROR + 2),
    ] {
        println!(
            "  {name:17}  {:8.4}  {:8.4}  {:7.4}",
            truth[i],
            x[i],
            p[(i, i)].sqrt()
        );
    }
    println!(
        "generated covariance propagation: {} ops",
        SurveyAuv::OPS_PROPAGATE_COVARIANCE
    );
    Ok(())
}
