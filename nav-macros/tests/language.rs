//! The builtins of the second round of the language: rotations and non-smooth
//! functions. Each model also carries its generated finite-difference tests
//! (`__*_generated_tests`), which check every Jacobian of these functions.

use nav_runtime::model::Sensor;
use nav_runtime::nalgebra::{SMatrix, SVector};

nav_runtime::model! {
    /// A quaternion attitude with gyro bias, body to navigation.
    pub model QuatAttitude {
        states { q: 4, gyro_bias: 3 }
        inputs { gyro: 3 }
        parameters { gravity }
        noise { gyro_noise: 3 }
        continuous {
            let w = gyro - gyro_bias + gyro_noise;
            d/dt q = 0.5 * quat_mul(q, [0.0, w[0], w[1], w[2]]);
        }
        /// Specific force at rest in body axes.
        sensor Accel: 3 {
            h = transpose(quat_to_dcm(normalize(q))) * [0.0, 0.0, -gravity];
        }
        sensor Euler: 3 {
            angles = [0, 2];
            h = dcm_to_euler(quat_to_dcm(normalize(q)));
        }
    }
}

nav_runtime::model! {
    /// A 3-element attitude error about a nominal quaternion.
    pub model AttitudeError {
        states { attitude_error: 3 }
        inputs { nominal: 4 }
        parameters { gravity }
        noise { gyro_noise: 3 }
        continuous {
            d/dt attitude_error = gyro_noise;
        }
        sensor Accel: 3 {
            let c_bn = quat_to_dcm(quat_mul(nominal, rotvec_to_quat(attitude_error)));
            h = transpose(c_bn) * [0.0, 0.0, -gravity];
        }
    }
}

nav_runtime::model! {
    /// Saturations and dead zones.
    pub model Wheel {
        states { speed, slip }
        parameters { limit }
        noise { accel }
        continuous {
            d/dt speed = clamp(-slip, -limit, limit) + accel;
            d/dt slip = -abs(slip) * sign(speed);
        }
        sensor Odometer: 3 {
            h = [max(speed, 0.1), min(speed, slip), clamp(slip, -0.5, 0.5)];
        }
    }
}

fn unit(v: [f64; 4]) -> SVector<f64, 4> {
    SVector::from(v).normalize()
}

#[test]
fn quaternion_sensors_match_closed_forms() {
    let q = unit([0.9, 0.1, -0.3, 0.2]);
    let x = SVector::<f64, 7>::from_fn(|i, _| if i < 4 { q[i] } else { 0.0 });
    let u = QuatAttitudeInput {
        gyro: SVector::zeros(),
    };
    let p = QuatAttitudeParams { gravity: 9.81 };
    let (w, a, b, c) = (q[0], q[1], q[2], q[3]);
    let c_bn = SMatrix::<f64, 3, 3>::new(
        1.0 - 2.0 * (b * b + c * c),
        2.0 * (a * b - w * c),
        2.0 * (a * c + w * b),
        2.0 * (a * b + w * c),
        1.0 - 2.0 * (a * a + c * c),
        2.0 * (b * c - w * a),
        2.0 * (a * c - w * b),
        2.0 * (b * c + w * a),
        1.0 - 2.0 * (a * a + b * b),
    );
    let f = QuatAttitudeAccel::predict(&x, &u, &p, &());
    let want = c_bn.transpose() * SVector::<f64, 3>::new(0.0, 0.0, -9.81);
    assert!((f - want).norm() < 1e-12, "{f} vs {want}");
    let e = QuatAttitudeEuler::predict(&x, &u, &p, &());
    let (roll, pitch, yaw) = (e[0], e[1], e[2]);
    assert!((yaw - c_bn[(1, 0)].atan2(c_bn[(0, 0)])).abs() < 1e-12);
    assert!((pitch + c_bn[(2, 0)].asin()).abs() < 1e-12);
    assert!((roll - c_bn[(2, 1)].atan2(c_bn[(2, 2)])).abs() < 1e-12);
}

#[test]
fn attitude_error_at_zero_is_the_nominal_attitude() {
    let nominal = unit([0.9, 0.1, -0.3, 0.2]);
    let u = AttitudeErrorInput { nominal };
    let p = AttitudeErrorParams { gravity: 9.81 };
    let zero = SVector::<f64, 3>::zeros();
    let h = AttitudeErrorAccel::predict(&zero, &u, &p, &());
    let h_jac = AttitudeErrorAccel::jacobian(&zero, &u, &p, &());
    assert!(h.iter().chain(h_jac.iter()).all(|v| v.is_finite()));
    // At zero error, H = [h x] (a small rotation of the body frame by e turns
    // the body-axis gravity g_b into g_b + g_b x e).
    let g_b = h;
    let want = SMatrix::<f64, 3, 3>::new(
        0.0, -g_b[2], g_b[1], g_b[2], 0.0, -g_b[0], -g_b[1], g_b[0], 0.0,
    );
    assert!((h_jac - want).norm() < 1e-12, "{h_jac} vs {want}");
}

#[test]
fn non_smooth_values_and_one_sided_derivatives() {
    let p = WheelParams { limit: 1.0 };
    // (speed, slip, h, H)
    #[allow(clippy::type_complexity)]
    let cases: [((f64, f64), [f64; 3], [[f64; 2]; 3]); 3] = [
        (
            (0.5, 0.2),
            [0.5, 0.2, 0.2],
            [[1.0, 0.0], [0.0, 1.0], [0.0, 1.0]],
        ),
        (
            (-0.5, 0.9),
            [0.1, -0.5, 0.5],
            [[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]],
        ),
        // Ties follow the first argument: max(0.1, 0.1) and min(0.1, 0.1).
        (
            (0.1, 0.1),
            [0.1, 0.1, 0.1],
            [[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        ),
    ];
    for ((speed, slip), h, jac) in cases {
        let x = SVector::<f64, 2>::new(speed, slip);
        let got = <WheelOdometer as Sensor<2, 3>>::predict(&x, &WheelInput {}, &p, &());
        let got_jac = <WheelOdometer as Sensor<2, 3>>::jacobian(&x, &WheelInput {}, &p, &());
        for i in 0..3 {
            assert_eq!(got[i], h[i], "h[{i}] at {x}");
            for j in 0..2 {
                assert_eq!(got_jac[(i, j)], jac[i][j], "H[({i}, {j})] at {x}");
            }
        }
    }
    let nan = SVector::<f64, 2>::new(f64::NAN, 0.2);
    let got = <WheelOdometer as Sensor<2, 3>>::predict(&nan, &WheelInput {}, &p, &());
    assert!(
        got[0].is_nan() && got[1].is_nan(),
        "NaN propagates through min/max"
    );
    let f = Wheel::derivative(&SVector::<f64, 2>::new(0.0, -3.0), &WheelInput {}, &p);
    assert_eq!(f, SVector::<f64, 2>::new(1.0, 0.0));
}

nav_runtime::model! {
    /// Model-level `let`s and functions shared by the process section and two sensors;
    /// the same quaternion dynamics as `QuatAttitude`, with `q` declared a
    /// unit quaternion and a heading declared an angle.
    pub model Shared {
        states { q: quaternion, heading: angle }
        inputs { gyro: 3 }
        parameters { gravity, heading_rate }
        noise { gyro_noise: 3, heading_noise }
        fn body_axes(q, v) = transpose(quat_to_dcm(q)) * v;
        fn yaw_of(c) = atan2(c[(1, 0)], c[(0, 0)]);
        let c_bn = quat_to_dcm(q);
        let down = [0.0, 0.0, -gravity];
        continuous {
            let w = gyro + gyro_noise;
            d/dt q = 0.5 * quat_mul(q, [0.0, w[0], w[1], w[2]]);
            d/dt heading = heading_rate + heading_noise;
        }
        sensor Accel: 3 {
            h = body_axes(q, down);
        }
        sensor Yaw: 1 {
            angles = [0];
            h = [yaw_of(c_bn)];
        }
        sensor Heading: 1 {
            angles = [0];
            h = heading;
        }
    }
}

nav_runtime::model! {
    /// `Shared` without the declarations of the manifolds: the drift trap.
    pub model Unkept {
        states { q: 4, heading }
        inputs { gyro: 3 }
        parameters { gravity, heading_rate }
        noise { gyro_noise: 3, heading_noise }
        continuous {
            let w = gyro + gyro_noise;
            d/dt q = 0.5 * quat_mul(q, [0.0, w[0], w[1], w[2]]);
            d/dt heading = heading_rate + heading_noise;
        }
        sensor Heading: 1 {
            angles = [0];
            h = heading;
        }
        // Only the heading is measured: the attitude is propagated, never corrected.
        allow_unused { q }
    }
}

#[test]
fn model_level_let_is_seen_by_every_sensor() {
    let q = unit([0.8, 0.2, -0.1, 0.4]);
    let x = SVector::<f64, 5>::from_fn(|i, _| if i < 4 { q[i] } else { 0.3 });
    let u = SharedInput {
        gyro: SVector::zeros(),
    };
    let p = SharedParams {
        gravity: 9.81,
        heading_rate: 0.0,
    };
    let xq = SVector::<f64, 7>::from_fn(|i, _| if i < 4 { q[i] } else { 0.0 });
    let a = <SharedAccel as Sensor<5, 3>>::predict(&x, &u, &p, &());
    let want = <QuatAttitudeAccel as Sensor<7, 3>>::predict(
        &xq,
        &QuatAttitudeInput {
            gyro: SVector::zeros(),
        },
        &QuatAttitudeParams { gravity: 9.81 },
        &(),
    );
    assert!((a - want).norm() < 1e-12);
    let yaw = <SharedYaw as Sensor<5, 1>>::predict(&x, &u, &p, &())[0];
    let euler = <QuatAttitudeEuler as Sensor<7, 3>>::predict(
        &xq,
        &QuatAttitudeInput {
            gyro: SVector::zeros(),
        },
        &QuatAttitudeParams { gravity: 9.81 },
        &(),
    );
    assert!((yaw - euler[2]).abs() < 1e-12);
}

/// The drift trap: a continuous quaternion model stepped at first order
/// (`q + 0.5 q ⊗ w dt`) grows `|q|` by `sqrt(1 + |w dt / 2|^2)` per step; the
/// `quaternion` declaration renormalizes after every predict and update, and
/// `angle` keeps the heading in (-pi, pi].
#[test]
fn declared_manifolds_are_kept_by_the_filter() {
    use nav_runtime::ekf::Ekf;
    let q0 = unit([0.8, 0.2, -0.1, 0.4]);
    let x0 = SVector::<f64, 5>::from_fn(|i, _| if i < 4 { q0[i] } else { 3.0 });
    let p0 = SMatrix::<f64, 5, 5>::identity() * 1e-4;
    let gyro = SVector::<f64, 3>::new(0.3, -0.2, 0.5);
    let mut kept = Ekf::<Shared, 5>::new(
        x0,
        p0,
        SharedParams {
            gravity: 9.81,
            heading_rate: 0.7,
        },
        SharedNoise {
            gyro_noise: SVector::repeat(1e-6),
            heading_noise: 1e-6,
        },
    )
    .unwrap();
    let mut unkept = Ekf::<Unkept, 5>::new(
        x0,
        p0,
        UnkeptParams {
            gravity: 9.81,
            heading_rate: 0.7,
        },
        UnkeptNoise {
            gyro_noise: SVector::repeat(1e-6),
            heading_noise: 1e-6,
        },
    )
    .unwrap();
    // The initial state and a replaced one are on the manifold at once: a
    // heading of 350 degrees is -10, a quaternion of norm 2 a unit one.
    let mut start = kept.clone();
    let mut off = x0 * 2.0;
    off[4] = 350f64.to_radians();
    for set in [true, false] {
        let filter = if set {
            start.set_state(off).unwrap();
            start.clone()
        } else {
            Ekf::<Shared, 5>::new(off, p0, *kept.params(), *kept.noise()).unwrap()
        };
        let x = filter.state();
        assert!(
            (x[4] - (-10f64).to_radians()).abs() < 1e-12,
            "heading {}",
            x[4]
        );
        assert!((x.fixed_rows::<4>(0) - q0).norm() < 1e-15, "{x:?}");
    }
    let dt = 0.1;
    for _ in 0..2000 {
        kept.predict(dt, &SharedInput { gyro }).unwrap();
        unkept.predict(dt, &UnkeptInput { gyro }).unwrap();
        let heading = kept.state()[4];
        assert!(heading > -std::f64::consts::PI && heading <= std::f64::consts::PI);
    }
    let norm = |x: &SVector<f64, 5>| x.fixed_rows::<4>(0).norm();
    // 2000 steps of sqrt(1 + 0.38 * 0.01 / 4): |q| = 1.0 + ~1.6.
    let grown = norm(unkept.state());
    let want = (1.0 + gyro.norm_squared() * dt * dt / 4.0).powf(1000.0);
    assert!((grown - want).abs() < 1e-9 * want, "{grown} vs {want}");
    assert!(grown > 2.5, "{grown}");
    assert!((norm(kept.state()) - 1.0).abs() < 1e-14);
    assert!(
        unkept.state()[4] > 140.0,
        "the undeclared heading grows without bound"
    );
    // Updates: the heading moved across pi comes back wrapped, and an
    // accelerometer update (which moves `q` off the unit sphere) is renormalized.
    let pi = std::f64::consts::PI;
    let x0 = SVector::<f64, 5>::from_fn(|i, _| if i < 4 { q0[i] } else { pi - 0.01 });
    let mut fresh = Ekf::<Shared, 5>::new(
        x0,
        SMatrix::identity() * 0.01,
        SharedParams {
            gravity: 9.81,
            heading_rate: 0.0,
        },
        SharedNoise::default(),
    )
    .unwrap();
    let z = SVector::<f64, 1>::new(-pi + 0.05);
    let r = SMatrix::<f64, 1, 1>::new(1e-8);
    assert!(
        fresh
            .update::<SharedHeading, 1>(&z, &r, &())
            .unwrap()
            .accepted
    );
    let heading = fresh.state()[4];
    assert!((heading - (-pi + 0.05)).abs() < 1e-5, "{heading}");
    let r3 = SMatrix::<f64, 3, 3>::identity() * 0.01;
    let before = <SharedAccel as Sensor<5, 3>>::predict(
        fresh.state(),
        &SharedInput::default(),
        fresh.params(),
        &(),
    );
    let f = before + SVector::<f64, 3>::new(0.3, -0.2, 0.1);
    let q_before = fresh.state().fixed_rows::<4>(0).into_owned();
    assert!(
        fresh
            .update::<SharedAccel, 3>(&f, &r3, &())
            .unwrap()
            .accepted
    );
    assert!(
        (fresh.state().fixed_rows::<4>(0) - q_before).norm() > 1e-3,
        "the update moved q"
    );
    assert!((norm(fresh.state()) - 1.0).abs() < 1e-14);
    assert!(
        fresh
            .update_sequential::<SharedAccel, 3>(&f, &SVector::repeat(0.01), &())
            .unwrap()
            .accepted
    );
    assert!((norm(fresh.state()) - 1.0).abs() < 1e-14);
}

#[test]
fn parameters_change_at_run_time_with_validation() {
    use nav_runtime::ekf::Ekf;
    let x0 = SVector::<f64, 5>::new(1.0, 0.0, 0.0, 0.0, 0.0);
    let mut ekf = Ekf::<Shared, 5>::new(
        x0,
        SMatrix::identity(),
        SharedParams {
            gravity: 9.81,
            heading_rate: 0.0,
        },
        SharedNoise::default(),
    )
    .unwrap();
    let bad = SharedParams {
        gravity: f64::NAN,
        heading_rate: 0.0,
    };
    assert!(ekf.set_params(bad).is_err());
    assert_eq!(
        ekf.params().gravity,
        9.81,
        "a refused setter leaves the parameters"
    );
    ekf.set_params(SharedParams {
        gravity: 9.81,
        heading_rate: 1.0,
    })
    .unwrap();
    ekf.predict(0.5, &SharedInput::default()).unwrap();
    assert!((ekf.state()[4] - 0.5).abs() < 1e-15);
}

nav_runtime::model! {
    /// A position error observed in metres: the WGS-84 radii builtins.
    pub model Radii {
        states { position_error: 2 }
        inputs { latitude, height }
        noise { walk: 2 }
        continuous {
            d/dt position_error = walk;
        }
        sensor Metres: 2 {
            h = [
                (meridian_radius(latitude) + height) * position_error[0],
                (transverse_radius(latitude) + height) * cos(latitude) * position_error[1]
            ];
        }
    }
}

/// `meridian_radius` and `transverse_radius` are the runtime's WGS-84 radii
/// (the blocks and `nav_runtime::earth` agree) at latitudes from pole to
/// pole; their derivatives are checked by the model's generated tests.
#[test]
fn earth_radii_are_the_runtimes() {
    use nav_runtime::earth::{meridian_radius, transverse_radius};
    for lat_deg in [-90.0, -60.0, -33.3, 0.0, 12.5, 45.0, 80.0, 90.0] {
        let lat = f64::to_radians(lat_deg);
        let x = SVector::<f64, 2>::new(1e-6, 2e-6);
        let u = RadiiInput {
            latitude: lat,
            height: 100.0,
        };
        let z = RadiiMetres::predict(&x, &u, &RadiiParams::default(), &());
        let north = (meridian_radius(lat) + 100.0) * 1e-6;
        let east = (transverse_radius(lat) + 100.0) * lat.cos() * 2e-6;
        assert!(
            (z[0] - north).abs() <= 1e-12 * north.abs().max(1.0),
            "{lat_deg}: {z} {north}"
        );
        assert!(
            (z[1] - east).abs() <= 1e-12 * east.abs().max(1.0),
            "{lat_deg}: {z} {east}"
        );
    }
}
