//! Integration tests: the models of docs/models/ declared with `nav_runtime::model!`,
//! compared with hand-written matrices; every generated model also carries its
//! own finite-difference and dense-product tests (`__*_generated_tests`).

use nav_runtime::model::{Model, Record, Sensor};
use nav_runtime::nalgebra::{SMatrix, SVector};

nav_runtime::model! {
    /// LEVELING-6, docs/models/leveling6.md (eqs. 15-17, 26, 29-34).
    pub model Leveling6 {
        states {
            /// body velocity, m/s
            velocity: 3,
            /// gravity direction in body axes
            a: 3,
        }
        inputs { gyro: 3, specific_force: 3, earth_rate_body: 3 }
        parameters { gravity }
        noise { accel_noise: 3, gyro_noise: 3 }
        continuous {
            let w_star = gyro + earth_rate_body; // eq. 15
            let w = gyro - earth_rate_body; // eq. 17
            d/dt velocity = -cross(w_star, velocity) + gravity * a + specific_force + accel_noise;
            d/dt a = -cross(w + gyro_noise, a); // eq. 7
        }
        /// Moving: forward speed and unit norm (eq. 30).
        sensor Moving: 2 {
            h = [velocity[0], norm_squared(a)];
        }
        /// Stationary: zero velocity and unit norm (eq. 33).
        sensor Stationary: 4 {
            h = [velocity[0], velocity[1], velocity[2], norm_squared(a)];
        }
    }
}

/// MARKER-9 (discrete), declared for a name and a scalar: [`Marker9`] in
/// `f64`, [`Marker9Single`] in `f32` (whose generated tests check the `f32`
/// code).
macro_rules! marker9 {
    ($name:ident, $scalar:ident) => {
nav_runtime::model! {
    /// MARKER-9, docs/models/marker9.md, eq. 2 (discrete).
    pub model $name {
        scalar $scalar;
        states { position: 3, velocity: 3, roll, pitch, yaw }
        inputs { gyro: 3, acceleration: 3 }
        noise { velocity_noise: 3, attitude_noise: 3 }
        discrete {
            let c = euler_dcm(roll, pitch, yaw);
            let p = gyro[0];
            let q = gyro[1];
            let r = gyro[2];
            position = position + c * velocity * dt;
            velocity = velocity + acceleration * dt + velocity_noise;
            roll = roll + (p + q * sin(roll) * tan(pitch) + r * cos(roll) * tan(pitch)) * dt + attitude_noise[0];
            pitch = pitch + (q * cos(roll) - r * sin(roll)) * dt + attitude_noise[1];
            yaw = yaw + (q * sin(roll) / cos(pitch) + r * cos(roll) / cos(pitch)) * dt + attitude_noise[2];
        }
        /// Marker position fix in the frame rotated by the initial heading (eq. 3).
        sensor MarkerFix: 2 {
            inputs { psi0 }
            h = [cos(psi0) * position[0] + sin(psi0) * position[1],
                 -sin(psi0) * position[0] + cos(psi0) * position[1]];
        }
        sensor Depth: 1 {
            h = position[2];
        }
        sensor Heading: 1 {
            angles = [0];
            h = [yaw];
        }
    }
}
    };
}

marker9!(Marker9, f64);
marker9!(Marker9Single, f32);

/// Every builtin, declared for a name and a scalar: [`Everything`] in `f64`,
/// [`EverythingSingle`] in `f32`.
macro_rules! everything {
    ($name:ident, $scalar:ident) => {
nav_runtime::model! {
    /// Every function, every vector function, a matrix input, method-call forms and a
    /// sensor with auxiliary inputs.
    model $name {
        scalar $scalar;
        states { s: 2, z }
        inputs { m: 2x2, v: 3 }
        parameters { k }
        noise { nz }
        continuous {
            let r = m * s;
            let q = transpose(m) * m + [[1.0, 0.5], [0.25, 2.0]];
            let e = euler_dcm(z, s[0], s[1]);
            d/dt s = [
                sin(s[0]) + cos(s[1]) * tan(0.3 * z) + asin(0.5 * sin(z)) + acos(0.4 * cos(s[0])),
                atan(s[1]) + sqrt(1.0 + s[0] * s[0]) + exp(0.5 * z) + ln(2.0 + sin(s[1]))
                    + abs(2.0 + z) * atan2(s[0], 2.0 + cos(z)) + powi(s[0], 3) - powi(1.0 + z * z, -2)
            ] + r + k * (q * s) / 3.0;
            d/dt z = dot(v, cross(v, [s[0], s[1], z])) + norm(v) * z + norm_squared([s[0], z])
                + (skew(v) * [s[0], z, s[1]])[1] + e[(0, 1)] * e[(2, 2)] + m[(1, 0)] * z
                + s[0].sin() * v.dot(v) + z.atan2(2.0) + s[1].powi(2) + nz * (1.0 + z * z);
        }
        sensor Look: 2 {
            inputs { offset, lever: 3 }
            angles = [1];
            let d = euler_dcm(z, s[0], s[1]) * lever;
            h = [d[0] + offset, atan2(s[1], 2.0 + s[0])];
        }
    }
}
    };
}

everything!(Everything, f64);
everything!(EverythingSingle, f32);

/// splitmix64, uniform in [-1, 1].
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn record<R: Record>(&mut self) -> R {
        R::from_fn(|_| self.uniform())
    }
    fn vector<const K: usize>(&mut self) -> SVector<f64, K> {
        SVector::from_fn(|_, _| self.uniform())
    }
}

fn assert_matrix_close<const R: usize, const C: usize>(
    what: &str,
    got: &SMatrix<f64, R, C>,
    want: &SMatrix<f64, R, C>,
    tol: f64,
) {
    for r in 0..R {
        for c in 0..C {
            let (a, b) = (got[(r, c)], want[(r, c)]);
            assert!(
                (a - b).abs() <= tol * (1.0 + b.abs()),
                "{what}[({r}, {c})]: {a} vs {b}\n{got}\n{want}"
            );
        }
    }
}

#[test]
fn leveling_f_is_eq_26() {
    let mut rng = Rng(1);
    for _ in 0..20 {
        let x: SVector<f64, 6> = rng.vector();
        let u: Leveling6Input = rng.record();
        let p: Leveling6Params = rng.record();
        let f = <Leveling6 as Model<6>>::jacobian(&x, &u, &p, 0.01);
        let ws = u.gyro + u.earth_rate_body;
        let w = u.gyro - u.earth_rate_body;
        let (ps, qs, rs) = (ws[0], ws[1], ws[2]);
        let (pp, qq, rr) = (w[0], w[1], w[2]);
        let g = p.gravity;
        #[rustfmt::skip]
        let want = SMatrix::<f64, 6, 6>::from_row_slice(&[
            0.0, rs, -qs, g, 0.0, 0.0,
            -rs, 0.0, ps, 0.0, g, 0.0,
            qs, -ps, 0.0, 0.0, 0.0, g,
            0.0, 0.0, 0.0, 0.0, rr, -qq,
            0.0, 0.0, 0.0, -rr, 0.0, pp,
            0.0, 0.0, 0.0, qq, -pp, 0.0,
        ]);
        assert_matrix_close("F", &f, &want, 1e-12);
        // The structural zeros of eq. 26 are compile-time constants.
        for r in 0..6 {
            for c in 0..6 {
                assert_eq!(
                    <Leveling6 as Model<6>>::JACOBIAN_SPARSITY[r][c],
                    want[(r, c)] != 0.0,
                    "({r}, {c})"
                );
            }
        }
        // Noise enters the velocity rows directly and the attitude rows through [a x].
        let gm = Leveling6::noise_jacobian(&x, &u, &p, 0.01);
        let a = x.fixed_rows::<3>(3).into_owned();
        let mut want_g = SMatrix::<f64, 6, 6>::zeros();
        want_g
            .fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&SMatrix::<f64, 3, 3>::identity());
        want_g
            .fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&a.cross_matrix());
        assert_matrix_close("G", &gm, &want_g, 1e-12);
    }
}

#[test]
fn leveling_sensors_are_eqs_30_and_33() {
    let mut rng = Rng(2);
    for _ in 0..20 {
        let x: SVector<f64, 6> = rng.vector();
        let u: Leveling6Input = rng.record();
        let p: Leveling6Params = rng.record();
        let (a1, a2, a3) = (x[3], x[4], x[5]);
        let hm = <Leveling6Moving as Sensor<6, 2>>::jacobian(&x, &u, &p, &());
        #[rustfmt::skip]
        let want = SMatrix::<f64, 2, 6>::from_row_slice(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 2.0 * a1, 2.0 * a2, 2.0 * a3,
        ]);
        assert_matrix_close("H moving", &hm, &want, 1e-12);
        let z = <Leveling6Moving as Sensor<6, 2>>::predict(&x, &u, &p, &());
        assert_matrix_close(
            "h moving",
            &z,
            &SVector::<f64, 2>::new(x[0], a1 * a1 + a2 * a2 + a3 * a3),
            1e-12,
        );

        let hs = <Leveling6Stationary as Sensor<6, 4>>::jacobian(&x, &u, &p, &());
        #[rustfmt::skip]
        let want = SMatrix::<f64, 4, 6>::from_row_slice(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 1.0, 0.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
            0.0, 0.0, 0.0, 2.0 * a1, 2.0 * a2, 2.0 * a3,
        ]);
        assert_matrix_close("H stationary", &hs, &want, 1e-12);
    }
}

#[test]
fn leveling_generated_api() {
    assert_eq!(Leveling6::N, 6);
    assert_eq!(Leveling6::NW, 6);
    assert_eq!((Leveling6::VELOCITY, Leveling6::A), (0, 3));
    assert_eq!(<Leveling6 as Model<6>>::NAME, "Leveling6");
    const { assert!(!<Leveling6 as Model<6>>::DISCRETE) };
    assert_eq!(
        <Leveling6 as Model<6>>::STATE_NAMES,
        [
            "velocity[0]",
            "velocity[1]",
            "velocity[2]",
            "a[0]",
            "a[1]",
            "a[2]"
        ]
    );
    assert_eq!(<Leveling6Input as Record>::LEN, 9);
    assert_eq!(<Leveling6Params as Record>::NAMES, &["gravity"]);
    assert_eq!(Leveling6Moving::M, 2);
    assert_eq!(<Leveling6Moving as Sensor<6, 2>>::NAME, "Moving");
    assert_eq!(<Leveling6Moving as Sensor<6, 2>>::ANGLES, [false, false]);
    assert_eq!(
        Leveling6::OPS_JACOBIAN,
        <Leveling6 as Model<6>>::OPS_JACOBIAN
    );
    const { assert!(Leveling6::OPS_PROPAGATE_COVARIANCE > 0) };
    eprintln!(
        "Leveling6 ops: transition {}, derivative {}, jacobian {}, noise_jacobian {}, process_noise {}, \
         propagate_covariance {}, Moving innovation_terms {}, Stationary innovation_terms {}",
        Leveling6::OPS_TRANSITION,
        Leveling6::OPS_DERIVATIVE,
        Leveling6::OPS_JACOBIAN,
        Leveling6::OPS_NOISE_JACOBIAN,
        Leveling6::OPS_PROCESS_NOISE,
        Leveling6::OPS_PROPAGATE_COVARIANCE,
        Leveling6Moving::OPS_INNOVATION_TERMS,
        Leveling6Stationary::OPS_INNOVATION_TERMS,
    );
    // The Euler step uses the derivative.
    let mut rng = Rng(3);
    let x: SVector<f64, 6> = rng.vector();
    let u: Leveling6Input = rng.record();
    let p: Leveling6Params = rng.record();
    let step = <Leveling6 as Model<6>>::transition(&x, &u, &p, 0.1);
    assert_matrix_close(
        "transition",
        &step,
        &(x + Leveling6::derivative(&x, &u, &p) * 0.1),
        1e-14,
    );
    let s = Leveling6State::from_vector(&x);
    assert_eq!(s.a[2], x[5]);
    assert_eq!(s.to_vector(), x);
}

/// C_b^n as printed in docs/models/conventions.md, item 2 (transposed C_n^b).
fn c_bn(phi: f64, theta: f64, psi: f64) -> SMatrix<f64, 3, 3> {
    let (sf, cf, st, ct, sp, cp) = (
        phi.sin(),
        phi.cos(),
        theta.sin(),
        theta.cos(),
        psi.sin(),
        psi.cos(),
    );
    #[rustfmt::skip]
    let c_nb = SMatrix::<f64, 3, 3>::from_row_slice(&[
        ct * cp, ct * sp, -st,
        sf * st * cp - cf * sp, sf * st * sp + cf * cp, sf * ct,
        cf * st * cp + sf * sp, cf * st * sp - sf * cp, cf * ct,
    ]);
    c_nb.transpose()
}

/// MARKER-9 eq. 2, written out by hand.
fn marker_step(
    x: &SVector<f64, 9>,
    gyro: &SVector<f64, 3>,
    acc: &SVector<f64, 3>,
    dt: f64,
) -> SVector<f64, 9> {
    let (phi, theta, psi) = (x[6], x[7], x[8]);
    let (p, q, r) = (gyro[0], gyro[1], gyro[2]);
    let pos = x.fixed_rows::<3>(0) + c_bn(phi, theta, psi) * x.fixed_rows::<3>(3) * dt;
    let vel = x.fixed_rows::<3>(3) + acc * dt;
    let mut out = SVector::<f64, 9>::zeros();
    out.fixed_rows_mut::<3>(0).copy_from(&pos);
    out.fixed_rows_mut::<3>(3).copy_from(&vel);
    out[6] = phi + (p + q * phi.sin() * theta.tan() + r * phi.cos() * theta.tan()) * dt;
    out[7] = theta + (q * phi.cos() - r * phi.sin()) * dt;
    out[8] = psi + (q * phi.sin() / theta.cos() + r * phi.cos() / theta.cos()) * dt;
    out
}

#[test]
fn marker_phi_matches_eq_2() {
    let mut rng = Rng(4);
    for _ in 0..20 {
        let x: SVector<f64, 9> = rng.vector();
        let u: Marker9Input = rng.record();
        let dt = 0.05 + 0.05 * rng.uniform().abs();
        let step = <Marker9 as Model<9>>::transition(&x, &u, &Marker9Params {}, dt);
        assert_matrix_close(
            "transition",
            &step,
            &marker_step(&x, &u.gyro, &u.acceleration, dt),
            1e-12,
        );

        let phi = <Marker9 as Model<9>>::jacobian(&x, &u, &Marker9Params {}, dt);
        // Exact blocks: dp/dp = I, dp/dv = C_b^n dt, dv/dv = I, and no coupling back.
        let c = c_bn(x[6], x[7], x[8]);
        assert_matrix_close(
            "dp/dp",
            &phi.fixed_view::<3, 3>(0, 0).into_owned(),
            &SMatrix::identity(),
            1e-12,
        );
        assert_matrix_close(
            "dp/dv",
            &phi.fixed_view::<3, 3>(0, 3).into_owned(),
            &(c * dt),
            1e-12,
        );
        assert_matrix_close(
            "dv/dv",
            &phi.fixed_view::<3, 3>(3, 3).into_owned(),
            &SMatrix::identity(),
            1e-12,
        );
        assert_eq!(
            phi.fixed_view::<3, 6>(3, 3)
                .iter()
                .filter(|v| **v != 0.0)
                .count(),
            3
        );
        assert!(phi.fixed_view::<3, 6>(6, 0).iter().all(|v| *v == 0.0));
        // The whole Phi against central differences of the hand-written step.
        let mut fd = SMatrix::<f64, 9, 9>::zeros();
        for j in 0..9 {
            let h = 1e-6;
            let (mut xp, mut xm) = (x, x);
            xp[j] += h;
            xm[j] -= h;
            fd.set_column(
                j,
                &((marker_step(&xp, &u.gyro, &u.acceleration, dt)
                    - marker_step(&xm, &u.gyro, &u.acceleration, dt))
                    / (2.0 * h)),
            );
        }
        assert_matrix_close("Phi", &phi, &fd, 1e-7);
        // Structural zeros: attitude rows do not depend on position or velocity.
        let sp = <Marker9 as Model<9>>::JACOBIAN_SPARSITY;
        assert!((6..9).all(|r| (0..6).all(|c| !sp[r][c])));
        assert!(sp[0][8] && sp[8][6] && !sp[8][8 - 8]);
    }
    const { assert!(<Marker9 as Model<9>>::DISCRETE) };
    assert_eq!(
        <Marker9 as Model<9>>::STATE_NAMES[6..],
        ["roll", "pitch", "yaw"]
    );
    assert_eq!(
        (
            Marker9::POSITION,
            Marker9::VELOCITY,
            Marker9::ROLL,
            Marker9::PITCH,
            Marker9::YAW
        ),
        (0, 3, 6, 7, 8)
    );
}

#[test]
fn marker_fix_h_is_rotated_position() {
    let mut rng = Rng(5);
    for _ in 0..10 {
        let x: SVector<f64, 9> = rng.vector();
        let u: Marker9Input = rng.record();
        let aux = Marker9MarkerFixAux {
            psi0: 3.0 * rng.uniform(),
        };
        let h = <Marker9MarkerFix as Sensor<9, 2>>::jacobian(&x, &u, &Marker9Params {}, &aux);
        let (c, s) = (aux.psi0.cos(), aux.psi0.sin());
        let mut want = SMatrix::<f64, 2, 9>::zeros();
        want[(0, 0)] = c;
        want[(0, 1)] = s;
        want[(1, 0)] = -s;
        want[(1, 1)] = c;
        assert_matrix_close("H marker", &h, &want, 1e-14);
        let hd = <Marker9Depth as Sensor<9, 1>>::jacobian(&x, &u, &Marker9Params {}, &());
        assert_eq!(hd[(0, 2)], 1.0);
        assert_eq!(hd.iter().filter(|v| **v != 0.0).count(), 1);
    }
    assert_eq!(<Marker9Heading as Sensor<9, 1>>::ANGLES, [true]);
    assert_eq!(
        <Marker9MarkerFix as Sensor<9, 2>>::JACOBIAN_SPARSITY[1][..3],
        [true, true, false]
    );
    // A scalar-only H costs nothing: the marker fix's H P H^T has 2 x 2 terms per entry.
    assert_eq!(Marker9Depth::OPS_JACOBIAN, 0);
    assert_eq!(<Marker9Depth as Sensor<9, 1>>::OPS_INNOVATION_TERMS, 0);
}

#[test]
fn everything_records_and_shapes() {
    assert_eq!(
        <EverythingInput as Record>::NAMES,
        &["m[0][0]", "m[0][1]", "m[1][0]", "m[1][1]", "v[0]", "v[1]", "v[2]"]
    );
    let u = EverythingInput::from_fn(|i| i as f64);
    assert_eq!(u.m, SMatrix::<f64, 2, 2>::new(0.0, 1.0, 2.0, 3.0));
    assert_eq!(u.get(2), 2.0);
    assert!(u.get(7).is_nan());
    assert_eq!(
        <EverythingLookAux as Record>::NAMES,
        &["offset", "lever[0]", "lever[1]", "lever[2]"]
    );
    assert_eq!(<EverythingLook as Sensor<3, 2>>::ANGLES, [false, true]);
    assert_eq!(Everything::NW, 1);
}

/// The `f32` twins evaluate every builtin as the `f64` models do, to `f32`
/// rounding: transition, `F` and sensor `h`/`H` at random points, relative
/// to the magnitude of each value (1e-4: a few hundred `f32` ulps, for
/// chains of transcendental functions).
#[test]
fn single_precision_twins_agree_with_double() {
    fn close<const R: usize, const C: usize>(
        what: &str,
        a: &SMatrix<f64, R, C>,
        b: &SMatrix<f32, R, C>,
    ) {
        for (x, y) in a.iter().zip(b.iter()) {
            let y = f64::from(*y);
            assert!(
                (x - y).abs() <= 1e-4 * (1.0 + x.abs()),
                "{what}: f64 {x} vs f32 {y}"
            );
        }
    }
    fn convert<A: Record, B: Record>(a: &A) -> B {
        B::from_fn(|i| a.get(i))
    }
    let mut rng = Rng(0xf32);
    for _ in 0..20 {
        let x: SVector<f64, 3> = rng.vector();
        let u: EverythingInput = rng.record();
        let p: EverythingParams = rng.record();
        let aux: EverythingLookAux = rng.record();
        let (xs, us, ps, auxs) = (x.cast::<f32>(), convert(&u), convert(&p), convert(&aux));
        let dt = 0.01;
        close(
            "transition",
            &<Everything as Model<3>>::transition(&x, &u, &p, dt),
            &<EverythingSingle as Model<3, f32>>::transition(&xs, &us, &ps, dt as f32),
        );
        close(
            "F",
            &<Everything as Model<3>>::jacobian(&x, &u, &p, dt),
            &<EverythingSingle as Model<3, f32>>::jacobian(&xs, &us, &ps, dt as f32),
        );
        close(
            "h",
            &<EverythingLook as Sensor<3, 2>>::predict(&x, &u, &p, &aux),
            &<EverythingSingleLook as Sensor<3, 2, f32>>::predict(&xs, &us, &ps, &auxs),
        );
        close(
            "H",
            &<EverythingLook as Sensor<3, 2>>::jacobian(&x, &u, &p, &aux),
            &<EverythingSingleLook as Sensor<3, 2, f32>>::jacobian(&xs, &us, &ps, &auxs),
        );
        let xm: SVector<f64, 9> = rng.vector();
        let um: Marker9Input = rng.record();
        close(
            "MARKER-9 Phi",
            &<Marker9 as Model<9>>::jacobian(&xm, &um, &Default::default(), 0.02),
            &<Marker9Single as Model<9, f32>>::jacobian(
                &xm.cast(),
                &convert(&um),
                &Default::default(),
                0.02,
            ),
        );
    }
}

/// The `f32` filter core with every discretization (first order through
/// the generated propagation, Heun with the dense second-order `Phi`, Van
/// Loan with Runge-Kutta 4) and both update forms follows the `f64` one on
/// MARKER-9 to `f32` rounding.
#[test]
fn single_precision_filter_follows_double_with_every_discretization() {
    use nav_runtime::ekf::{Discretization, Ekf};
    let x0 =
        SVector::<f64, 9>::from_column_slice(&[3.0, -2.0, 10.0, 0.4, 0.05, 0.01, 0.03, -0.02, 1.1]);
    let p0 = SMatrix::<f64, 9, 9>::identity() * 0.01;
    let noise = |i: usize| if i < 3 { 1e-4 } else { 1e-6 };
    for method in [
        Discretization::FirstOrder,
        Discretization::SecondOrder,
        Discretization::VanLoan,
    ] {
        let mut double = Ekf::<Marker9, 9>::new(x0, p0, Default::default(), Record::from_fn(noise))
            .unwrap()
            .with_discretization(method);
        let mut single = Ekf::<Marker9Single, 9, f32>::new(
            x0.cast(),
            p0.cast(),
            Default::default(),
            Record::from_fn(noise),
        )
        .unwrap()
        .with_discretization(method);
        let mut rng = Rng(9);
        for k in 0..200 {
            let u: Marker9Input =
                Record::from_fn(|i| 0.1 * rng.uniform() + if i == 3 { 0.2 } else { 0.0 });
            double.predict(0.05, &u).unwrap();
            single
                .predict(0.05, &Record::from_fn(|i| u.get(i)))
                .unwrap();
            if k % 5 == 4 {
                let z = SVector::<f64, 2>::new(0.01 * rng.uniform(), 0.01 * rng.uniform());
                let r = SMatrix::<f64, 2, 2>::identity() * 1e-4;
                let aux: Marker9MarkerFixAux = Record::from_fn(|_| 0.3);
                double.update::<Marker9MarkerFix, 2>(&z, &r, &aux).unwrap();
                single
                    .update::<Marker9SingleMarkerFix, 2>(
                        &z.cast(),
                        &r.cast(),
                        &Record::from_fn(|_| 0.3),
                    )
                    .unwrap();
                let zd = SVector::<f64, 1>::new(10.0 + 0.01 * rng.uniform());
                let rd = SVector::<f64, 1>::new(1e-4);
                double
                    .update_sequential::<Marker9Depth, 1>(&zd, &rd, &())
                    .unwrap();
                single
                    .update_sequential::<Marker9SingleDepth, 1>(&zd.cast(), &rd.cast(), &())
                    .unwrap();
            }
        }
        let (xd, xs) = (double.state(), single.state());
        let (pd, ps) = (double.covariance(), single.covariance());
        for i in 0..9 {
            let sigma = pd[(i, i)].sqrt();
            let dx = (xd[i] - f64::from(xs[i])).abs();
            assert!(
                dx <= 1e-2 * sigma + 1e-5 * xd[i].abs(),
                "{method:?}: state {i}: {} vs {}",
                xd[i],
                xs[i]
            );
            let ds = (sigma - f64::from(ps[(i, i)]).sqrt()).abs() / sigma;
            assert!(ds < 1e-3, "{method:?}: sigma {i} differs by {ds} relative");
        }
        assert_eq!(single.counters().covariance_repairs, 0, "{method:?}");
    }
}

nav_runtime::model! {
    /// An error model: `F x` and noise only.
    model ErrorOnly {
        states { e: 2 }
        inputs { rate }
        noise { w: 2 }
        continuous {
            d/dt e = [rate * e[1] + w[0], -rate * e[0] + sin(e[1]) + w[1]];
        }
        sensor Fix: 1 { h = [e[0]]; }
    }
}
nav_runtime::model! {
    /// The same with a forcing input: zero is not kept.
    model Forced {
        states { e: 2 }
        inputs { rate, push }
        noise { w: 2 }
        continuous {
            d/dt e = [rate * e[1] + w[0] + push, -rate * e[0] + cos(e[1]) + w[1]];
        }
        sensor Fix: 1 { h = [e[0]]; }
    }
}

/// `Model::ZERO_IS_FIXED` is proved symbolically: true only where the
/// transition of the zero state is zero for every input and parameter.
#[test]
fn zero_is_fixed_only_where_the_transition_keeps_zero() {
    let cases = [
        ("ErrorOnly", <ErrorOnly as Model<2>>::ZERO_IS_FIXED, true),
        ("Forced", <Forced as Model<2>>::ZERO_IS_FIXED, false),
        ("Leveling6", <Leveling6 as Model<6>>::ZERO_IS_FIXED, false),
        ("Marker9", <Marker9 as Model<9>>::ZERO_IS_FIXED, false),
        ("Everything", <Everything as Model<3>>::ZERO_IS_FIXED, false),
    ];
    for (name, got, want) in cases {
        assert_eq!(got, want, "{name}");
    }
    // Where it holds, skipping the transition at zero is exact.
    let u = ErrorOnlyInput { rate: 0.3 };
    let x = <ErrorOnly as Model<2>>::transition(&SVector::zeros(), &u, &Default::default(), 0.1);
    assert_eq!(x, SVector::<f64, 2>::zeros());
}
