//! The generated Jacobians against the paper: F against eq. 16 (blocks F11..F35,
//! written out by hand from docs/models/sdins25.md), H against eq. 17, and the two compass
//! residuals on a pitched vehicle.

use nav_runtime::attitude::{euler_from_c_bn, perturb_c_bn, skew, Euler};
use nav_runtime::earth::{
    meridian_radius, meridian_radius_dlat, normal_gravity_series, normal_gravity_series_dh,
    transverse_radius, transverse_radius_dlat, OMEGA,
};
use nav_runtime::model::{Model, Sensor};
use nav_runtime::nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::model::*;

type Mat = SMatrix<f64, 25, 25>;

/// A seeded point: latitude, height, velocity, attitude, specific force.
fn input(k: u64) -> Sdins25Input {
    // splitmix64 -> uniform [-1, 1]
    let mut s = k.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0x1234_5678;
    let mut u = || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let e = Euler {
        roll: 0.5 * u(),
        pitch: 0.5 * u(),
        yaw: 3.0 * u(),
    };
    Sdins25Input {
        latitude: 1.2 * u(),
        height: -3000.0 + 3000.0 * u(),
        velocity: Vector3::new(3.0 * u(), 3.0 * u(), 0.5 * u()),
        c_bn: e.c_bn(),
        specific_force: Vector3::new(0.3 * u(), 0.3 * u(), -9.8 + 0.1 * u()),
    }
}

fn block(m: &mut Mat, r: usize, c: usize, b: &Matrix3<f64>) {
    m.fixed_view_mut::<3, 3>(r, c).copy_from(b);
}

/// F of docs/models/sdins25.md, eq. 16, entry by entry, plus the gravity terms the paper omits.
fn paper_f(u: &Sdins25Input) -> Mat {
    let (lat, h, v) = (u.latitude, u.height, u.velocity);
    let (vn, ve, vd) = (v.x, v.y, v.z);
    let (rm, rl) = (meridian_radius(lat) + h, transverse_radius(lat) + h);
    let (rmm, rll) = (meridian_radius_dlat(lat), transverse_radius_dlat(lat));
    let (tl, sec) = (lat.tan(), 1.0 / lat.cos());
    let (rho_n, rho_e, rho_d) = (ve / rl, -vn / rm, -ve * tl / rl);
    let (om_n, om_d) = (OMEGA * lat.cos(), -OMEGA * lat.sin());
    let f11 = Matrix3::new(
        rho_e * rmm / rm,
        0.0,
        rho_e / rm,
        rho_n * sec * (tl - rll / rl),
        0.0,
        -rho_n * sec / rl,
        0.0,
        0.0,
        0.0,
    );
    let f12 = Matrix3::from_diagonal(&Vector3::new(1.0 / rm, sec / rl, -1.0));
    let a = 2.0 * om_n + rho_n * sec * sec + rho_d * rll / rl;
    let b = 2.0 * om_d - rho_n * rll / rl;
    let mut f21 = Matrix3::new(
        -a * ve + rho_e * rmm / rm * vd,
        0.0,
        -rho_d / rl * ve + rho_e / rm * vd,
        a * vn + b * vd,
        0.0,
        rho_d / rl * vn - rho_n / rl * vd,
        -rho_e * rmm / rm * vn - b * ve,
        0.0,
        -rho_e / rm * vn + rho_n / rl * ve,
    );
    // Not in the paper: gravity's latitude and height derivatives.
    let dl = 1e-6;
    f21[(2, 0)] +=
        (normal_gravity_series(lat + dl, h) - normal_gravity_series(lat - dl, h)) / (2.0 * dl);
    f21[(2, 2)] += normal_gravity_series_dh(lat, h);
    let f22 = Matrix3::new(
        vd / rm,
        2.0 * om_d + 2.0 * rho_d,
        -rho_e,
        -2.0 * om_d - rho_d,
        (vn * tl + vd) / rl,
        2.0 * om_n + rho_n,
        2.0 * rho_e,
        -2.0 * om_n - 2.0 * rho_n,
        0.0,
    );
    let f23 = skew(&(u.c_bn * u.specific_force));
    let f31 = Matrix3::new(
        om_d - rho_n * rll / rl,
        0.0,
        -rho_n / rl,
        -rho_e * rmm / rm,
        0.0,
        -rho_e / rm,
        -om_n - rho_n * sec * sec - rho_d * rll / rl,
        0.0,
        -rho_d / rl,
    );
    let f32 = Matrix3::new(0.0, 1.0 / rl, 0.0, -1.0 / rm, 0.0, 0.0, 0.0, -tl / rl, 0.0);
    let w_in = Vector3::new(om_n + rho_n, rho_e, om_d + rho_d);
    let mut f = Mat::zeros();
    block(&mut f, 0, 0, &f11);
    block(&mut f, 0, 3, &f12);
    block(&mut f, 3, 0, &f21);
    block(&mut f, 3, 3, &f22);
    block(&mut f, 3, 6, &f23);
    block(&mut f, 3, 9, &u.c_bn);
    block(&mut f, 6, 0, &f31);
    block(&mut f, 6, 3, &f32);
    block(&mut f, 6, 6, &(-skew(&w_in)));
    block(&mut f, 6, 12, &(-u.c_bn));
    f
}

#[test]
fn f_matches_eq16_blocks() {
    for k in 0..50 {
        let u = input(k);
        let got = <Sdins25 as Model<25>>::jacobian(
            &SVector::zeros(),
            &u,
            &Sdins25Params::default(),
            0.01,
        );
        let want = paper_f(&u);
        for i in 0..25 {
            for j in 0..25 {
                let (g, w) = (got[(i, j)], want[(i, j)]);
                // Latitude columns are per radian: scale by R to compare per metre.
                let scale = if j < 2 { 1.0 / 6.4e6 } else { 1.0 };
                assert!(
                    (g - w).abs() * scale <= 1e-9 * (1.0 + w.abs() * scale) + 1e-15,
                    "point {k}: F[{i}][{j}] generated {g:e}, eq. 16 {w:e}"
                );
            }
        }
        // The 14 sensor-error rows are zero (random constants).
        assert!(got.rows(11, 14).iter().all(|v| *v == 0.0));
    }
}

#[test]
fn h_matches_eq17() {
    let p = Sdins25Params::default();
    let x = SVector::<f64, 25>::zeros();
    for k in 0..20 {
        let u = input(k);
        let (lat, h) = (u.latitude, u.height);
        // Depth: dh - b_depth.
        let hd = Sdins25Depth::jacobian(&x, &u, &p, &());
        let mut want = SMatrix::<f64, 1, 25>::zeros();
        want[2] = 1.0;
        want[Sdins25::DEPTH_BIAS] = -1.0;
        assert_eq!(hd, want);
        // DVL: dV - V x phi - C b_dvl.
        let hv = Sdins25Dvl::jacobian(&x, &u, &p, &());
        let mut want = SMatrix::<f64, 3, 25>::zeros();
        want.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&Matrix3::identity());
        want.fixed_view_mut::<3, 3>(0, 6)
            .copy_from(&(-skew(&u.velocity)));
        want.fixed_view_mut::<3, 3>(0, Sdins25::DVL_BIAS)
            .copy_from(&(-u.c_bn));
        assert!((hv - want).abs().max() < 1e-12, "DVL H at point {k}");
        // Small-angle compass: -phi_D - b_psi.
        let hc = Sdins25CompassSmallAngle::jacobian(&x, &u, &p, &());
        let mut want = SMatrix::<f64, 1, 25>::zeros();
        want[8] = -1.0;
        want[Sdins25::COMPASS_BIAS] = -1.0;
        assert_eq!(hc, want);
        // USBL: [(R_m+h) dL, (R_n+h) cos L dl] - b_usbl - ([theta x] r)_NE.
        let r = Vector3::new(40.0 * (k as f64 - 10.0), 25.0, 6000.0 - 10.0 * k as f64);
        let aux = Sdins25UsblAux {
            relative_position: r,
        };
        let hu = Sdins25Usbl::jacobian(&x, &u, &p, &aux);
        let mut want = SMatrix::<f64, 2, 25>::zeros();
        want[(0, 0)] = meridian_radius(lat) + h;
        want[(1, 1)] = (transverse_radius(lat) + h) * lat.cos();
        want[(0, Sdins25::USBL_BIAS)] = -1.0;
        want[(1, Sdins25::USBL_BIAS + 1)] = -1.0;
        // -(theta x r) = (r x theta) = [r x] theta.
        let rx = skew(&r);
        for i in 0..2 {
            for j in 0..3 {
                want[(i, Sdins25::USBL_MISALIGNMENT + j)] = rx[(i, j)];
            }
        }
        assert!(
            (hu - want).abs().max() < 1e-6,
            "USBL H at point {k}: {hu} vs {want}"
        );
    }
}

/// On a pitched vehicle the exact-yaw compass residual follows the true
/// residual `yaw(C^) - yaw(C)` to second order, the paper's `-phi_D` misses
/// the `tan(theta)` coupling of the level errors (eq. 12 assumes a level vehicle).
#[test]
fn exact_compass_beats_small_angle_when_pitching() {
    let p = Sdins25Params::default();
    let x0 = SVector::<f64, 25>::zeros();
    let phi = Vector3::new(
        0.5f64.to_radians(),
        -0.3f64.to_radians(),
        0.2f64.to_radians(),
    );
    let mut x = x0;
    x.fixed_rows_mut::<3>(6).copy_from(&phi);
    for pitch_deg in [0.0f64, 10.0, 20.0, 30.0, -25.0] {
        let truth = Euler {
            roll: 3f64.to_radians(),
            pitch: pitch_deg.to_radians(),
            yaw: 40f64.to_radians(),
        };
        let c_true = truth.c_bn();
        let c_hat = perturb_c_bn(&c_true, &phi);
        let actual = euler_from_c_bn(&c_hat).yaw - truth.yaw;
        let u = Sdins25Input {
            c_bn: c_hat,
            ..input(1)
        };
        let exact = (Sdins25Compass::jacobian(&x0, &u, &p, &()) * x)[0];
        let small = (Sdins25CompassSmallAngle::jacobian(&x0, &u, &p, &()) * x)[0];
        let (e_exact, e_small) = ((exact - actual).abs(), (small - actual).abs());
        // Second order in |phi| (1e-2 rad): below 1e-4 rad.
        assert!(
            e_exact < 1e-4,
            "pitch {pitch_deg}: exact off by {e_exact:e}"
        );
        if pitch_deg.abs() >= 10.0 {
            // First order: |tan(theta)| times the level error along the heading,
            // tan(10 deg) (0.5 cos 40 - 0.3 sin 40) deg = 5.8e-4 rad at 10 deg pitch.
            let level = phi.x * truth.yaw.cos() + phi.y * truth.yaw.sin();
            let first_order = truth.pitch.tan().abs() * level.abs();
            assert!(
                e_small > 5.0 * e_exact && e_small > 0.5 * first_order,
                "pitch {pitch_deg}: {e_small:e} vs {e_exact:e} (tan-theta term {first_order:e})"
            );
        }
    }
}
