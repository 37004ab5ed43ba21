//! PX4's 24-state model declared with the rotation written out as a matrix
//! of the quaternion's components, in a crate of its own (as a user's
//! model is), against `models::px4_ekf24::Px4Ekf24`, which uses the builtin
//! `quat_to_dcm`: the generator reaches the same structure and the same
//! operation count from either declaration (docs/performance.md, "PX4's
//! 24-state model").

#[path = "../../benches/common/px4_rotation_matrix.rs"]
mod declaration;

use declaration::{
    homogeneous_matrix_point, rotation_matrix_point, Px4HomogeneousMatrix, Px4RotationMatrix,
};
use models::px4_ekf24::{Px4Ekf24, Px4Ekf24Input, Px4Ekf24Noise, Px4Ekf24Params};
use nav_runtime::model::Model;
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3, Vector4};
use nav_runtime::propagation::Structure;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A random operating point with a unit quaternion, and a dense covariance.
fn point(
    seed: u64,
) -> (
    SVector<f64, 24>,
    Px4Ekf24Input,
    Px4Ekf24Params,
    Px4Ekf24Noise,
    SMatrix<f64, 24, 24>,
) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut u = |scale: f64| scale * rng.random_range(-1.0..1.0);
    let q = Vector4::new(u(1.0), u(1.0), u(1.0), u(1.0)).normalize();
    let mut x = SVector::<f64, 24>::from_fn(|i, _| u(if i < 7 { 10.0 } else { 1.0 }));
    x.fixed_rows_mut::<4>(0).copy_from(&q);
    let dt = 0.01;
    let input = Px4Ekf24Input {
        delta_velocity: Vector3::new(u(0.1), u(0.1), -9.8 * dt),
        delta_velocity_dt: dt,
        delta_angle: Vector3::new(u(0.02), u(0.02), u(0.02)),
        delta_angle_dt: dt,
    };
    let noise = Px4Ekf24Noise {
        delta_velocity_noise: Vector3::repeat((0.35 * dt).powi(2)),
        delta_angle_noise: Vector3::repeat((0.015 * dt).powi(2)),
    };
    let a = SMatrix::<f64, 24, 24>::from_fn(|_, _| u(0.3));
    let cov = a * a.transpose() + SMatrix::identity();
    (x, input, Px4Ekf24Params { gravity: 9.80665 }, noise, cov)
}

fn rel_diff<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(f64::MIN_POSITIVE)
}

fn same_structure(a: &Structure<'_>, b: &Structure<'_>) -> bool {
    a.identity == b.identity
        && a.rows == b.rows
        && a.start == b.start
        && a.columns == b.columns
        && a.noise == b.noise
}

/// Both matrix forms: the structure of `Phi` and `Qd` the builtin's, and
/// the operations of the propagation within 1 % of its count.
#[test]
fn either_declaration_gives_the_same_structure_and_cost() {
    let builtin = Px4Ekf24::PROPAGATION_STRUCTURE;
    let cases = [
        (
            "rotation matrix",
            Px4RotationMatrix::PROPAGATION_STRUCTURE,
            Px4RotationMatrix::OPS_PROPAGATE_COVARIANCE,
        ),
        (
            "homogeneous matrix",
            Px4HomogeneousMatrix::PROPAGATION_STRUCTURE,
            Px4HomogeneousMatrix::OPS_PROPAGATE_COVARIANCE,
        ),
    ];
    for (name, structure, ops) in cases {
        assert!(
            same_structure(&structure, &builtin),
            "{name}: {structure:?}"
        );
        let (ops, reference) = (ops as f64, Px4Ekf24::OPS_PROPAGATE_COVARIANCE as f64);
        assert!(
            (ops / reference - 1.0).abs() < 0.01,
            "{name}: {ops} ops against {reference}"
        );
    }
}

/// The textbook matrix is `quat_to_dcm` written out: the transition, `Phi`,
/// `Qd` and the propagated covariance are the builtin's at 50 random points.
#[test]
fn the_textbook_matrix_is_the_builtin() {
    for seed in 0..50 {
        let (x, u, p, q, cov) = point(seed);
        let (um, pm, qm) = rotation_matrix_point(&u, &p, &q);
        let dt = u.delta_velocity_dt;
        let pairs = [
            (
                Px4Ekf24::transition(&x, &u, &p, dt).fixed_resize::<24, 24>(0.0),
                Px4RotationMatrix::transition(&x, &um, &pm, dt).fixed_resize::<24, 24>(0.0),
            ),
            (
                Px4Ekf24::jacobian(&x, &u, &p, dt),
                Px4RotationMatrix::jacobian(&x, &um, &pm, dt),
            ),
            (
                Px4Ekf24::process_noise(&x, &u, &p, &q, dt),
                Px4RotationMatrix::process_noise(&x, &um, &pm, &qm, dt),
            ),
            {
                let (mut a, mut b) = (cov, cov);
                Px4Ekf24::propagate_covariance(&mut a, &x, &u, &p, &q, dt);
                Px4RotationMatrix::propagate_covariance(&mut b, &x, &um, &pm, &qm, dt);
                (a, b)
            },
        ];
        for (k, (builtin, written)) in pairs.iter().enumerate() {
            let d = rel_diff(written, builtin);
            assert!(d < 1e-13, "seed {seed}, item {k}: {d:e}");
        }
    }
}

/// PX4's homogeneous form (`q0² + q1² - q2² - q3²` on the diagonal) is
/// another function off the unit sphere: the same transition on unit
/// quaternions and the same derivative along every direction tangent to
/// the sphere, but not along the quaternion itself. No generator can give
/// it the builtin's `Phi`; the structure and cost are the same (above).
#[test]
fn the_homogeneous_matrix_differs_only_off_the_unit_sphere() {
    for seed in 0..50 {
        let (x, u, p, q, _) = point(seed);
        let (uh, ph, _) = homogeneous_matrix_point(&u, &p, &q);
        let dt = u.delta_velocity_dt;
        let f = Px4Ekf24::transition(&x, &u, &p, dt);
        let fh = Px4HomogeneousMatrix::transition(&x, &uh, &ph, dt);
        assert!((fh - f).amax() < 1e-12 * f.amax(), "seed {seed}");
        let phi = Px4Ekf24::jacobian(&x, &u, &p, dt);
        let phi_h = Px4HomogeneousMatrix::jacobian(&x, &uh, &ph, dt);
        let quaternion = x.fixed_rows::<4>(0).into_owned();
        // A direction in every state, its quaternion part made tangent.
        let mut direction =
            SVector::<f64, 24>::from_fn(|i, _| ((i * 7 + seed as usize) % 5) as f64 - 2.0);
        let along = direction.fixed_rows::<4>(0).dot(&quaternion);
        direction
            .fixed_rows_mut::<4>(0)
            .axpy(-along, &quaternion, 1.0);
        let (a, b) = (phi * direction, phi_h * direction);
        assert!((a - b).amax() < 1e-12 * a.amax(), "seed {seed}: tangent");
        // Along the quaternion the two derivatives differ (the velocity rows).
        let mut radial = SVector::<f64, 24>::zeros();
        radial.fixed_rows_mut::<4>(0).copy_from(&quaternion);
        let (a, b) = (phi * radial, phi_h * radial);
        assert!((a - b).amax() > 1e-4, "seed {seed}: radial");
    }
}
