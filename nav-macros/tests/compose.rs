//! Composition: blocks declared in one module, vehicles assembled from them in
//! another (by `use` and by path), checked against the same model written as one
//! declaration.

use nalgebra::{SMatrix, SVector};
use nav_runtime::model::{Model, Record, Sensor};

mod blocks {
    nav_runtime::model! {
        /// A 1D constant-velocity core.
        pub block Cv {
            states {
                /// Position, m.
                pos,
                /// Velocity, m/s.
                vel,
            }
            inputs { accel }
            noise { accel_noise }
            continuous {
                let a = 1.0;
                d/dt pos = vel;
                d/dt vel = a * accel + accel_noise;
            }
        }

        /// A position fix with a constant bias.
        pub block Gps {
            states { gps_bias }
            needs { pos }
            sensor Gps: 1 {
                h = pos + gps_bias;
            }
        }

        /// An odometer with a first-order Markov scale factor error.
        pub block Odo {
            states { odo_scale }
            needs { vel }
            parameters { odo_tau }
            noise { odo_noise }
            continuous {
                let a = 1.0 / odo_tau;
                d/dt odo_scale = -a * odo_scale + odo_noise;
            }
            sensor Odo: 1 {
                inputs { odo_offset }
                let a = 1.0 + odo_scale;
                h = a * vel + odo_offset;
            }
        }
    }
}

mod vehicles {
    use super::blocks::{Cv, Gps};

    nav_runtime::model! {
        /// Core and position fix.
        pub model CvGps = Cv + Gps;

        /// All three blocks, in an explicit state order.
        pub model CvAll = Cv + super::blocks::Odo + Gps {
            order { gps_bias, pos, vel, odo_scale }
        }

        /// Without a position fix nothing observes the position.
        pub model CvOdo = Cv + super::blocks::Odo {
            allow_unused { pos }
        }

        /// Run with the fix, and through fix outages with the odometer alone,
        /// which sees neither the position nor the fix's bias.
        pub model CvRuns = Cv + super::blocks::Odo + Gps {
            runs_with { [Odo, Gps], [Odo] }
            allow_unused { pos, gps_bias }
        }
    }
}

/// A composition's `runs_with` and `allow_unused` reach the generated data
/// (states pos, vel, odo_scale, gps_bias; sensors Odo, Gps).
#[test]
fn composed_runs_with() {
    use vehicles::{CvRuns, CvRunsGps, CvRunsOdo};
    assert_eq!(CvRuns::SENSORS, ["Odo", "Gps"]);
    assert_eq!((CvRunsOdo::INDEX, CvRunsGps::INDEX), (0, 1));
    assert_eq!(CvRuns::RUNS_WITH, [&[0usize, 1][..], &[0][..]]);
    assert_eq!(
        CvRuns::RUNS_WITH_OBSERVABLE,
        [[true; 4], [false, true, true, false]]
    );
    assert_eq!(CvRunsOdo::OBSERVES, [false, true, true, false]);
    assert_eq!(CvRunsGps::OBSERVES, [true, true, false, true]);
    assert!(CvRuns::UNUSED_STATES.is_empty());
}

nav_runtime::model! {
    /// `CvAll` written as one declaration.
    pub model CvMono {
        states { gps_bias, pos, vel, odo_scale }
        inputs { accel }
        parameters { odo_tau }
        noise { accel_noise, odo_noise }
        continuous {
            let a = 1.0;
            d/dt pos = vel;
            d/dt vel = a * accel + accel_noise;
            let b = 1.0 / odo_tau;
            d/dt odo_scale = -b * odo_scale + odo_noise;
        }
        sensor Odo: 1 {
            inputs { odo_offset }
            let a = 1.0 + odo_scale;
            h = a * vel + odo_offset;
        }
        sensor Gps: 1 {
            h = pos + gps_bias;
        }
    }
}

use vehicles::{CvAll, CvAllGps, CvAllOdo, CvGps, CvOdo};

#[test]
fn layout_follows_blocks_and_order() {
    assert_eq!(CvGps::N, 3);
    assert_eq!(<CvGps as Model<3>>::STATE_NAMES, ["pos", "vel", "gps_bias"]);
    assert_eq!(
        <CvAll as Model<4>>::STATE_NAMES,
        <CvMono as Model<4>>::STATE_NAMES
    );
    assert_eq!((CvAll::GPS_BIAS, CvAll::POS, CvAll::ODO_SCALE), (0, 1, 3));
    assert_eq!(CvAll::NW, 2);
    assert_eq!(
        <<CvAll as Model<4>>::Noise as Record>::NAMES,
        ["accel_noise", "odo_noise"]
    );
    assert_eq!(<CvAllOdo as Sensor<4, 1>>::NAME, "Odo");
    assert_eq!(CvGps::UNUSED_STATES, &[] as &[&str]);
    assert_eq!(CvAll::UNUSED_STATES, &[] as &[&str]);
    assert_eq!(CvOdo::UNUSED_STATES, &["pos"]);
    assert_eq!(CvMono::UNUSED_STATES, &[] as &[&str]);
}

#[test]
fn composed_equals_monolithic() {
    let mut seed = 7u64;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..20 {
        let x = SVector::<f64, 4>::from_fn(|_, _| rnd());
        let u_c = <CvAll as Model<4>>::Input::from_fn(|_| rnd());
        let u_m = <CvMono as Model<4>>::Input::from_fn(|i| u_c.get(i));
        let p_c = <CvAll as Model<4>>::Params::from_fn(|_| 2.0 + rnd());
        let p_m = <CvMono as Model<4>>::Params::from_fn(|i| p_c.get(i));
        let q_c = <CvAll as Model<4>>::Noise::from_fn(|_| 1.0 + rnd());
        let q_m = <CvMono as Model<4>>::Noise::from_fn(|i| q_c.get(i));
        let dt = 0.1;
        assert_eq!(
            CvAll::jacobian(&x, &u_c, &p_c, dt),
            CvMono::jacobian(&x, &u_m, &p_m, dt)
        );
        assert_eq!(
            CvAll::noise_jacobian(&x, &u_c, &p_c, dt),
            CvMono::noise_jacobian(&x, &u_m, &p_m, dt)
        );
        assert_eq!(
            CvAll::process_noise(&x, &u_c, &p_c, &q_c, dt),
            CvMono::process_noise(&x, &u_m, &p_m, &q_m, dt)
        );
        assert_eq!(
            CvAll::transition(&x, &u_c, &p_c, dt),
            CvMono::transition(&x, &u_m, &p_m, dt)
        );
        let aux_c = vehicles::CvAllOdoAux { odo_offset: rnd() };
        let aux_m = CvMonoOdoAux {
            odo_offset: aux_c.odo_offset,
        };
        assert_eq!(
            CvAllOdo::jacobian(&x, &u_c, &p_c, &aux_c),
            CvMonoOdo::jacobian(&x, &u_m, &p_m, &aux_m)
        );
        assert_eq!(
            CvAllOdo::predict(&x, &u_c, &p_c, &aux_c),
            CvMonoOdo::predict(&x, &u_m, &p_m, &aux_m)
        );
        assert_eq!(
            CvAllGps::jacobian(&x, &u_c, &p_c, &()),
            CvMonoGps::jacobian(&x, &u_m, &p_m, &())
        );
        let _: SMatrix<f64, 1, 4> = CvAllGps::jacobian(&x, &u_c, &p_c, &());
    }
}

mod private_blocks {
    nav_runtime::model! {
        /// A private block, used in the same invocation; its sensor's `let vel`
        /// shadows nothing although the core has a state `vel` (it is renamed).
        block Tick {
            states { tick_bias }
            needs { pos }
            sensor Tick: 1 {
                let vel = 2.0 * pos;
                h = vel + tick_bias;
            }
        }

        pub model CvTick = super::blocks::Cv + Tick;
    }
}

#[test]
fn private_blocks_and_local_names() {
    use private_blocks::{CvTick, CvTickTick};
    let x = SVector::from([1.5, -3.0, 0.25]);
    let u = <CvTick as Model<3>>::Input::default();
    let z = CvTickTick::predict(&x, &u, &Default::default(), &());
    assert_eq!(z[0], 2.0 * 1.5 + 0.25);
    assert_eq!(CvTick::UNUSED_STATES, &[] as &[&str]);
}

mod shared_in_blocks {
    nav_runtime::model! {
        /// A block with a block-level `let` and a function, seen by its
        /// process section and its sensor.
        pub block Spring {
            states { x, v }
            parameters { k }
            noise { w }
            fn square(a) = a * a;
            let energy = 0.5 * (square(v) + k * square(x));
            continuous {
                d/dt x = v;
                d/dt v = -k * x + w;
            }
            sensor Energy: 1 { h = [energy]; }
        }

        /// A second block reading the first's state; its own `let` of the
        /// same local role has another name.
        pub block Ruler {
            states { ruler_bias }
            needs { x }
            let reading = x + ruler_bias;
            sensor Ruler: 1 { h = [reading]; }
        }

        pub model Oscillator = Spring + Ruler;
    }
}

#[test]
fn block_level_lets_and_functions_compose() {
    use shared_in_blocks::{Oscillator, OscillatorEnergy, OscillatorParams, OscillatorRuler};
    let x = SVector::from([0.5, -2.0, 0.1]);
    let u = <Oscillator as Model<3>>::Input::default();
    let p = OscillatorParams { k: 4.0 };
    let e = OscillatorEnergy::predict(&x, &u, &p, &());
    assert!((e[0] - 0.5 * (4.0 + 4.0 * 0.25)).abs() < 1e-12, "{e}");
    let r = OscillatorRuler::predict(&x, &u, &p, &());
    assert!((r[0] - 0.6).abs() < 1e-12, "{r}");
    // d energy / d (x, v) = (k x, v).
    let h = OscillatorEnergy::jacobian(&x, &u, &p, &());
    assert!(
        (h[(0, 0)] - 2.0).abs() < 1e-12 && (h[(0, 1)] + 2.0).abs() < 1e-12,
        "{h}"
    );
}

mod blocks_named_like_generated_types {
    // A block named like a type its vehicle generates in the same module:
    // `model Boat = .. + BoatFix` with `sensor Fix` generates the sensor type
    // `BoatFix`, and `BoatLog`'s sensor `Log` the type `BoatLog`. The
    // block's macro and the type must not clash (the block used to import
    // the type along with its macro: "the name `BoatFix` is defined
    // multiple times").
    nav_runtime::model! {
        pub block BoatCore {
            states { pos, vel }
            noise { accel_noise }
            continuous {
                d/dt pos = vel;
                d/dt vel = accel_noise;
            }
        }

        /// A position fix; `pub`.
        pub block BoatFix {
            needs { pos }
            sensor Fix: 1 { h = pos; }
        }

        /// A speed log; private.
        block BoatLog {
            needs { vel }
            sensor Log: 1 { h = vel; }
        }
    }

    nav_runtime::model! {
        pub model Boat = BoatCore + BoatFix + BoatLog;
    }
}

#[test]
fn blocks_may_be_named_like_the_types_their_vehicle_generates() {
    use blocks_named_like_generated_types::{Boat, BoatFix, BoatLog};
    let x = SVector::from([3.0, -0.5]);
    let u = <Boat as Model<2>>::Input::default();
    let p = <Boat as Model<2>>::Params::default();
    assert_eq!(BoatFix::predict(&x, &u, &p, &())[0], 3.0);
    assert_eq!(BoatLog::predict(&x, &u, &p, &())[0], -0.5);
}
