use nalgebra::Cholesky;

use super::joseph::{joseph_in_place, joseph_in_place_steps, joseph_update};
use super::*;
use crate::model::Sensor;
use crate::testmodels::{
    Angle, Cvb, CvbInput, CvbNoise, Dcv, DcvNoise, Gauss, Offset, Osc, OscNoise, OscParams, Pos,
    PosVel, Quad, Rows, RowsInput, RowsNoise,
};

type M3 = SMatrix<f64, 3, 3>;
type V3 = SVector<f64, 3>;

const NOISE: CvbNoise = CvbNoise {
    q_a: 1e-2,
    q_b: 1e-5,
};

fn p0() -> M3 {
    M3::new(4.0, 0.3, 0.01, 0.3, 0.5, -0.02, 0.01, -0.02, 0.01)
}

fn filter() -> Ekf<Cvb, 3> {
    Ekf::new(V3::new(1.0, -0.5, 0.1), p0(), (), NOISE).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / (1.0 + a.abs().max(b.abs()))
}

fn max_rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / (1.0 + a.amax().max(b.amax()))
}

/// Bitwise identity of state, covariance and last input.
fn same_bits(a: &Ekf<Cvb, 3>, b: &Ekf<Cvb, 3>) -> bool {
    let bits = |e: &Ekf<Cvb, 3>| {
        let mut v: Vec<u64> = e
            .state()
            .iter()
            .chain(e.covariance().iter())
            .map(|x| x.to_bits())
            .collect();
        v.push(e.input().a.to_bits());
        v
    };
    bits(a) == bits(b)
}

/// A random SPD prior `P`, `H`, SPD `R`, and `U = P H^T`, `S = H U + R`.
#[allow(clippy::type_complexity)]
fn random_update<const N: usize, const M: usize>(
    g: &mut Gauss,
) -> (
    SMatrix<f64, N, N>,
    SMatrix<f64, M, N>,
    SMatrix<f64, M, M>,
    SMatrix<f64, N, M>,
    SMatrix<f64, M, M>,
) {
    let p: SMatrix<f64, N, N> = g.spd(0.1);
    let h = SMatrix::<f64, M, N>::from_fn(|_, _| g.normal());
    let r: SMatrix<f64, M, M> = g.spd(0.05);
    let u = p * h.transpose();
    let s = h * u + r;
    (p, h, r, u, s)
}

#[test]
fn joseph_equals_textbook_for_any_gain_and_standard_form_for_optimal_gain() {
    let mut g = Gauss::new(1);
    for _ in 0..50 {
        let (p, h, r, u, s) = random_update::<5, 2>(&mut g);
        let i5 = SMatrix::<f64, 5, 5>::identity();
        // Random suboptimal gain.
        let k = SMatrix::<f64, 5, 2>::from_fn(|_, _| g.normal());
        let textbook = (i5 - k * h) * p * (i5 - k * h).transpose() + k * r * k.transpose();
        let got = joseph_update(&p, &k, &u, &s);
        assert!(
            max_rel(&got, &textbook) < 1e-12,
            "{}",
            max_rel(&got, &textbook)
        );
        // Optimal gain: equals (I - K H) P.
        let k_opt = u * s.try_inverse().unwrap();
        let standard = (i5 - k_opt * h) * p;
        let got = joseph_update(&p, &k_opt, &u, &s);
        assert!(
            max_rel(&got, &standard) < 1e-12,
            "{}",
            max_rel(&got, &standard)
        );
        assert_eq!(got, got.transpose());
    }
}

#[test]
fn joseph_vector_width_never_changes_a_bit() {
    let mut g = Gauss::new(7);
    for _ in 0..20 {
        let (p, _, _, u, s) = random_update::<25, 3>(&mut g);
        let k = u * s.try_inverse().unwrap();
        let (mut dispatched, mut portable) = (p, p);
        let a = joseph_in_place(&mut dispatched, &k, &u, &s, 0.0);
        let b = joseph_in_place_steps::<f64, 25, 3, false, { crate::dispatch::FUSED }>(
            &mut portable,
            &k,
            &u,
            &s,
            0.0,
        );
        assert_eq!(a, b);
        assert!(dispatched
            .iter()
            .zip(&portable)
            .all(|(x, y)| x.to_bits() == y.to_bits()));
    }
}

/// The fused Joseph kernel (the `fma` build) equals the unfused one to the
/// last bits, and is not the same rounding.
#[test]
fn fused_joseph_differs_only_in_the_last_bits() {
    let mut g = Gauss::new(11);
    let mut differs = false;
    for _ in 0..20 {
        let (p, _, _, u, s) = random_update::<25, 3>(&mut g);
        let k = u * s.try_inverse().unwrap();
        let (mut fused, mut unfused) = (p, p);
        let a = joseph_in_place_steps::<f64, 25, 3, false, true>(&mut fused, &k, &u, &s, 0.0);
        let b = joseph_in_place_steps::<f64, 25, 3, false, false>(&mut unfused, &k, &u, &s, 0.0);
        assert_eq!(a, b);
        assert_eq!(fused, fused.transpose());
        let apart = max_rel(&fused, &unfused);
        assert!(apart < 1e-12, "{apart}");
        differs |= fused != unfused;
    }
    assert!(differs, "the fused kernel rounds as the unfused one");
}

#[test]
fn update_matches_textbook_kalman_update() {
    let mut f = filter().with_default_gate(None);
    let z = SVector::<f64, 2>::new(1.7, -0.2);
    let r = SMatrix::<f64, 2, 2>::new(0.3, 0.05, 0.05, 0.2);
    let (x, p) = (*f.state(), *f.covariance());
    let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let s = h * p * h.transpose() + r;
    let k = p * h.transpose() * s.try_inverse().unwrap();
    let nu = z - h * x;
    let rep = f.update::<PosVel, 2>(&z, &r, &()).unwrap();
    assert!(rep.accepted && rep.threshold.is_none());
    assert!(max_rel(&rep.innovation, &nu) < 1e-15);
    assert!(max_rel(&rep.innovation_covariance, &s) < 1e-15);
    assert!(rel(rep.nis, (nu.transpose() * s.try_inverse().unwrap() * nu)[0]) < 1e-13);
    assert!(max_rel(f.state(), &(x + k * nu)) < 1e-14);
    assert!(max_rel(f.covariance(), &((M3::identity() - k * h) * p)) < 1e-13);
    assert_eq!(f.counters().updates_accepted, 1);
}

#[test]
fn sequential_update_equals_batch_for_diagonal_noise() {
    fn check<S: Sensor<3, 2, Model = Cvb, Aux = ()>>(z: SVector<f64, 2>) {
        let r = SVector::<f64, 2>::new(0.3, 0.2);
        let mut batch = filter().with_default_gate(None);
        let mut seq = batch.clone();
        let rb = batch
            .update::<S, 2>(&z, &SMatrix::from_diagonal(&r), &())
            .unwrap();
        let rs = seq.update_sequential::<S, 2>(&z, &r, &()).unwrap();
        assert!(rel(rb.nis, rs.nis) < 1e-12, "{} {}", rb.nis, rs.nis);
        assert!(max_rel(&rb.innovation_covariance, &rs.innovation_covariance) < 1e-14);
        assert!(max_rel(batch.state(), seq.state()) < 1e-12);
        assert!(max_rel(batch.covariance(), seq.covariance()) < 1e-12);
    }
    check::<PosVel>(SVector::<f64, 2>::new(1.7, -0.2));
    check::<Quad>(SVector::<f64, 2>::new(0.9, 0.3));
}

/// Table-driven: one long run per discretization, with two sensors.
#[test]
fn covariance_stays_symmetric_positive_definite_over_long_runs() {
    for method in [
        Discretization::FirstOrder,
        Discretization::SecondOrder,
        Discretization::VanLoan,
    ] {
        let mut f = filter().with_discretization(method);
        let mut g = Gauss::new(3);
        let r2 = SMatrix::<f64, 2, 2>::new(0.04, 0.0, 0.0, 1e-4);
        let r1 = SMatrix::<f64, 1, 1>::new(1e-6);
        for k in 0..100_000u32 {
            f.predict(
                0.01,
                &CvbInput {
                    a: (f64::from(k) * 1e-3).sin(),
                },
            )
            .unwrap();
            if k % 10 == 0 {
                let z = SVector::<f64, 2>::new(
                    f.state()[0] + 0.2 * g.normal(),
                    f.state()[1] + 0.01 * g.normal(),
                );
                f.update::<PosVel, 2>(&z, &r2, &()).unwrap();
            }
            if k % 97 == 0 {
                // A very precise position fix stresses the update.
                let z = SVector::<f64, 1>::new(f.state()[0] + 1e-3 * g.normal());
                f.update::<Pos, 1>(&z, &r1, &Offset::default()).unwrap();
            }
            let p = f.covariance();
            assert_eq!(p, &p.transpose(), "{method:?} step {k}");
            assert!(Cholesky::new(*p).is_some(), "{method:?} step {k}: {p}");
        }
        assert_eq!(f.counters().covariance_repairs, 0, "{method:?}");
        assert_eq!(f.counters().predictions, 100_000);
    }
}

#[test]
fn gate_rejects_ten_sigma_outlier_and_leaves_state_unchanged() {
    let mut f = filter().with_default_gate(Some(Gate::new(0.9973).unwrap()));
    let before = f.clone();
    let r = SMatrix::<f64, 1, 1>::new(0.25);
    let sigma = (f.covariance()[(0, 0)] + 0.25).sqrt();
    let z = SVector::<f64, 1>::new(f.state()[0] + 10.0 * sigma);
    let rep = f.update::<Pos, 1>(&z, &r, &Offset::default()).unwrap();
    assert!(!rep.accepted);
    assert!((rep.nis - 100.0).abs() < 1e-9);
    assert!(same_bits(&f, &before));
    assert_eq!(f.counters().updates_gated, 1);
    assert_eq!(f.counters().updates_accepted, 0);
    // A 1-sigma measurement passes.
    let z = SVector::<f64, 1>::new(f.state()[0] + sigma);
    assert!(
        f.update::<Pos, 1>(&z, &r, &Offset::default())
            .unwrap()
            .accepted
    );
}

/// A filter 10 sigma off its sensor (as after an accepted outlier) with
/// measurements that agree with each other: the third refusal in a row
/// releases the lock-out by inflating `P`, and the fourth sample passes
/// the gate on its own and is applied through the Kalman gain. Refusals
/// that disagree, or lie beyond the plausibility bound, never release.
#[test]
fn lockout_release_applies_the_measurement_after_consecutive_refusals() {
    use crate::lockout::LockoutRelease;
    let r = SMatrix::<f64, 1, 1>::new(0.25);
    let gate = Some(Gate::new(0.9999).unwrap());
    let rule = Some(LockoutRelease::default());
    let none = Offset::default();
    // The sensor's constant reading, 10 innovation sigmas off the estimate.
    let f0 = filter().with_default_gate(gate);
    let sigma = (f0.covariance()[(0, 0)] + 0.25).sqrt();
    let reading = SVector::<f64, 1>::new(f0.state()[0] + 10.0 * sigma);
    let fuse = |f: &mut Ekf<Cvb, 3>, z: SVector<f64, 1>| {
        let rep = f.update::<Pos, 1>(&z, &r, &none).unwrap();
        (rep.accepted, rep.nis)
    };
    let mut locked = f0.clone();
    let mut released = f0.clone().with_lockout_release(rule);
    for k in 0..3 {
        let before = released.clone();
        assert!(!fuse(&mut released, reading).0, "refusal {k}");
        assert!(!fuse(&mut locked, reading).0);
        // A refusal never moves the state; only the third inflates `P`.
        assert_eq!(released.state(), before.state());
        assert_eq!(released.covariance() == before.covariance(), k < 2);
    }
    assert_eq!(released.counters().updates_released, 1);
    assert_eq!(released.counters().updates_gated, 3);
    // Inflated along the position: `S` grew by about the offset squared.
    let s_after = released.covariance()[(0, 0)] + 0.25;
    assert!(s_after > 99.0 * sigma * sigma, "{s_after}");
    // The fourth passes the gate (no forcing) and is applied: the estimate
    // moves onto the reading, within the sensor noise.
    let (accepted, nis) = fuse(&mut released, reading);
    assert!(accepted && nis < 1.0, "NIS {nis}");
    assert_eq!(released.counters().updates_accepted, 1);
    assert!((released.state()[0] - reading[0]).abs() < 0.5);
    // A repeat is consistent now.
    assert!(fuse(&mut released, reading).0);
    // Without the rule the sensor stays locked out.
    assert!(!fuse(&mut locked, reading).0);
    assert_eq!(locked.counters().updates_released, 0);

    // Refusals that disagree (+10, -10, +10 sigma ...) never release.
    let mut f = f0.clone().with_lockout_release(rule);
    for k in 0..12 {
        let sign = if k % 2 == 0 { 10.0 } else { -10.0 };
        let z = SVector::<f64, 1>::new(f0.state()[0] + sign * sigma);
        assert!(!fuse(&mut f, z).0);
    }
    assert_eq!(f.counters().updates_released, 0);
    assert_eq!(f.covariance(), f0.covariance());

    // Agreeing refusals beyond the plausibility bound never release.
    let mut f = f0.clone().with_lockout_release(rule);
    f.set_lockout_bound(Pos::NAME, 5.0 * sigma).unwrap();
    for _ in 0..12 {
        assert!(!fuse(&mut f, reading).0);
    }
    assert_eq!(f.counters().updates_released, 0);
    assert_eq!(f.covariance(), f0.covariance());

    // Isolated outliers between good samples never release.
    let mut f = f0
        .clone()
        .with_lockout_release(Some(LockoutRelease::new(2, 0.999).unwrap()));
    for _ in 0..5 {
        let good = SVector::<f64, 1>::new(f.state()[0]);
        assert!(fuse(&mut f, good).0);
        let s = (f.covariance()[(0, 0)] + 0.25).sqrt();
        let z = SVector::<f64, 1>::new(f.state()[0] + 10.0 * s);
        assert!(!fuse(&mut f, z).0);
    }
    assert_eq!(f.counters().updates_released, 0);
}

/// Over 10,000 consistent draws the acceptance rate is the gate probability
/// within 4.5 binomial standard deviations.
#[test]
fn gate_acceptance_rate_matches_probability() {
    const DRAWS: u32 = 10_000;
    let mut g = Gauss::new(11);
    for prob in [0.9, 0.95, 0.99] {
        let gate = Some(Gate::new(prob).unwrap());
        let base = filter().with_default_gate(gate);
        let bound = 4.5 * (prob * (1.0 - prob) / f64::from(DRAWS)).sqrt();
        // M = 1.
        let r1 = SMatrix::<f64, 1, 1>::new(0.5);
        let s1 = base.covariance()[(0, 0)] + 0.5;
        let mut accepted = 0;
        for _ in 0..DRAWS {
            let z = SVector::<f64, 1>::new(base.state()[0] + s1.sqrt() * g.normal());
            accepted += u32::from(
                base.clone()
                    .update::<Pos, 1>(&z, &r1, &Offset::default())
                    .unwrap()
                    .accepted,
            );
        }
        let rate = f64::from(accepted) / f64::from(DRAWS);
        assert!((rate - prob).abs() < bound, "M=1 p={prob}: rate {rate}");
        // M = 2.
        let r2 = SMatrix::<f64, 2, 2>::new(0.3, 0.1, 0.1, 0.2);
        let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        let s2 = h * base.covariance() * h.transpose() + r2;
        let mut accepted = 0;
        for _ in 0..DRAWS {
            let z = h * base.state() + g.multivariate(&s2);
            accepted += u32::from(
                base.clone()
                    .update::<PosVel, 2>(&z, &r2, &())
                    .unwrap()
                    .accepted,
            );
        }
        let rate = f64::from(accepted) / f64::from(DRAWS);
        assert!((rate - prob).abs() < bound, "M=2 p={prob}: rate {rate}");
    }
}

/// A filter whose model is the truth's: mean NIS -> M, mean NEES -> N.
#[test]
fn nis_and_nees_of_a_consistent_filter_average_to_their_dimensions() {
    const UPDATES: u32 = 5_000;
    let dt = 0.01;
    let mut g = Gauss::new(2024);
    let mut f = filter().with_default_gate(None);
    let mut truth = f.state() + g.multivariate(&p0());
    let r = SMatrix::<f64, 2, 2>::new(0.25, 0.0, 0.0, 0.01);
    let (mut nis_sum, mut nees_sum) = (0.0, 0.0);
    let mut seq_nis_sum = 0.0;
    for k in 0..UPDATES * 10 {
        let u = CvbInput {
            a: (f64::from(k) * 2e-3).cos(),
        };
        let w = V3::new(
            0.0,
            (NOISE.q_a * dt).sqrt() * g.normal(),
            (NOISE.q_b * dt).sqrt() * g.normal(),
        );
        truth = Cvb::transition(&truth, &u, &(), dt) + w;
        f.predict(dt, &u).unwrap();
        if k % 10 == 9 {
            let z =
                SVector::<f64, 2>::new(truth[0] + 0.5 * g.normal(), truth[1] + 0.1 * g.normal());
            // The sequential NIS of a clone, for the same draw.
            let rs = f
                .clone()
                .update_sequential::<PosVel, 2>(&z, &SVector::<f64, 2>::new(0.25, 0.01), &())
                .unwrap();
            seq_nis_sum += rs.nis;
            nis_sum += f.update::<PosVel, 2>(&z, &r, &()).unwrap().nis;
            let e = f.state() - truth;
            nees_sum += (e.transpose() * f.covariance().try_inverse().unwrap() * e)[0];
        }
    }
    let n = f64::from(UPDATES);
    let nis = nis_sum / n;
    // chi2(2): mean 2, variance 4; innovations of a consistent filter are white.
    assert!((nis - 2.0).abs() < 4.5 * (4.0 / n).sqrt(), "mean NIS {nis}");
    assert!(rel(seq_nis_sum / n, nis) < 1e-9);
    // NEES samples are correlated in time: a looser bound.
    let nees = nees_sum / n;
    assert!((nees - 3.0).abs() < 0.3, "mean NEES {nees}");
}

#[test]
fn invalid_inputs_are_refused_and_leave_state_unchanged() {
    let mut f = filter();
    f.predict(0.01, &CvbInput { a: 0.3 }).unwrap();
    let before = f.clone();
    let r1 = SMatrix::<f64, 1, 1>::new(0.1);
    let z1 = SVector::<f64, 1>::new(1.0);
    let ok_aux = Offset::default();
    type Case = (
        &'static str,
        Box<dyn Fn(&mut Ekf<Cvb, 3>) -> Result<(), FilterError>>,
    );
    let cases: Vec<Case> = vec![
        (
            "dt NaN",
            Box::new(|f| f.predict(f64::NAN, &CvbInput { a: 0.0 })),
        ),
        (
            "dt inf",
            Box::new(|f| f.predict(f64::INFINITY, &CvbInput { a: 0.0 })),
        ),
        (
            "dt zero",
            Box::new(|f| f.predict(0.0, &CvbInput { a: 0.0 })),
        ),
        (
            "dt negative (time backwards)",
            Box::new(|f| f.predict(-0.01, &CvbInput { a: 0.0 })),
        ),
        (
            "input NaN",
            Box::new(|f| f.predict(0.01, &CvbInput { a: f64::NAN })),
        ),
        (
            "input -inf",
            Box::new(|f| {
                f.predict(
                    0.01,
                    &CvbInput {
                        a: f64::NEG_INFINITY,
                    },
                )
            }),
        ),
        (
            "z NaN",
            Box::new(move |f| {
                f.update::<Pos, 1>(&SVector::<f64, 1>::new(f64::NAN), &r1, &ok_aux)
                    .map(drop)
            }),
        ),
        (
            "R NaN",
            Box::new(move |f| {
                f.update::<Pos, 1>(&z1, &SMatrix::<f64, 1, 1>::new(f64::NAN), &ok_aux)
                    .map(drop)
            }),
        ),
        (
            "R negative",
            Box::new(move |f| {
                f.update::<Pos, 1>(&z1, &SMatrix::<f64, 1, 1>::new(-1.0), &ok_aux)
                    .map(drop)
            }),
        ),
        (
            "R asymmetric",
            Box::new(|f| {
                let r = SMatrix::<f64, 2, 2>::new(1.0, 0.5, 0.0, 1.0);
                f.update::<PosVel, 2>(&SVector::<f64, 2>::new(1.0, 0.0), &r, &())
                    .map(drop)
            }),
        ),
        (
            "aux NaN",
            Box::new(move |f| {
                f.update::<Pos, 1>(&z1, &r1, &Offset { offset: f64::NAN })
                    .map(drop)
            }),
        ),
        (
            "sequential R negative",
            Box::new(move |f| {
                f.update_sequential::<Pos, 1>(&z1, &SVector::<f64, 1>::new(-0.1), &ok_aux)
                    .map(drop)
            }),
        ),
        (
            "sequential z inf",
            Box::new(move |f| {
                f.update_sequential::<Pos, 1>(
                    &SVector::<f64, 1>::new(f64::INFINITY),
                    &SVector::<f64, 1>::new(0.1),
                    &ok_aux,
                )
                .map(drop)
            }),
        ),
    ];
    for (name, case) in &cases {
        assert!(case(&mut f).is_err(), "{name} accepted");
        assert!(same_bits(&f, &before), "{name} changed the state");
    }
    assert_eq!(f.counters().predictions_rejected, 6);
    assert_eq!(f.counters().updates_rejected, 7);
    assert_eq!(
        f.counters().updates_accepted + f.counters().updates_gated,
        0
    );
}

/// Results that overflow are refused after `P` was (partly) overwritten in
/// place: the prior must come back bit for bit, for every discretization
/// and for both updates.
#[test]
fn overflowing_results_are_refused_and_leave_state_unchanged() {
    // Valid setup (symmetric, finite, non-negative variances) whose
    // propagation and update overflow in off-diagonal entries.
    let p = M3::new(1.0, 1e200, 1e200, 1e200, 1e300, 0.0, 1e200, 0.0, 1e300);
    let x = V3::new(0.1, 0.2, 0.3);
    for method in [
        Discretization::FirstOrder,
        Discretization::SecondOrder,
        Discretization::VanLoan,
    ] {
        let mut f = Ekf::<Cvb, 3>::new(x, p, (), NOISE)
            .unwrap()
            .with_discretization(method)
            .with_default_gate(None);
        let before = f.clone();
        let err = f.predict(1e10, &CvbInput { a: 0.0 }).unwrap_err();
        assert_eq!(
            err,
            FilterError::NonFiniteResult {
                stage: "prediction"
            },
            "{method:?}"
        );
        assert!(same_bits(&f, &before), "{method:?}");
        assert_eq!(f.counters().predictions_rejected, 1);
    }
    let mut f = Ekf::<Cvb, 3>::new(x, p, (), NOISE)
        .unwrap()
        .with_default_gate(None);
    let before = f.clone();
    let z = SVector::<f64, 1>::new(0.5);
    let err = f
        .update::<Pos, 1>(&z, &SMatrix::<f64, 1, 1>::new(0.1), &Offset::default())
        .unwrap_err();
    assert_eq!(err, FilterError::NonFiniteResult { stage: "update" });
    assert!(same_bits(&f, &before));
    let err = f
        .update_sequential::<Pos, 1>(&z, &SVector::<f64, 1>::new(0.1), &Offset::default())
        .unwrap_err();
    assert_eq!(err, FilterError::NonFiniteResult { stage: "update" });
    assert!(same_bits(&f, &before));
    assert_eq!(f.counters().updates_rejected, 2);
}

#[test]
fn singular_innovation_covariance_is_an_error() {
    let mut p = p0();
    for i in 0..3 {
        p[(0, i)] = 0.0;
        p[(i, 0)] = 0.0;
    }
    let mut f = Ekf::<Cvb, 3>::new(V3::zeros(), p, (), NOISE).unwrap();
    let before = f.clone();
    let z = SVector::<f64, 1>::new(0.1);
    let err = f
        .update::<Pos, 1>(&z, &SMatrix::<f64, 1, 1>::zeros(), &Offset::default())
        .unwrap_err();
    assert_eq!(
        err,
        FilterError::InnovationCovarianceNotPositiveDefinite { sensor: "pos" }
    );
    assert!(same_bits(&f, &before));
    let err = f
        .update_sequential::<Pos, 1>(&z, &SVector::<f64, 1>::zeros(), &Offset::default())
        .unwrap_err();
    assert_eq!(
        err,
        FilterError::InnovationCovarianceNotPositiveDefinite { sensor: "pos" }
    );
}

#[test]
fn non_positive_variance_after_update_is_repaired_and_counted() {
    // A noise-free position fix drives the position variance to exactly 0.
    let mut f = filter().with_default_gate(None);
    let prior = f.covariance()[(0, 0)];
    let rep = f
        .update::<Pos, 1>(
            &SVector::<f64, 1>::new(1.2),
            &SMatrix::<f64, 1, 1>::zeros(),
            &Offset::default(),
        )
        .unwrap();
    assert_eq!(rep.repairs, 1);
    assert_eq!(f.counters().covariance_repairs, 1);
    assert_eq!(f.covariance()[(0, 0)], prior);
    assert_eq!(f.covariance()[(0, 1)], 0.0);
    assert!(Cholesky::new(*f.covariance()).is_some());
}

#[test]
fn setup_is_validated() {
    let bad: [(V3, M3, CvbNoise); 5] = [
        (V3::new(f64::NAN, 0.0, 0.0), p0(), NOISE),
        (
            V3::zeros(),
            M3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
            NOISE,
        ),
        (V3::zeros(), -p0(), NOISE),
        (V3::zeros(), p0() * f64::INFINITY, NOISE),
        (
            V3::zeros(),
            p0(),
            CvbNoise {
                q_a: -1.0,
                q_b: 0.0,
            },
        ),
    ];
    for (x, p, q) in bad {
        assert!(matches!(
            Ekf::<Cvb, 3>::new(x, p, (), q),
            Err(SetupError::Invalid { .. })
        ));
    }
}

/// `F` of the toy is nilpotent, so `exp(F dt) = I + F dt + (F dt)^2 / 2` and
/// `Qd` has the closed form of the module docs of `testmodels`.
#[test]
fn van_loan_matches_closed_forms() {
    let (qa, qb) = (0.3, 0.07);
    let qc = M3::from_diagonal(&V3::new(0.0, qa, qb));
    for dt in [1e-3, 0.1, 1.0, 5.0] {
        let (phi, qd) = van_loan(&Cvb::f(), &qc, dt);
        let fdt = Cvb::f() * dt;
        let exact_phi = M3::identity() + fdt + fdt * fdt * 0.5;
        assert!(max_rel(&phi, &exact_phi) < 1e-13, "dt {dt}");
        let (d2, d3, d4, d5) = (dt * dt, dt.powi(3), dt.powi(4), dt.powi(5));
        let exact_qd = M3::new(d3 / 3.0, d2 / 2.0, 0.0, d2 / 2.0, dt, 0.0, 0.0, 0.0, 0.0) * qa
            + M3::new(
                d5 / 20.0,
                d4 / 8.0,
                -d3 / 6.0,
                d4 / 8.0,
                d3 / 3.0,
                -d2 / 2.0,
                -d3 / 6.0,
                -d2 / 2.0,
                dt,
            ) * qb;
        let err = (qd - exact_qd).amax() / exact_qd.amax();
        assert!(err < 1e-13, "dt {dt}: {err}");
        // The same Phi from the second-order series (exact here, F^3 = 0).
        let (phi2, _) = second_order(&Cvb::f(), &qc, dt);
        assert!(max_rel(&phi2, &exact_phi) < 1e-15);
    }
    // Oscillator: Phi is a rotation-like matrix, Qd matches fine steps.
    let w = 2.0;
    let qc2 = SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, 0.5);
    for dt in [0.01, 0.7, 3.0, 40.0] {
        let (phi, qd) = van_loan(&Osc::f(w), &qc2, dt);
        let (c, s) = ((w * dt).cos(), (w * dt).sin());
        let exact = SMatrix::<f64, 2, 2>::new(c, s / w, -w * s, c);
        assert!(max_rel(&phi, &exact) < 1e-11, "dt {dt}: {phi} vs {exact}");
        // Qd = int_0^dt e^{Fs} Qc e^{Fs}^T ds, closed form for the oscillator.
        let q = 0.5;
        let t = dt;
        let q11 = q / (w * w) * (t / 2.0 - (2.0 * w * t).sin() / (4.0 * w));
        let q12 = q / (2.0 * w * w) * (w * t).sin().powi(2);
        let q22 = q * (t / 2.0 + (2.0 * w * t).sin() / (4.0 * w));
        let exact_qd = SMatrix::<f64, 2, 2>::new(q11, q12, q12, q22);
        assert!(
            (qd - exact_qd).amax() < 1e-11 * (1.0 + exact_qd.amax()),
            "dt {dt}: {qd} vs {exact_qd}"
        );
    }
}

#[test]
fn discretizations_propagate_state_consistently() {
    // Linear dynamics: Heun gives exactly the second-order Phi times x; RK4
    // is within O((w dt)^5) of the exact rotation.
    let w = 1.5;
    let dt = 0.2;
    let x0 = SVector::<f64, 2>::new(0.4, -0.3);
    let p0 = SMatrix::<f64, 2, 2>::identity() * 0.1;
    let params = OscParams { w };
    let mk = |d| {
        Ekf::<Osc, 2>::new(x0, p0, params, OscNoise { q: 0.01 })
            .unwrap()
            .with_discretization(d)
    };
    let mut second = mk(Discretization::SecondOrder);
    second.predict(dt, &()).unwrap();
    let (phi2, qd2) = second_order(
        &Osc::f(w),
        &SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, 0.01),
        dt,
    );
    assert!(max_rel(second.state(), &(phi2 * x0)) < 1e-15);
    assert!(max_rel(second.covariance(), &(phi2 * p0 * phi2.transpose() + qd2)) < 1e-15);
    let mut vl = mk(Discretization::VanLoan);
    vl.predict(dt, &()).unwrap();
    let (c, s) = ((w * dt).cos(), (w * dt).sin());
    let exact = SMatrix::<f64, 2, 2>::new(c, s / w, -w * s, c) * x0;
    assert!((vl.state() - exact).amax() < (w * dt).powi(5) / 60.0 * x0.norm());
    assert!((vl.state() - exact).amax() > 1e-12, "RK4 is not exact");
    // First order equals the model's own sparse path.
    let mut first = mk(Discretization::FirstOrder);
    first.predict(dt, &()).unwrap();
    let mut p = p0;
    Osc::propagate_covariance(&mut p, &x0, &(), &params, &OscNoise { q: 0.01 }, dt);
    assert_eq!(first.covariance(), &p);
    assert_eq!(first.state(), &Osc::transition(&x0, &(), &params, dt));
}

#[test]
fn discrete_models_use_their_own_transition_matrix() {
    let x0 = SVector::<f64, 2>::new(1.0, 2.0);
    let p0 = SMatrix::<f64, 2, 2>::new(1.0, 0.1, 0.1, 0.5);
    let mk = |d| {
        Ekf::<Dcv, 2>::new(x0, p0, (), DcvNoise { var_v: 0.2 })
            .unwrap()
            .with_discretization(d)
    };
    let mut a = mk(Discretization::FirstOrder);
    a.predict(2.0, &()).unwrap();
    for d in [Discretization::SecondOrder, Discretization::VanLoan] {
        let mut b = mk(d);
        b.predict(2.0, &()).unwrap();
        assert_eq!(a.state(), b.state());
        assert_eq!(a.covariance(), b.covariance());
    }
    assert_eq!(a.state(), &SVector::<f64, 2>::new(5.0, 2.0));
    assert!((a.covariance()[(1, 1)] - 0.7).abs() < 1e-15);
}

#[test]
fn angle_innovations_are_wrapped() {
    let x0 = SVector::<f64, 2>::new(3.1, 0.0);
    let mut f = Ekf::<Osc, 2>::new(
        x0,
        SMatrix::identity() * 0.01,
        OscParams { w: 1.0 },
        OscNoise { q: 0.0 },
    )
    .unwrap();
    let z = SVector::<f64, 1>::new(-3.1);
    let r = SMatrix::<f64, 1, 1>::new(0.01);
    let rep = f.update::<Angle, 1>(&z, &r, &()).unwrap();
    let want = 2.0 * core::f64::consts::PI - 6.2;
    assert!(
        (rep.innovation[0] - want).abs() < 1e-12,
        "{}",
        rep.innovation[0]
    );
    assert!(rep.accepted);
    assert!((f.state()[0] - (3.1 + want / 2.0)).abs() < 1e-12);
    let mut f2 = Ekf::<Osc, 2>::new(
        x0,
        SMatrix::identity() * 0.01,
        OscParams { w: 1.0 },
        OscNoise { q: 0.0 },
    )
    .unwrap();
    let rs = f2
        .update_sequential::<Angle, 1>(&z, &SVector::<f64, 1>::new(0.01), &())
        .unwrap();
    assert!((rs.innovation[0] - want).abs() < 1e-12);
    assert!(max_rel(f.state(), f2.state()) < 1e-14);
}

#[test]
fn per_sensor_gates_override_the_default() {
    let mut f = filter();
    assert_eq!(f.sensor_gate::<Pos, 1>(), Some(Gate::default()));
    f.set_sensor_gate::<Pos, 1>(None).unwrap();
    let tight = Gate::new(0.5).unwrap();
    f.set_sensor_gate::<PosVel, 2>(Some(tight)).unwrap();
    assert_eq!(f.sensor_gate::<Pos, 1>(), None);
    assert_eq!(f.sensor_gate::<PosVel, 2>(), Some(tight));
    assert_eq!(f.sensor_gate::<Quad, 2>(), Some(Gate::default()));
    // Ungated: a 100-sigma fix is applied.
    let z = SVector::<f64, 1>::new(f.state()[0] + 200.0);
    let rep = f
        .update::<Pos, 1>(&z, &SMatrix::<f64, 1, 1>::new(1.0), &Offset::default())
        .unwrap();
    assert!(rep.accepted && rep.threshold.is_none());
    // Re-setting an existing entry does not use capacity.
    for _ in 0..100 {
        f.set_sensor_gate::<Pos, 1>(Some(tight)).unwrap();
    }
    assert_eq!(f.sensor_gate::<Pos, 1>(), Some(tight));
}

/// A prediction over a model's structure saves, checks and restores only
/// the entries it changes when `P` is known clean; the outcome (state,
/// every bit of `P`, errors, repairs, counters) equals the whole-matrix
/// path's, which runs when `P` is not known clean. Cases: a zero variance
/// outside the changed rows at the start (repaired by the first,
/// whole-matrix step), ordinary steps, a changed row zeroed (its variance
/// repaired), an overflowing diagonal entry (repaired), an overflowing
/// off-diagonal block (refused, `P` restored), and a `Qd` entry outside the
/// changed rows overflowing on every step (repaired).
#[test]
fn structured_prediction_equals_the_whole_check() {
    let input = |f00: f64, f01: f64, f22: f64, f23: f64| RowsInput { f00, f01, f22, f23 };
    let dt = 0.1;
    let steps = [
        input(-0.1, 0.5, 0.2, -0.3),
        input(0.3, -0.2, -0.5, 0.1),
        // Row 0 of Phi = I + F dt becomes zero: P[0, 0] = 0, repaired.
        input(-1.0 / dt, 0.0, 0.1, 0.2),
        input(0.05, 1.0, 0.0, 0.4),
        // Overflows in a diagonal entry of a changed row: repaired.
        input(1e300, 1e300, 0.0, 0.0),
        // Overflows in the off-diagonal block of the changed rows: refused.
        input(1e300, 1e300, 1e300, 0.0),
        input(0.2, 0.1, -0.1, 0.3),
    ];
    let start = |p11: f64, q1: f64| {
        let p0 = SMatrix::<f64, 4, 4>::from_row_slice(&[
            2.0, 0.3, 0.1, 0.0, //
            0.3, p11, 0.0, 0.0, //
            0.1, 0.0, 0.5, 0.0, //
            0.0, 0.0, 0.0, 0.0, // d: zero variance at the start
        ]);
        let x0 = SVector::<f64, 4>::new(0.1, -0.2, 0.3, 0.4);
        Ekf::<Rows, 4>::new(x0, p0, (), RowsNoise { q1, q2: 1e-3 }).unwrap()
    };
    // Second case: the Qd entry (1, 1), outside the changed rows,
    // overflows on every step (its variance repaired each time). The
    // counts are what both paths must arrive at: refusals, repairs.
    for (p11, q1, rejected, repairs) in [(1.0, 1e-2, 1, 2), (0.95 * f64::MAX, f64::MAX, 2, 6)] {
        let (mut structured, mut whole) = (start(p11, q1), start(p11, q1));
        for (k, u) in steps.iter().enumerate() {
            let before = structured.covariance().map(f64::to_bits);
            whole.clean = false;
            let a = structured.predict(dt, u);
            let b = whole.predict(dt, u);
            assert_eq!(a, b, "step {k}, q1 {q1:e}");
            assert_eq!(
                structured.covariance().map(f64::to_bits),
                whole.covariance().map(f64::to_bits),
                "step {k}, q1 {q1:e}"
            );
            assert_eq!(structured.state(), whole.state());
            assert_eq!(structured.counters(), whole.counters());
            if a.is_err() {
                assert_eq!(
                    structured.covariance().map(f64::to_bits),
                    before,
                    "restored"
                );
            }
        }
        let counters = structured.counters();
        assert_eq!(
            (counters.predictions_rejected, counters.covariance_repairs),
            (rejected, repairs),
            "q1 {q1:e}"
        );
    }
}
