//! The smoother against the batch least-squares solution of a linear-Gaussian
//! run, the error-state form against the plain one, rollbacks against a
//! straight run, and its consistency over seeds.

use nalgebra::{DMatrix, DVector, Matrix1, SMatrix, SVector, Vector1, Vector3};

use super::{smooth, EpochFile, Recorder, SmoothedEpoch};
use crate::ekf::{Ekf, Propagate};
use crate::error_state::ErrorStateFilter;
use crate::model::Model;
use crate::testmodels::{Cvb, CvbInput, CvbNoise, Gauss, Offset, Pos, Toy};

const DT: f64 = 0.1;
const NOISE: CvbNoise = CvbNoise {
    q_a: 0.04,
    q_b: 1e-4,
};
const R: f64 = 0.25;
const OFFSET: f64 = 0.5;

fn prior() -> (Vector3<f64>, SMatrix<f64, 3, 3>) {
    (
        Vector3::new(0.0, 1.0, 0.05),
        SMatrix::from_diagonal(&Vector3::new(4.0, 1.0, 0.01)),
    )
}

fn input(i: usize) -> CvbInput {
    CvbInput {
        a: (0.3 * i as f64).sin(),
    }
}

fn phi() -> SMatrix<f64, 3, 3> {
    SMatrix::identity() + Cvb::f() * DT
}

/// A simulated run: truth at every step and position fixes every `every` steps.
struct Run {
    truth: Vec<Vector3<f64>>,
    fixes: Vec<Option<f64>>,
}

fn simulate(seed: u64, steps: usize, every: usize) -> Run {
    let mut g = Gauss::new(seed);
    let (m, p0) = prior();
    let mut x = m + g.multivariate(&p0);
    let mut truth = vec![x];
    let mut fixes = vec![None];
    for i in 0..steps {
        let w = Vector3::new(
            0.0,
            (NOISE.q_a * DT).sqrt() * g.normal(),
            (NOISE.q_b * DT).sqrt() * g.normal(),
        );
        x = phi() * x + Vector3::new(0.0, input(i).a * DT, 0.0) + w;
        truth.push(x);
        let k = i + 1;
        fixes.push((k % every == 0).then(|| x[0] + OFFSET + R.sqrt() * g.normal()));
    }
    Run { truth, fixes }
}

type Smoothed = Vec<SmoothedEpoch<3, 3>>;

fn backward(rec: &mut Recorder<3, 3>) -> Smoothed {
    rec.finish().unwrap();
    let store = rec.store();
    let mut out = Vec::new();
    smooth(&mut store.borrow_mut(), |e| {
        out.push(*e);
        Ok(())
    })
    .unwrap();
    out.reverse();
    out
}

/// Forward EKF over steps `from..to` of `run`, recording; marks every step
/// when `mark_all`, and always the last one.
fn forward(
    run: &Run,
    ekf: &mut Ekf<Cvb, 3>,
    rec: &mut Recorder<3, 3>,
    from: usize,
    to: usize,
    mark_all: bool,
) {
    for i in from..to {
        let u = input(i);
        let f = Cvb::jacobian(ekf.state(), &u, &(), DT);
        rec.propagated::<Cvb>(&f, DT);
        ekf.predict(DT, &u).unwrap();
        let t = (i + 1) as f64 * DT;
        if let Some(z) = run.fixes[i + 1] {
            rec.updating(ekf.covariance(), *ekf.state());
            let before = *ekf.state();
            ekf.update::<Pos, 1>(
                &Vector1::new(z),
                &Matrix1::new(R),
                &Offset { offset: OFFSET },
            )
            .unwrap();
            rec.updated(&(before - ekf.state()), ekf.covariance(), *ekf.state());
        } else if mark_all || i + 1 == run.truth.len() - 1 {
            rec.mark(t, ekf.covariance(), *ekf.state());
        }
    }
}

fn start(seed_file: Option<&std::path::Path>) -> (Ekf<Cvb, 3>, Recorder<3, 3>) {
    let (m, p0) = prior();
    let ekf = Ekf::<Cvb, 3>::new(m, p0, (), NOISE)
        .unwrap()
        .with_default_gate(None);
    let rec = Recorder::new(
        EpochFile::create(seed_file).unwrap(),
        0.0,
        ekf.covariance(),
        *ekf.state(),
    );
    (ekf, rec)
}

fn smoothed_ekf(run: &Run, mark_all: bool) -> Smoothed {
    let (mut ekf, mut rec) = start(None);
    forward(run, &mut ekf, &mut rec, 0, run.truth.len() - 1, mark_all);
    backward(&mut rec)
}

/// The smoothed estimate: the forward snapshot with the smoothed error removed.
fn estimate(e: &SmoothedEpoch<3, 3>) -> Vector3<f64> {
    e.snapshot - e.error
}

/// Batch least squares over the initial state and every process-noise draw:
/// `x_i = A_i theta + c_i`; returns each step's mean and covariance.
fn batch(run: &Run) -> Vec<(Vector3<f64>, SMatrix<f64, 3, 3>)> {
    let steps = run.truth.len() - 1;
    let dim = 3 + 2 * steps;
    let (m, p0) = prior();
    let mut info = DMatrix::<f64>::zeros(dim, dim);
    let mut rhs = DVector::<f64>::zeros(dim);
    let p0_inv = p0.try_inverse().unwrap();
    for r in 0..3 {
        for c in 0..3 {
            info[(r, c)] = p0_inv[(r, c)];
        }
    }
    let prior_rhs = p0_inv * m;
    for r in 0..3 {
        rhs[r] = prior_rhs[r];
    }
    for i in 0..steps {
        info[(3 + 2 * i, 3 + 2 * i)] = 1.0 / (NOISE.q_a * DT);
        info[(4 + 2 * i, 4 + 2 * i)] = 1.0 / (NOISE.q_b * DT);
    }
    let mut a = DMatrix::<f64>::zeros(3, dim);
    for r in 0..3 {
        a[(r, r)] = 1.0;
    }
    let mut c = Vector3::zeros();
    let mut maps = vec![(a.clone(), c)];
    let phi = DMatrix::from_column_slice(3, 3, phi().as_slice());
    for i in 0..steps {
        a = &phi * &a;
        a[(1, 3 + 2 * i)] += 1.0;
        a[(2, 4 + 2 * i)] += 1.0;
        c = self::phi() * c + Vector3::new(0.0, input(i).a * DT, 0.0);
        if let Some(z) = run.fixes[i + 1] {
            let h = a.row(0).transpose();
            info += &h * h.transpose() / R;
            rhs += &h * ((z - c[0] - OFFSET) / R);
        }
        maps.push((a.clone(), c));
    }
    let cov = info.clone().try_inverse().unwrap();
    let theta = &cov * rhs;
    maps.iter()
        .map(|(a, c)| {
            let mean = a * &theta;
            let p = a * &cov * a.transpose();
            (
                Vector3::new(mean[0], mean[1], mean[2]) + c,
                SMatrix::<f64, 3, 3>::from_fn(|r, k| p[(r, k)]),
            )
        })
        .collect()
}

fn step_of(t: f64) -> usize {
    (t / DT).round() as usize
}

#[test]
fn linear_gaussian_smoother_equals_batch_least_squares() {
    // Cases: (seed, steps, fix every, an epoch at every step). With an
    // epoch at every step, the output epochs between fixes are derived from
    // the next fix.
    for &(seed, steps, every, mark_all) in &[
        (1, 60, 4, false),
        (2, 60, 4, true),
        (3, 45, 1, false),
        (4, 80, 9, false),
        (5, 80, 9, true),
        (6, 70, 25, true),
    ] {
        let run = simulate(seed, steps, every);
        let exact = batch(&run);
        let smoothed = smoothed_ekf(&run, mark_all);
        assert!(smoothed.len() >= steps / every);
        for e in &smoothed {
            let (mean, cov) = &exact[step_of(e.time)];
            let x = estimate(e);
            for r in 0..3 {
                let scale = cov[(r, r)].sqrt();
                assert!(
                    (x[r] - mean[r]).abs() <= 1e-9 * scale.max(1.0),
                    "seed {seed} t {} state {r}: {} vs {}",
                    e.time,
                    x[r],
                    mean[r]
                );
                for k in 0..3 {
                    assert!(
                        (e.covariance[(r, k)] - cov[(r, k)]).abs() <= 1e-9 * cov.norm(),
                        "seed {seed} t {} cov ({r},{k})",
                        e.time
                    );
                }
            }
        }
    }
}

#[test]
fn error_state_smoother_equals_the_plain_one() {
    let run = simulate(11, 70, 5);
    let plain = smoothed_ekf(&run, false);
    let (m, p0) = prior();
    let ekf = Ekf::<Cvb, 3>::new(SVector::zeros(), p0, (), NOISE)
        .unwrap()
        .with_default_gate(None);
    let mut filter = ErrorStateFilter::new(
        ekf,
        Toy {
            p: m[0],
            v: m[1],
            b: m[2],
        },
    );
    // The filter records itself; snapshots are taken beside it, per epoch.
    filter
        .start_recording(EpochFile::create(None).unwrap(), 0.0)
        .unwrap();
    let mut snapshots = vec![Vector3::new(m[0], m[1], m[2])];
    let steps = run.truth.len() - 1;
    for i in 0..steps {
        filter.propagate(DT, &input(i)).unwrap();
        let t = (i + 1) as f64 * DT;
        if let Some(z) = run.fixes[i + 1] {
            // Residual: INS value minus sensor value.
            let residual = filter.nominal().p + OFFSET - z;
            filter
                .update::<Pos, 1>(
                    &Vector1::new(residual),
                    &Matrix1::new(R),
                    &Offset { offset: 0.0 },
                )
                .unwrap();
        } else if i + 1 == steps {
            filter.mark_epoch(t);
        } else {
            continue;
        }
        let n = filter.nominal();
        snapshots.push(Vector3::new(n.p, n.v, n.b));
    }
    let store = filter.finish_recording().unwrap().unwrap();
    let mut error_state = Vec::new();
    smooth(&mut store.borrow_mut(), |e| {
        error_state.push((e.time, e.error, e.covariance));
        Ok(())
    })
    .unwrap();
    error_state.reverse();
    assert_eq!(error_state.len(), plain.len());
    assert_eq!(snapshots.len(), plain.len());
    for (((t, error, cov), snapshot), b) in error_state.iter().zip(&snapshots).zip(&plain) {
        assert!((t - b.time).abs() < 1e-9);
        let (xa, xb) = (snapshot - error, estimate(b));
        assert!((xa - xb).norm() <= 1e-9, "t {t}: {xa} vs {xb}");
        assert!((cov - b.covariance).norm() <= 1e-9 * b.covariance.norm());
    }
}

#[test]
fn a_rolled_back_span_replaces_its_records() {
    let run = simulate(21, 60, 3);
    let straight = smoothed_ekf(&run, false);
    let (mut ekf, mut rec) = start(None);
    forward(&run, &mut ekf, &mut rec, 0, 20, false);
    // Checkpoint, run ahead (writing records), then resume from the checkpoint.
    let (mut ekf_back, mut rec_back) = (ekf.clone(), rec.clone());
    forward(&run, &mut ekf, &mut rec, 20, 45, false);
    drop((ekf, rec));
    forward(&run, &mut ekf_back, &mut rec_back, 20, 60, false);
    let replayed = backward(&mut rec_back);
    assert_eq!(replayed, straight);
}

#[test]
fn smoothed_estimates_are_consistent_and_better_than_forward() {
    // 200 seeds; at three epochs the NEES averaged over seeds must lie in the
    // two-sided 95 % band of chi2(3 * 200) / 200, and the smoothed variance
    // must not exceed the forward one.
    let seeds = 200;
    let probe = [0usize, 7, 14];
    let mut nees = [0.0; 3];
    let mut squared = [[0.0; 2]; 3]; // forward, smoothed position error^2
    for seed in 0..seeds {
        let run = simulate(1000 + seed, 60, 4);
        let smoothed = smoothed_ekf(&run, false);
        for (slot, &k) in probe.iter().enumerate() {
            let e = &smoothed[k];
            let truth = run.truth[step_of(e.time)];
            let err = estimate(e) - truth;
            let info = e.covariance.try_inverse().unwrap();
            nees[slot] += (err.transpose() * info * err)[0] / seeds as f64;
            squared[slot][0] += (e.snapshot[0] - truth[0]).powi(2) / seeds as f64;
            squared[slot][1] += err[0].powi(2) / seeds as f64;
            for r in 0..3 {
                assert!(e.covariance[(r, r)] <= e.filtered[(r, r)] * (1.0 + 1e-12));
            }
        }
    }
    for (slot, value) in nees.iter().enumerate() {
        assert!(
            (2.67..=3.35).contains(value),
            "epoch {}: NEES {value}",
            probe[slot]
        );
    }
    // Early epochs gain from every later fix.
    assert!(squared[0][1] < 0.5 * squared[0][0], "{squared:?}");
}
