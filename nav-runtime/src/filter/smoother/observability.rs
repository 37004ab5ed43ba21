//! How much a recorded run taught each state, and which combinations of
//! states it left undetermined (`docs/observability.md`).
//!
//! Every epoch with updates carries the information
//! `I_k = (P_k+)^-1 - (P_k-)^-1` (for a linear update, `H^T R^-1 H`), and the
//! recorded transitions map it back to the start of the run:
//!
//! ```text
//! W = sum_k Phi(k, 0)^T I_k Phi(k, 0)
//! ```
//!
//! the observability Gramian of the linearized system along the estimated
//! trajectory, computed backwards over the [`EpochFile`] with
//! `L_k = I_k + Phi_{k+1}^T L_{k+1} Phi_{k+1}` (no matrix is kept per epoch).
//! In coordinates scaled by the prior sigmas (`x_i / sigma_i`) the posterior
//! covariance of the run's start, with the run's information and no process
//! noise, is `(I + W~)^-1`: a state was learned by `1 - sqrt([(I + W~)^-1]_ii)`
//! (0: the log told nothing, 1: exactly), and the eigenvectors of `W~` with
//! the smallest eigenvalues are the weakest directions, each learned by
//! `1 - 1/sqrt(1 + lambda)`.
//!
//! The analysis is local: it holds along the estimated trajectory, for the
//! linearization the filter used, and says nothing of errors that a
//! nonlinear filter could still make. Process noise is left out on purpose:
//! it measures what the measurements determine, not how fast the states
//! drift afterwards.

use nalgebra::{DMatrix, SMatrix, SVector, SymmetricEigen};

use super::{Epoch, EpochFile, SensorInformation, SmootherError};

/// A combination of states a run left (nearly) undetermined.
#[derive(Clone, Debug, PartialEq)]
pub struct Direction<const N: usize> {
    /// How much the run learned along it, in `[0, 1]`.
    pub learned: f64,
    /// Its coefficients, per state, in units of each state's prior sigma,
    /// scaled so that the largest is 1 in magnitude (0 for the states left
    /// out of the analysis).
    pub coefficients: [f64; N],
}

/// What a run taught ([`observability`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Observability<const N: usize> {
    /// Per state: how much the run learned of it, in `[0, 1]`; NaN for a
    /// state left out (its prior sigma at most `floor`: known from the
    /// start).
    pub learned: [f64; N],
    /// The weakest directions, weakest first.
    pub weakest: Vec<Direction<N>>,
    /// Epochs whose information could not be formed (a covariance without
    /// a Cholesky factor); skipped.
    pub skipped_epochs: usize,
    /// Per sensor (in the order first seen), how much its updates alone
    /// would have taught each state, as [`Observability::learned`]; empty
    /// without each sensor's information (`sensors` of [`observability`]).
    pub by_sensor: Vec<(&'static str, [f64; N])>,
}

/// Per sensor, how much its updates alone taught each state, in `[0, 1]`
/// (`1 - sqrt([(I + W~_s)^-1]_ii)` with `W~_s` that sensor's information in
/// coordinates scaled by `prior_sigma`); NaN for the states whose prior
/// sigma is at most `floor`, as in [`observability`]. A sensor's figures
/// are not shares: two sensors that each pin a state alone both read near 1.
fn learned_by_sensor<const N: usize>(
    information: &SensorInformation<N>,
    prior_sigma: &[f64; N],
    floor: f64,
) -> Vec<(&'static str, [f64; N])> {
    let used: [bool; N] = core::array::from_fn(|i| prior_sigma[i] > floor);
    information
        .sensors()
        .map(|(name, w)| {
            let scaled = SMatrix::<f64, N, N>::from_fn(|r, c| {
                if used[r] && used[c] {
                    prior_sigma[r] * w[(r, c)] * prior_sigma[c]
                } else {
                    0.0
                }
            });
            (
                name,
                learned_from(&((scaled + scaled.transpose()) * 0.5), &used),
            )
        })
        .collect()
}

/// Per used state, `1 - sqrt([(I + w)^-1]_ii)` for the scaled information
/// `w`; NaN for a state left out.
fn learned_from<const N: usize>(w: &SMatrix<f64, N, N>, used: &[bool; N]) -> [f64; N] {
    let posterior = (SMatrix::<f64, N, N>::identity() + w)
        .try_inverse()
        .unwrap_or_else(SMatrix::identity);
    core::array::from_fn(|i| {
        if used[i] {
            (1.0 - posterior[(i, i)].max(0.0).sqrt()).clamp(0.0, 1.0)
        } else {
            f64::NAN
        }
    })
}

/// The observability of the run recorded in `file`, whose states started
/// with the sigmas `prior_sigma` (in the states' units): per state, and the
/// `directions` weakest directions; with `sensors` (each sensor's
/// information, kept beside the recording), per sensor too. States whose
/// prior sigma is at most `floor` are known from the start and left out.
///
/// # Errors
/// [`SmootherError::Io`] on a failed read; [`SmootherError::NonFinite`] if
/// the information matrix is not finite.
pub fn observability<const N: usize, const S: usize>(
    file: &mut EpochFile<N, S>,
    prior_sigma: &[f64; N],
    floor: f64,
    directions: usize,
    sensors: Option<&SensorInformation<N>>,
) -> Result<Observability<N>, SmootherError> {
    let used: [bool; N] = core::array::from_fn(|i| prior_sigma[i] > floor);
    let scale: SVector<f64, N> =
        SVector::from_fn(|i, _| if used[i] { prior_sigma[i] } else { 0.0 });
    let inverse_scale: SVector<f64, N> =
        SVector::from_fn(|i, _| if used[i] { 1.0 / prior_sigma[i] } else { 0.0 });
    // `L` in scaled coordinates, carried from the latest epoch backwards.
    let mut information = Box::new(SMatrix::<f64, N, N>::zeros());
    let mut skipped = 0usize;
    file.read_back(|epoch: &Epoch<N, S>| {
        if epoch.predicted != epoch.filtered {
            match epoch_information(epoch, &scale, &used) {
                Some(i) => *information += i,
                None => skipped += 1,
            }
        }
        // Back through this epoch's transition (from the previous epoch):
        // Phi~ = D^-1 Phi D.
        let phi = SMatrix::<f64, N, N>::from_fn(|r, c| {
            inverse_scale[r] * epoch.transition[(r, c)] * scale[c]
        });
        *information = phi.transpose() * *information * phi;
        Ok(())
    })?;
    if information.iter().any(|v| !v.is_finite()) {
        return Err(SmootherError::NonFinite { time: f64::NAN });
    }
    let w = (*information + information.transpose()) * 0.5;
    let learned = learned_from(&w, &used);
    // Dynamic-size for the decomposition (a const-generic size has no
    // eigen solver); once per run.
    let eigen = SymmetricEigen::new(DMatrix::from_fn(N, N, |r, c| w[(r, c)]));
    let mut order: Vec<usize> = (0..N)
        .filter(|&k| {
            // An eigenvector of the left-out states only is no direction.
            (0..N).any(|i| used[i] && eigen.eigenvectors[(i, k)].abs() > 1e-9)
        })
        .collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let weakest = order
        .into_iter()
        .take(directions)
        .map(|k| {
            let lambda = eigen.eigenvalues[k].max(0.0);
            let v = eigen.eigenvectors.column(k);
            let largest = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            // Sign: the largest coefficient positive.
            let sign = v
                .iter()
                .find(|x| x.abs() == largest)
                .map_or(1.0, |x| x.signum());
            Direction {
                learned: 1.0 - 1.0 / (1.0 + lambda).sqrt(),
                coefficients: core::array::from_fn(|i| {
                    if used[i] && largest > 0.0 {
                        sign * v[i] / largest
                    } else {
                        0.0
                    }
                }),
            }
        })
        .collect();
    Ok(Observability {
        learned,
        weakest,
        skipped_epochs: skipped,
        by_sensor: sensors.map_or_else(Vec::new, |s| learned_by_sensor(s, prior_sigma, floor)),
    })
}

/// `I_k` of an epoch in scaled coordinates, over the used states:
/// `(P~+)^-1 - (P~-)^-1`; `None` without Cholesky factors.
fn epoch_information<const N: usize, const S: usize>(
    epoch: &Epoch<N, S>,
    scale: &SVector<f64, N>,
    used: &[bool; N],
) -> Option<SMatrix<f64, N, N>> {
    let scaled = |p: &SMatrix<f64, N, N>| {
        SMatrix::<f64, N, N>::from_fn(|r, c| {
            if used[r] && used[c] {
                p[(r, c)] / (scale[r] * scale[c])
            } else if r == c {
                // Left-out states: unit variance, no information.
                1.0
            } else {
                0.0
            }
        })
    };
    let before = scaled(&epoch.predicted).cholesky()?.inverse();
    let after = scaled(&epoch.filtered).cholesky()?.inverse();
    let i = after - before;
    Some((i + i.transpose()) * 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ekf::Ekf;
    use crate::ekf::Propagate;
    use crate::error_state::ErrorStateFilter;
    use crate::testmodels::{Cvb, CvbInput, CvbNoise, Offset, Pos, PosVel, Toy};

    /// Prior sigmas of the position, velocity and bias.
    const SIGMA: [f64; 3] = [2.0, 0.5, 0.1];

    /// The observability of a run of the constant-velocity-and-bias filter
    /// (no process noise) that `run` drives, recorded from the start.
    fn recorded(
        directions: usize,
        run: impl FnOnce(&mut ErrorStateFilter<Cvb, Toy, 3>),
    ) -> Observability<3> {
        let p0 = SMatrix::<f64, 3, 3>::from_diagonal(
            &SVector::from(SIGMA).component_mul(&SVector::from(SIGMA)),
        );
        let noise = CvbNoise { q_a: 0.0, q_b: 0.0 };
        let ekf = Ekf::<Cvb, 3>::new(SVector::zeros(), p0, (), noise)
            .unwrap()
            .with_default_gate(None);
        let toy = Toy {
            p: 0.0,
            v: 0.0,
            b: 0.0,
        };
        let mut filter = ErrorStateFilter::new(ekf, toy);
        filter
            .start_recording(EpochFile::<3, 0>::create(None).unwrap(), 0.0)
            .unwrap();
        filter.track_sensor_information();
        run(&mut filter);
        let information = filter.sensor_information().unwrap().clone();
        let store = filter.finish_recording().unwrap().unwrap();
        let mut file = store.borrow_mut();
        observability(&mut file, &SIGMA, 1e-9, directions, Some(&information)).unwrap()
    }

    /// A position fix of variance `r`.
    fn fix(filter: &mut ErrorStateFilter<Cvb, Toy, 3>, r: f64) {
        filter
            .update::<Pos, 1>(
                &SVector::<f64, 1>::new(0.0),
                &SMatrix::<f64, 1, 1>::new(r),
                &Offset::default(),
            )
            .unwrap();
    }

    /// The constant-velocity-and-bias model with position fixes: the
    /// Gramian of the recorded run equals `sum Phi^T H^T R^-1 H Phi`
    /// written by hand.
    #[test]
    fn the_gramian_of_a_linear_model_is_the_hand_written_one() {
        let (r, dt) = (0.5, 0.1);
        let mut hand = SMatrix::<f64, 3, 3>::zeros();
        let h = SMatrix::<f64, 1, 3>::new(1.0, 0.0, 0.0);
        let o = recorded(3, |filter| {
            for k in 1..=40 {
                Propagate::propagate(filter, dt, &CvbInput { a: 0.0 }).unwrap();
                if k % 10 == 0 {
                    fix(filter, r);
                    // Phi(t, 0) of p' = v, v' = -b, as the filter
                    // discretizes it: k first-order steps (I + F dt)^k.
                    let step =
                        SMatrix::<f64, 3, 3>::new(1.0, dt, 0.0, 0.0, 1.0, -dt, 0.0, 0.0, 1.0);
                    let phi = step.pow(k as u32);
                    hand += phi.transpose() * h.transpose() * h * phi / r;
                }
            }
        });
        let d = SMatrix::<f64, 3, 3>::from_diagonal(&SVector::from(SIGMA));
        let expected = (SMatrix::identity() + d * hand * d).try_inverse().unwrap();
        for i in 0..3 {
            let want = 1.0 - expected[(i, i)].sqrt();
            assert!(
                (o.learned[i] - want).abs() < 1e-6,
                "{i}: {} vs {want}",
                o.learned[i]
            );
        }
        assert_eq!(o.weakest.len(), 3);
        assert!(o.weakest[0].learned <= o.weakest[1].learned);
        // One sensor: its information is the run's.
        assert_eq!(o.by_sensor.len(), 1);
        assert_eq!(o.by_sensor[0].0, "pos");
        for i in 0..3 {
            assert!((o.by_sensor[0].1[i] - o.learned[i]).abs() < 1e-6);
        }
    }

    /// Position fixes (batch updates) and position-velocity readings
    /// (sequential), some at the same epoch: each sensor's information is
    /// its own `sum (H Phi)^T R^-1 (H Phi)`, and the two sum to the run's
    /// Gramian.
    #[test]
    fn each_sensor_keeps_its_own_information_and_they_sum_to_the_run() {
        let dt = 0.1;
        let step = SMatrix::<f64, 3, 3>::new(1.0, dt, 0.0, 0.0, 1.0, -dt, 0.0, 0.0, 1.0);
        let (r_pos, r_pv) = (0.5, SVector::<f64, 2>::new(0.2, 0.01));
        let mut hand_pos = SMatrix::<f64, 3, 3>::zeros();
        let mut hand_pv = SMatrix::<f64, 3, 3>::zeros();
        let h_pos = SMatrix::<f64, 1, 3>::new(1.0, 0.0, 0.0);
        let h_pv = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        let r_pv_inverse = SMatrix::<f64, 2, 2>::from_diagonal(&r_pv.map(|v| 1.0 / v));
        let mut information = None;
        let o = recorded(3, |filter| {
            for k in 1..=60 {
                Propagate::propagate(filter, dt, &CvbInput { a: 0.0 }).unwrap();
                let phi = step.pow(k as u32);
                if k % 10 == 0 {
                    fix(filter, r_pos);
                    hand_pos += phi.transpose() * h_pos.transpose() * h_pos * phi / r_pos;
                }
                if k % 15 == 0 {
                    filter
                        .update_sequential::<PosVel, 2>(&SVector::zeros(), &r_pv, &())
                        .unwrap();
                    hand_pv += phi.transpose() * h_pv.transpose() * r_pv_inverse * h_pv * phi;
                }
            }
            information = filter.sensor_information().cloned();
        });
        let information = information.unwrap();
        let by_name: Vec<_> = information.sensors().collect();
        assert_eq!(by_name.len(), 2);
        assert_eq!(by_name[0].0, "pos");
        assert_eq!(by_name[1].0, "posvel");
        assert!((by_name[0].1 - hand_pos).abs().max() < 1e-9 * hand_pos.abs().max());
        assert!((by_name[1].1 - hand_pv).abs().max() < 1e-9 * hand_pv.abs().max());
        // Scaled, summed: the run's learned fractions.
        let d = SMatrix::<f64, 3, 3>::from_diagonal(&SVector::from(SIGMA));
        let total = learned_from(&(d * (hand_pos + hand_pv) * d), &[true; 3]);
        for (i, (t, l)) in total.iter().zip(o.learned).enumerate() {
            assert!((t - l).abs() < 1e-6, "{i}");
        }
        // The velocity readings teach the velocity more than the fixes do.
        let velocity = |s: usize| o.by_sensor[s].1[1];
        assert!(velocity(1) > velocity(0), "{:?}", o.by_sensor);
    }

    /// One position fix, no time for velocity or bias to act on the
    /// position: the position is learned, velocity and bias are not, and
    /// the weakest direction has no position in it.
    #[test]
    fn a_state_no_measurement_reaches_is_not_learned() {
        let o = recorded(2, |filter| fix(filter, 0.01));
        assert!(o.learned[0] > 0.9, "{:?}", o.learned);
        assert!(
            o.learned[1] < 1e-9 && o.learned[2] < 1e-9,
            "{:?}",
            o.learned
        );
        assert!(o.weakest[0].learned < 1e-9);
        assert!(o.weakest[0].coefficients[0].abs() < 1e-9);
    }
}
