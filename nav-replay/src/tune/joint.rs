//! The standard errors of the tuned parameters taken together (eq. T5 of
//! docs/tuning.md): the inverse of their joint information.
//!
//! The curvature of the likelihood in one parameter with the others held
//! gives its conditional standard error. Two parameters that act on the
//! same innovations (a speed log's sigma and the water current's random
//! walk behind it) trade against each other, and each is then known less
//! well than its own curvature says: the marginal error
//! `sqrt((J^-1)_pp)` of the joint information `J` is the one to report.

use nalgebra::DMatrix;

use nav_runtime::innovations::InnovationTotals;

/// The gradient of the innovation log-likelihood in `ln sigma` of the
/// sensor whose totals these are, `P` held (eq. T2 as a gradient):
/// `sum_k nu^T S^-1 R S^-1 nu - tr(S^-1 R)`.
pub(super) fn sensor_gradient(totals: &InnovationTotals) -> f64 {
    totals.noise_nis - totals.noise_share
}

/// The information of each parameter (`None`: not part of the joint
/// estimate: a clock, or one the log does not identify) and the measured
/// cross terms `(p, q, J_pq)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct JointInformation {
    pub diagonal: Vec<Option<f64>>,
    pub cross: Vec<(usize, usize, f64)>,
}

impl JointInformation {
    /// The marginal standard error of each parameter with a diagonal term:
    /// `sqrt((J^-1)_pp)` over the parameters with positive information.
    /// `None` for the others, and for all when `J` is not positive definite
    /// (finite differences too noisy to combine): the caller keeps the
    /// conditional errors then.
    pub fn marginal_errors(&self) -> Option<Vec<Option<f64>>> {
        let (joint, j) = self.matrix();
        let inverse = j.cholesky()?.inverse();
        let mut errors = vec![None; self.diagonal.len()];
        for (a, &p) in joint.iter().enumerate() {
            errors[p] = Some(inverse[(a, a)].sqrt());
        }
        Some(errors)
    }

    /// The Newton step of the parameters taken together, from the step
    /// `conditional` each would take with the others held (`m_p = g_p /
    /// J_pp`, `g` the gradient): `J^-1 D m` with `D` the diagonal of `J`
    /// (eq. T6), which is `J^-1 g`. Steps taken each on its own overshoot
    /// when two parameters trade against each other (the speed log's sigma
    /// and the current's random walk): each takes the whole of the misfit
    /// the other also takes, and the two zig-zag about the optimum, closing
    /// in by the factor of their correlation per step. Parameters without
    /// a diagonal term keep their step; `None` when `J` is not positive
    /// definite.
    pub fn joint_step(&self, conditional: &[f64]) -> Option<Vec<f64>> {
        let (joint, j) = self.matrix();
        let g = nalgebra::DVector::from_iterator(
            joint.len(),
            joint
                .iter()
                .enumerate()
                .map(|(a, &p)| j[(a, a)] * conditional[p]),
        );
        let step = j.cholesky()?.solve(&g);
        let mut out = conditional.to_vec();
        for (a, &p) in joint.iter().enumerate() {
            out[p] = step[a];
        }
        out.iter().all(|m| m.is_finite()).then_some(out)
    }

    /// The parameters with positive information and their matrix `J`.
    fn matrix(&self) -> (Vec<usize>, DMatrix<f64>) {
        let joint: Vec<usize> = (0..self.diagonal.len())
            .filter(|&p| self.diagonal[p].is_some_and(|d| d > 0.0 && d.is_finite()))
            .collect();
        let mut j = DMatrix::<f64>::zeros(joint.len(), joint.len());
        for (a, &p) in joint.iter().enumerate() {
            j[(a, a)] = self.diagonal[p].unwrap_or_default();
        }
        for &(p, q, v) in &self.cross {
            let (Some(a), Some(b)) = (
                joint.iter().position(|&i| i == p),
                joint.iter().position(|&i| i == q),
            ) else {
                continue;
            };
            if v.is_finite() && a != b {
                j[(a, b)] = v;
                j[(b, a)] = v;
            }
        }
        (joint, j)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two parameters with unit information and correlation `rho`: each
    /// marginal error is `1 / sqrt(1 - rho^2)`; uncorrelated ones keep
    /// their own; a third without information is left out; a cross term
    /// beyond the diagonal's (no positive definite `J`) gives `None`.
    #[test]
    fn marginal_errors_grow_with_the_cross_information() {
        // (cross term, expected marginal error of the first two)
        let cases = [
            (0.0, Some(1.0)),
            (0.6, Some(1.25)),
            (-0.8, Some(1.0 / 0.6)),
            (1.2, None),
        ];
        for (cross, expected) in cases {
            let j = JointInformation {
                diagonal: vec![Some(1.0), Some(1.0), None, Some(4.0)],
                cross: vec![(0, 1, cross), (2, 0, 5.0)],
            };
            let errors = j.marginal_errors();
            match expected {
                None => assert!(errors.is_none(), "{cross}: {errors:?}"),
                Some(e) => {
                    let errors = errors.unwrap();
                    for p in [0, 1] {
                        approx::assert_relative_eq!(errors[p].unwrap(), e, max_relative = 1e-12);
                    }
                    assert_eq!(errors[2], None);
                    approx::assert_relative_eq!(errors[3].unwrap(), 0.5, max_relative = 1e-12);
                }
            }
        }
        // Nothing to combine is no failure (and no note).
        let none = JointInformation {
            diagonal: vec![None, Some(0.0)],
            cross: vec![(0, 1, 1.0)],
        };
        assert_eq!(none.marginal_errors(), Some(vec![None, None]));
    }

    /// On a quadratic log-likelihood with information `J` and optimum
    /// `x*`, the steps taken each with the others held, from any point,
    /// become the step to `x*` itself; uncoupled parameters and one without
    /// information keep their own step.
    #[test]
    fn the_joint_step_reaches_the_optimum_of_a_quadratic() {
        let j = nalgebra::Matrix3::new(40.0, -30.0, 0.0, -30.0, 50.0, 0.0, 0.0, 0.0, 9.0);
        let optimum = nalgebra::Vector3::new(0.3, -0.2, 0.5);
        for start in [[0.0, 0.0, 0.0], [2.0, 1.0, -1.0], [-1.0, 0.4, 0.5]] {
            let x = nalgebra::Vector3::from(start);
            // Gradient of -(x - x*)^T J (x - x*) / 2.
            let g = j * (optimum - x);
            let conditional = vec![g[0] / j[(0, 0)], g[1] / j[(1, 1)], 7.0, g[2] / j[(2, 2)]];
            let info = JointInformation {
                diagonal: vec![Some(j[(0, 0)]), Some(j[(1, 1)]), None, Some(j[(2, 2)])],
                cross: vec![(0, 1, j[(0, 1)])],
            };
            let step = info.joint_step(&conditional).unwrap();
            for (p, k) in [(0, 0), (1, 1), (3, 2)] {
                approx::assert_relative_eq!(x[k] + step[p], optimum[k], epsilon = 1e-12);
            }
            assert_eq!(step[2], 7.0);
        }
        let singular = JointInformation {
            diagonal: vec![Some(1.0), Some(1.0)],
            cross: vec![(0, 1, 1.5)],
        };
        assert_eq!(singular.joint_step(&[0.1, 0.2]), None);
    }
}
