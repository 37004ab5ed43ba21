//! SDINS-25 as a composition of blocks, and the same vehicle without USBL.
//!
//! [`Sdins25Composed`] is the core plus the USBL, depth, DVL and compass blocks
//! in the paper's state order; the tests below show it equals the monolithic
//! declaration [`crate::sdins25::model::Sdins25`] (same `F`, `G`, `Qd`, `H`, and
//! the same estimates through [`nav_runtime::ekf::Ekf`]).
//!
//! [`Sdins20`] drops the USBL block: 20 states. Without USBL nothing measures
//! the longitude error `dl` (`position_error[1]`) and no other state's dynamics
//! depend on it (the Earth and transport rates depend on latitude only), so the
//! generator flags it; the declaration accepts it with `allow_unused`.

use crate::sdins25::vehicle::{Absent, InsVehicle};
use nav_blocks::{Compass, Depth, Dvl, DvlCalibrated, InsCore, Usbl, UsblCalibrated};

nav_runtime::model! {
    /// SDINS-25 assembled from blocks, in the paper's state order.
    pub model Sdins25Composed = InsCore + Usbl + Depth + Dvl + Compass {
        order {
            position_error, velocity_error, attitude_error, accel_bias, gyro_bias,
            usbl_bias, depth_bias, dvl_bias, compass_bias, usbl_misalignment,
        }
    }

    /// SDINS-25 generated in single precision (`f32`), for flight computers
    /// without a double FPU: the same blocks and state order as
    /// [`Sdins25Composed`] (the propagation bench and the accuracy test
    /// below compare the two).
    pub model Sdins25Single = InsCore + Usbl + Depth + Dvl + Compass {
        order {
            position_error, velocity_error, attitude_error, accel_bias, gyro_bias,
            usbl_bias, depth_bias, dvl_bias, compass_bias, usbl_misalignment,
        }
        scalar f32;
    }

    /// SDINS-25 without USBL: 20 states.
    pub model Sdins20 = InsCore + Depth + Dvl + Compass {
        allow_unused { position_error[1] }
    }

    /// [`Sdins20`] with the calibrated DVL: the DVL's scale, misalignment,
    /// lever-arm error and clock lag as filter states (28 states),
    /// estimated when the log's `[sensors.dvl] estimate` lists them
    /// (docs/calibration.md).
    pub model Sdins20DvlCal = InsCore + Depth + DvlCalibrated + Compass {
        allow_unused { position_error[1] }
    }

    /// SDINS-25 with the calibrated USBL: the error of the transponder's
    /// given lever arm and the lag of the fixes' clock as filter states
    /// (29 states), estimated when the log's `[sensors.usbl] estimate`
    /// lists them (docs/calibration.md).
    pub model Sdins25UsblCal = InsCore + UsblCalibrated + Depth + Dvl + Compass;
}

// Registration for `navsim replay --model ..` (with one line each in
// `crate::cli::replay_models`): which generated sensor reads which log file.

impl InsVehicle<25> for Sdins25Composed {
    const REPLAY_NAME: &'static str = "sdins25-composed";
    const DESCRIPTION: &'static str =
        "SDINS-25 composed from blocks (core + USBL + depth + DVL + compass); equals sdins25";
    type Depth = Sdins25ComposedDepth;
    type Dvl = Sdins25ComposedDvl;
    type Compass = Sdins25ComposedCompass;
    type CompassSmallAngle = Sdins25ComposedCompassSmallAngle;
    type Usbl = Sdins25ComposedUsbl;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

impl InsVehicle<20> for Sdins20 {
    const REPLAY_NAME: &'static str = "sdins20";
    const DESCRIPTION: &'static str =
        "SDINS-25 without USBL (20 states) over imu.csv + any of dvl/depth/heading; usbl.csv rows are counted and not used";
    type Depth = Sdins20Depth;
    type Dvl = Sdins20Dvl;
    type Compass = Sdins20Compass;
    type CompassSmallAngle = Sdins20CompassSmallAngle;
    type Usbl = Absent;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

impl InsVehicle<28> for Sdins20DvlCal {
    const REPLAY_NAME: &'static str = "sdins20-dvl-cal";
    const DESCRIPTION: &'static str =
        "sdins20 with the DVL's lever arm, misalignment, scale and clock lag as states (28), estimated per meta.toml [sensors.dvl] estimate";
    const DVL_SENSOR: &'static str = "DvlCalibrated";
    type Depth = Sdins20DvlCalDepth;
    type Dvl = Sdins20DvlCalDvlCalibrated;
    type Compass = Sdins20DvlCalCompass;
    type CompassSmallAngle = Sdins20DvlCalCompassSmallAngle;
    type Usbl = Absent;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

impl InsVehicle<29> for Sdins25UsblCal {
    const REPLAY_NAME: &'static str = "sdins25-usbl-cal";
    const DESCRIPTION: &'static str =
        "sdins25 with the USBL transponder's lever arm and clock lag as states (29), estimated per meta.toml [sensors.usbl] estimate";
    const USBL_SENSOR: &'static str = "UsblCalibrated";
    type Depth = Sdins25UsblCalDepth;
    type Dvl = Sdins25UsblCalDvl;
    type Compass = Sdins25UsblCalCompass;
    type CompassSmallAngle = Sdins25UsblCalCompassSmallAngle;
    type Usbl = Sdins25UsblCalUsblCalibrated;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

#[cfg(test)]
mod tests {
    use nalgebra::{SMatrix, SVector};
    use nav_runtime::ekf::Ekf;
    use nav_runtime::model::{Model, Record, Sensor};

    use super::*;
    use crate::sdins25::model as mono;

    /// splitmix64, uniform in [-1, 1].
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    /// A plausible nominal solution: mid latitude, shallow, moving, tilted.
    fn input(rng: &mut Rng) -> mono::Sdins25Input {
        let (roll, pitch, yaw) = (0.1 * rng.next(), 0.1 * rng.next(), 3.0 * rng.next());
        let c_nb = nalgebra::Rotation3::from_euler_angles(roll, pitch, yaw);
        mono::Sdins25Input {
            latitude: 0.6 + 0.1 * rng.next(),
            height: -50.0 + 10.0 * rng.next(),
            velocity: SVector::from_fn(|_, _| 1.5 * rng.next()),
            c_bn: *c_nb.matrix(),
            specific_force: SVector::from([
                0.2 * rng.next(),
                0.2 * rng.next(),
                -9.8 + 0.1 * rng.next(),
            ]),
        }
    }

    /// A small error state (radians of latitude are small).
    fn state(rng: &mut Rng) -> SVector<f64, 25> {
        SVector::from_fn(|i, _| if i < 2 { 1e-6 } else { 1e-2 } * rng.next())
    }

    fn same<const R: usize, const C: usize>(
        what: &str,
        a: &SMatrix<f64, R, C>,
        b: &SMatrix<f64, R, C>,
    ) {
        for (x, y) in a.iter().zip(b.iter()) {
            assert!(
                (x - y).abs() <= 1e-12 * (1.0 + x.abs()),
                "{what}: {x} vs {y}\n{a}\n{b}"
            );
        }
    }

    fn convert<A: Record, B: Record>(a: &A) -> B {
        assert_eq!(A::NAMES, B::NAMES);
        B::from_fn(|i| a.get(i))
    }

    /// A zero reading with noise variance 1e-4 per component of sensor `A`
    /// (`f64` filter) and its twin `B` (`f32` filter).
    fn fuse<A, B, const M: usize>(
        double: &mut Ekf<Sdins25Composed, 25>,
        single: &mut Ekf<Sdins25Single, 25, f32>,
    ) where
        A: Sensor<25, M, Model = Sdins25Composed, Aux = ()>,
        B: Sensor<25, M, f32, Model = Sdins25Single, Aux = ()>,
    {
        let z = SVector::<f64, M>::zeros();
        let r = SMatrix::<f64, M, M>::identity() * 1e-4;
        double.update::<A, M>(&z, &r, &()).expect("f64 update");
        single
            .update::<B, M>(&z.cast(), &r.cast(), &())
            .expect("f32 update");
    }

    /// The SDINS-25 error filter in `f32` and in `f64` over 500 s from the
    /// same inputs (IMU at 100 Hz, covariance steps of `dt` s), with DVL,
    /// depth and compass updates at 1 Hz. Returns the largest relative
    /// difference of the sigmas of the navigation states (position,
    /// velocity, attitude) and of the sensor-error states, over the run,
    /// and the `f32` covariance repairs.
    fn single_against_double(dt: f64) -> (f64, f64, u64) {
        let mut rng = Rng(32);
        let u0 = input(&mut rng);
        let q = mono::Sdins25Noise::from_fn(|i| if i < 3 { 1e-6 } else { 1e-11 });
        let sigmas: [f64; 25] = core::array::from_fn(|i| match i {
            0..=1 => 1e-6,
            2 => 1.0,
            3..=5 => 0.1,
            6..=8 => 0.01,
            9..=11 => 1e-3,
            12..=14 => 1e-5,
            _ => 0.05,
        });
        let p0 = SMatrix::<f64, 25, 25>::from_diagonal(&SVector::from(sigmas.map(|s| s * s)));
        let mut double =
            Ekf::<Sdins25Composed, 25>::new(SVector::zeros(), p0, Default::default(), convert(&q))
                .expect("f64 filter");
        let mut single = Ekf::<Sdins25Single, 25, f32>::new(
            SVector::zeros(),
            p0.map(|v| v as f32),
            Default::default(),
            convert(&q),
        )
        .expect("f32 filter");
        double.set_default_gate(None);
        single.set_default_gate(None);
        let (mut navigation, mut sensors): (f64, f64) = (0.0, 0.0);
        let steps = (500.0 / dt).round() as u32;
        let per_second = (1.0 / dt).round() as u32;
        for k in 0..steps {
            // The nominal turns slowly: yaw changes by 0.5 rad over the run.
            let mut u = u0;
            let yaw = 1e-3 * dt * f64::from(k);
            let (s, c) = yaw.sin_cos();
            let turn = SMatrix::<f64, 3, 3>::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
            u.c_bn = turn * u0.c_bn;
            double.predict(dt, &convert(&u)).expect("f64 predict");
            single
                .predict(dt as f32, &convert(&u))
                .expect("f32 predict");
            if k % per_second != per_second - 1 {
                continue;
            }
            // A zero reading of each sensor, in both filters.
            fuse::<Sdins25ComposedDvl, Sdins25SingleDvl, 3>(&mut double, &mut single);
            fuse::<Sdins25ComposedDepth, Sdins25SingleDepth, 1>(&mut double, &mut single);
            fuse::<Sdins25ComposedCompass, Sdins25SingleCompass, 1>(&mut double, &mut single);
            for i in 0..25 {
                let a = double.covariance()[(i, i)].sqrt();
                let b = f64::from(single.covariance()[(i, i)]).sqrt();
                let worst = if i < 9 { &mut navigation } else { &mut sensors };
                *worst = worst.max((a - b).abs() / a);
            }
        }
        (navigation, sensors, single.counters().covariance_repairs)
    }

    /// What `f32` costs in covariance accuracy on SDINS-25 (measured, with
    /// about 2x margin; `docs/language.md`, "Scalar type"): at 100 Hz the
    /// navigation sigmas stay within 0.53 % of `f64`, but the gyro-bias sigma
    /// ends 10 % high: each step adds to the attitude/bias cross-covariances
    /// increments of about 4e-6 of their value, of which `f32` keeps only a
    /// few bits, and the lost information accumulates. Covariance steps of
    /// 0.1 s (IMU increments summed over ten samples) cut the differences to
    /// 0.066 % and 2 %. No repair in either.
    #[test]
    fn single_precision_covariance_tracks_double() {
        // (covariance step, bound on navigation states, bound on sensor errors)
        let cases = [(0.01, 1e-2, 0.2), (0.1, 1.5e-3, 0.04)];
        for (dt, navigation_bound, sensor_bound) in cases {
            let (navigation, sensors, repairs) = single_against_double(dt);
            eprintln!(
                "SDINS-25 f32 against f64, 500 s, covariance steps of {dt} s: largest relative \
                 sigma difference {navigation:.2e} (navigation states), {sensors:.2e} (sensor \
                 errors), {repairs} repairs"
            );
            assert_eq!(repairs, 0, "dt {dt}");
            assert!(
                navigation < navigation_bound,
                "dt {dt}: navigation {navigation}"
            );
            assert!(sensors < sensor_bound, "dt {dt}: sensor errors {sensors}");
        }
    }

    /// `sdins20-dvl-cal` fits the navigator, and its DVL mounting states
    /// are the ones the nominal solution does not keep (total states in the
    /// filter, docs/calibration.md); everything else is `sdins20`'s.
    #[test]
    fn the_calibrated_dvl_vehicle_keeps_its_mounting_states_in_the_filter() {
        let layout =
            crate::sdins25::vehicle::Layout::of::<Sdins20DvlCal, 28>().expect("fits the navigator");
        let absorbed = layout.absorbed::<28>();
        let names = <Sdins20DvlCal as Model<28>>::STATE_NAMES;
        let kept: Vec<&str> = (0..28)
            .filter(|&i| !absorbed[i])
            .map(|i| names[i])
            .collect();
        assert_eq!(
            kept,
            [
                "dvl_scale",
                "dvl_misalignment[0]",
                "dvl_misalignment[1]",
                "dvl_misalignment[2]",
                "dvl_lever_arm[0]",
                "dvl_lever_arm[1]",
                "dvl_lever_arm[2]",
                "dvl_time_offset",
            ]
        );
        let others: Vec<&str> = (0..28).filter(|&i| absorbed[i]).map(|i| names[i]).collect();
        assert_eq!(others, <Sdins20 as Model<20>>::STATE_NAMES);
    }

    #[test]
    fn same_layout_as_the_monolithic_declaration() {
        assert_eq!(Sdins25Composed::N, 25);
        assert_eq!(
            <Sdins25Composed as Model<25>>::STATE_NAMES,
            <mono::Sdins25 as Model<25>>::STATE_NAMES
        );
        assert_eq!(
            <Sdins25Composed as Model<25>>::JACOBIAN_SPARSITY,
            <mono::Sdins25 as Model<25>>::JACOBIAN_SPARSITY
        );
        assert_eq!(
            <Sdins25ComposedDvl as Sensor<25, 3>>::JACOBIAN_SPARSITY,
            <mono::Sdins25Dvl as Sensor<25, 3>>::JACOBIAN_SPARSITY
        );
        assert_eq!(
            Sdins25Composed::USBL_MISALIGNMENT,
            mono::Sdins25::USBL_MISALIGNMENT
        );
        assert_eq!(Sdins25Composed::UNUSED_STATES, &[] as &[&str]);
        // Error-state models: the filter skips the transition at zero.
        const {
            assert!(<Sdins25Composed as Model<25>>::ZERO_IS_FIXED);
            assert!(<mono::Sdins25 as Model<25>>::ZERO_IS_FIXED);
        }
        assert_eq!(Sdins20::N, 20);
        assert_eq!(Sdins20::UNUSED_STATES, &["position_error[1]"]);
    }

    #[test]
    fn same_f_g_qd_h_as_the_monolithic_declaration() {
        let mut rng = Rng(25);
        for _ in 0..50 {
            let u = input(&mut rng);
            let uc: <Sdins25Composed as Model<25>>::Input = convert(&u);
            let x = state(&mut rng);
            let q = mono::Sdins25Noise::from_fn(|_| 1e-6 * (1.5 + rng.next()));
            let qc: <Sdins25Composed as Model<25>>::Noise = convert(&q);
            let dt = 0.01;
            same(
                "F",
                &Sdins25Composed::jacobian(&x, &uc, &Default::default(), dt),
                &mono::Sdins25::jacobian(&x, &u, &Default::default(), dt),
            );
            same(
                "G",
                &Sdins25Composed::noise_jacobian(&x, &uc, &Default::default(), dt),
                &mono::Sdins25::noise_jacobian(&x, &u, &Default::default(), dt),
            );
            same(
                "Qd",
                &Sdins25Composed::process_noise(&x, &uc, &Default::default(), &qc, dt),
                &mono::Sdins25::process_noise(&x, &u, &Default::default(), &q, dt),
            );
            same(
                "transition",
                &Sdins25Composed::transition(&x, &uc, &Default::default(), dt),
                &mono::Sdins25::transition(&x, &u, &Default::default(), dt),
            );
            let (p, pm) = (
                Sdins25ComposedParams::default(),
                mono::Sdins25Params::default(),
            );
            same(
                "H depth",
                &Sdins25ComposedDepth::jacobian(&x, &uc, &p, &()),
                &mono::Sdins25Depth::jacobian(&x, &u, &pm, &()),
            );
            same(
                "H dvl",
                &Sdins25ComposedDvl::jacobian(&x, &uc, &p, &()),
                &mono::Sdins25Dvl::jacobian(&x, &u, &pm, &()),
            );
            same(
                "H compass",
                &Sdins25ComposedCompass::jacobian(&x, &uc, &p, &()),
                &mono::Sdins25Compass::jacobian(&x, &u, &pm, &()),
            );
            same(
                "H compass (small angle)",
                &Sdins25ComposedCompassSmallAngle::jacobian(&x, &uc, &p, &()),
                &mono::Sdins25CompassSmallAngle::jacobian(&x, &u, &pm, &()),
            );
            let r = SVector::from_fn(|_, _| 300.0 * rng.next());
            same(
                "H usbl",
                &Sdins25ComposedUsbl::jacobian(
                    &x,
                    &uc,
                    &p,
                    &Sdins25ComposedUsblAux {
                        relative_position: r,
                    },
                ),
                &mono::Sdins25Usbl::jacobian(
                    &x,
                    &u,
                    &pm,
                    &mono::Sdins25UsblAux {
                        relative_position: r,
                    },
                ),
            );
            same(
                "h usbl",
                &Sdins25ComposedUsbl::predict(
                    &x,
                    &uc,
                    &p,
                    &Sdins25ComposedUsblAux {
                        relative_position: r,
                    },
                ),
                &mono::Sdins25Usbl::predict(
                    &x,
                    &u,
                    &pm,
                    &mono::Sdins25UsblAux {
                        relative_position: r,
                    },
                ),
            );
        }
    }

    /// A short synthetic run: both filters see the same inputs and measurements.
    #[test]
    fn same_estimates_through_the_ekf() {
        let mut rng = Rng(2025);
        let p0 = SMatrix::<f64, 25, 25>::from_diagonal(&SVector::from_fn(|i, _| {
            if i < 2 {
                1e-12
            } else {
                [1.0, 0.01, 1e-4, 1e-6, 1e-8][((i + 1) / 3).min(4)]
            }
        }));
        let q = mono::Sdins25Noise {
            accel_noise: SVector::repeat(1e-6),
            gyro_noise: SVector::repeat(1e-10),
        };
        let mut a = Ekf::<mono::Sdins25, 25>::new(SVector::zeros(), p0, Default::default(), q)
            .unwrap()
            .with_default_gate(None);
        let mut b =
            Ekf::<Sdins25Composed, 25>::new(SVector::zeros(), p0, Default::default(), convert(&q))
                .unwrap()
                .with_default_gate(None);
        let mut u = input(&mut rng);
        for step in 0..300 {
            u.velocity += SVector::from_fn(|_, _| 0.01 * rng.next());
            u.specific_force =
                SVector::from([0.2 * rng.next(), 0.2 * rng.next(), -9.8 + 0.1 * rng.next()]);
            a.predict(0.01, &u).unwrap();
            b.predict(0.01, &convert(&u)).unwrap();
            let noise = |rng: &mut Rng, s: f64| SVector::<f64, 3>::from_fn(|_, _| s * rng.next());
            if step % 10 == 0 {
                let z = SVector::<f64, 3>::from_fn(|_, _| 0.02 * rng.next());
                let r = SMatrix::<f64, 3, 3>::from_diagonal_element(1e-4);
                a.update::<mono::Sdins25Dvl, 3>(&z, &r, &()).unwrap();
                b.update::<Sdins25ComposedDvl, 3>(&z, &r, &()).unwrap();
            }
            if step % 20 == 5 {
                let z = SVector::<f64, 1>::new(0.05 * rng.next());
                let r = SMatrix::<f64, 1, 1>::new(1e-3);
                a.update::<mono::Sdins25Depth, 1>(&z, &r, &()).unwrap();
                b.update::<Sdins25ComposedDepth, 1>(&z, &r, &()).unwrap();
                let z = SVector::<f64, 1>::new(0.01 * rng.next());
                a.update::<mono::Sdins25Compass, 1>(&z, &r, &()).unwrap();
                b.update::<Sdins25ComposedCompass, 1>(&z, &r, &()).unwrap();
            }
            if step % 50 == 25 {
                let rel = noise(&mut rng, 200.0);
                let z = SVector::<f64, 2>::from_fn(|_, _| 2.0 * rng.next());
                let r = SMatrix::<f64, 2, 2>::from_diagonal_element(1.0);
                a.update::<mono::Sdins25Usbl, 2>(
                    &z,
                    &r,
                    &mono::Sdins25UsblAux {
                        relative_position: rel,
                    },
                )
                .unwrap();
                b.update::<Sdins25ComposedUsbl, 2>(
                    &z,
                    &r,
                    &Sdins25ComposedUsblAux {
                        relative_position: rel,
                    },
                )
                .unwrap();
            }
            same("x", a.state(), b.state());
            same("P", a.covariance(), b.covariance());
        }
        assert!(a.state().norm() > 0.0, "the run moved the estimate");
    }

    #[test]
    fn dropping_usbl_shrinks_the_generated_code() {
        let (ops25, ops20) = (
            Sdins25Composed::OPS_PROPAGATE_COVARIANCE,
            Sdins20::OPS_PROPAGATE_COVARIANCE,
        );
        eprintln!(
            "OPS_PROPAGATE_COVARIANCE: 25 states {ops25}, 20 states {ops20}; OPS_JACOBIAN {} vs {}; \
             OPS_PROCESS_NOISE {} vs {}; monolithic {}",
            Sdins25Composed::OPS_JACOBIAN,
            Sdins20::OPS_JACOBIAN,
            Sdins25Composed::OPS_PROCESS_NOISE,
            Sdins20::OPS_PROCESS_NOISE,
            mono::Sdins25::OPS_PROPAGATE_COVARIANCE,
        );
        assert_eq!(ops25, mono::Sdins25::OPS_PROPAGATE_COVARIANCE);
        assert!(ops20 < ops25);
        assert_eq!(Sdins25Composed::OPS_JACOBIAN, Sdins20::OPS_JACOBIAN);
    }
}
