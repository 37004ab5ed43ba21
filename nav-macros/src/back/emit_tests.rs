//! The `#[cfg(test)]` module emitted with every model: generated Jacobians
//! against central finite differences and the generated covariance algebra
//! against dense products, at seeded pseudo-random points (an inline splitmix64,
//! so the user's crate needs no extra dependency).

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use crate::front::names::snake_case;
use crate::front::parse::{ModelDecl, Scalar};
use crate::symbolic::derive::Derived;
use crate::symbolic::ProcessKind;

/// The test module of one model.
pub fn tests(decl: &ModelDecl, d: &Derived) -> TokenStream {
    let name = &decl.name;
    let module = format_ident!("__{}_generated_tests", snake_case(&name.to_string()));
    let (state_ty, input_ty, params_ty, noise_ty) = (
        format_ident!("{}State", name),
        format_ident!("{}Input", name),
        format_ident!("{}Params", name),
        format_ident!("{}Noise", name),
    );
    let n = Literal::usize_unsuffixed(d.n);
    let nw = Literal::usize_unsuffixed(d.nw);
    let continuous = d.kind == ProcessKind::Continuous;
    // The function whose Jacobian `jacobian` is: f (continuous) or the transition.
    let f_of_x = if continuous {
        quote!(#name::derivative(x, &u, &p))
    } else {
        quote!(<#name as Model<N, S>>::transition(x, &u, &p, dt))
    };
    // The function whose noise Jacobian `noise_jacobian` is.
    let noisy_f = if continuous {
        quote!(#name::derivative_with_noise(&x, &u, &p, w))
    } else {
        quote!(#name::step_with_noise(&x, &u, &p, w, dt))
    };
    let phi = if continuous {
        quote!(SMatrix::<S, N, N>::identity() + jac * dt)
    } else {
        quote!(jac)
    };
    let qd_scale = if continuous { quote!(dt) } else { quote!(1.0) };
    let scalar = decl.scalar.tokens();
    let math = decl.scalar.math();
    // f64: step 1e-6 (near the optimum eps^(1/3)); f32: 2e-3, where the
    // truncation error h^2 f'''/6 and the rounding 4 eps |f| / h of the
    // quotient are both below the 1e-3 tolerance for O(1) derivatives. The
    // sparse algebra sums at most N products: 1e-12 in f64, 1e-4 in f32.
    let (fd_step, fd_tolerance, relative) = match decl.scalar {
        Scalar::F64 => (quote!(1e-6), quote!(1e-6), quote!(1e-12)),
        Scalar::F32 => (quote!(2e-3), quote!(1e-3), quote!(1e-4)),
    };

    let sensor_tests = decl.sensors.iter().map(|s| {
        let ty = format_ident!("{}{}", name, s.name);
        let snake = snake_case(&s.name.to_string());
        let t_jac = format_ident!("sensor_{}_jacobian_matches_finite_differences", snake);
        let t_inn = format_ident!("sensor_{}_innovation_terms_match_dense_products", snake);
        let m = Literal::usize_unsuffixed(s.dim);
        quote! {
            #[test]
            fn #t_jac() {
                at_random_points(0x5eed_0002, |rng, x, u, p, dt| {
                    let aux: <#ty as Sensor<N, #m, S>>::Aux = random_record(rng);
                    let jac = <#ty as Sensor<N, #m, S>>::jacobian(&x, &u, &p, &aux);
                    let h = |x: &SVector<S, N>| <#ty as Sensor<N, #m, S>>::predict(x, &u, &p, &aux);
                    let Some(fd) = fd_jacobian(&x, h) else { return false };
                    if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                        return false;
                    }
                    assert_close_fd(concat!(stringify!(#ty), "::jacobian"), &jac, &fd);
                    assert_sparsity(concat!(stringify!(#ty), "::jacobian"), &jac, &<#ty as Sensor<N, #m, S>>::JACOBIAN_SPARSITY);
                    true
                });
            }

            #[test]
            fn #t_inn() {
                at_random_points(0x5eed_0003, |rng, x, u, p, dt| {
                    let aux: <#ty as Sensor<N, #m, S>>::Aux = random_record(rng);
                    let cov = random_covariance(rng);
                    let hjac = <#ty as Sensor<N, #m, S>>::jacobian(&x, &u, &p, &aux);
                    let pred = <#ty as Sensor<N, #m, S>>::predict(&x, &u, &p, &aux);
                    if !finite(&hjac) || !finite(&pred) {
                        return false;
                    }
                    let (h, pht, s) = <#ty as Sensor<N, #m, S>>::innovation_terms(&upper_only(&cov), &x, &u, &p, &aux);
                    assert_close_rel("h", &h, &pred);
                    assert_close_rel("P H^T", &pht, &(cov * hjac.transpose()));
                    assert_close_rel("H P H^T", &s, &(hjac * cov * hjac.transpose()));
                    assert_eq!(s, s.transpose(), "H P H^T must be symmetric");
                    true
                });
            }
        }
    });

    quote! {
        #[cfg(test)]
        #[allow(clippy::possible_missing_comma, non_snake_case)]
        mod #module {
            use super::*;
            use ::nav_runtime::model::{Model, Record, Sensor};
            use ::nav_runtime::nalgebra::{SMatrix, SVector};

            /// The model's scalar.
            type S = #scalar;
            /// Finite-difference step (relative), tolerance of a Jacobian entry
            /// against it, and tolerance of the sparse covariance algebra
            /// against dense products, for this scalar's precision.
            const FD_STEP: S = #fd_step;
            const FD_TOLERANCE: S = #fd_tolerance;
            const RELATIVE: S = #relative;
            const N: usize = #n;
            const NW: usize = #nw;
            /// Points checked per test.
            const POINTS: usize = 6;
            /// Random draws tried to find them (points with non-finite values, or a kink within a step, are skipped).
            const ATTEMPTS: usize = 400;

            /// Calls `check` at random `(x, u, p, dt)` (it draws anything else from
            /// `rng`) until `POINTS` points were usable (`check` returns true
            /// for those); fails if none had.
            fn at_random_points(
                seed: u64,
                mut check: impl FnMut(&mut SplitMix64, SVector<S, N>, #input_ty, #params_ty, S) -> bool,
            ) {
                let mut rng = SplitMix64(seed);
                let mut checked = 0;
                for _ in 0..ATTEMPTS {
                    if checked == POINTS {
                        break;
                    }
                    let x = random_vector::<N>(&mut rng);
                    let u: #input_ty = random_record(&mut rng);
                    let p: #params_ty = random_record(&mut rng);
                    let dt = random_dt(&mut rng);
                    if check(&mut rng, x, u, p, dt) {
                        checked += 1;
                    }
                }
                assert!(checked > 0, "no point with finite values found");
            }

            /// splitmix64: a tiny deterministic generator.
            struct SplitMix64(u64);

            impl SplitMix64 {
                fn next_u64(&mut self) -> u64 {
                    self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
                    let mut z = self.0;
                    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                    z ^ (z >> 31)
                }
                /// Uniform in [-1, 1].
                fn uniform(&mut self) -> f64 {
                    ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
                }
            }

            fn abs(v: S) -> S {
                #math::abs(v)
            }

            /// A uniform draw in [-1, 1] in the model's scalar.
            fn draw(rng: &mut SplitMix64) -> S {
                <S as ::nav_runtime::Real>::of(rng.uniform())
            }

            fn random_record<R: Record>(rng: &mut SplitMix64) -> R {
                R::from_fn(|_| rng.uniform())
            }

            fn random_vector<const K: usize>(rng: &mut SplitMix64) -> SVector<S, K> {
                SVector::<S, K>::from_fn(|_, _| draw(rng))
            }

            fn random_dt(rng: &mut SplitMix64) -> S {
                0.01 + 0.1 * abs(draw(rng))
            }

            /// A random symmetric positive definite matrix `L L^T + I`.
            fn random_covariance(rng: &mut SplitMix64) -> SMatrix<S, N, N> {
                let l = SMatrix::<S, N, N>::from_fn(|_, _| draw(rng));
                l * l.transpose() + SMatrix::<S, N, N>::identity()
            }

            /// The upper triangle of `m`, NaN below (generated code must not read it).
            fn upper_only(m: &SMatrix<S, N, N>) -> SMatrix<S, N, N> {
                SMatrix::<S, N, N>::from_fn(|i, j| if i <= j { m[(i, j)] } else { S::NAN })
            }

            fn finite<const R: usize, const C: usize>(m: &SMatrix<S, R, C>) -> bool {
                m.iter().all(|v| v.is_finite())
            }

            /// Central differences with step `FD_STEP (1 + |x_j|)`, and for each entry
            /// the rounding bound `4 eps |f| / step` of the difference quotient
            /// (it matters only for outputs of order 1e6, such as Earth radii, or
            /// in `f32`). `None` where the step straddles a kink of a non-smooth
            /// function (`min`, `max`, `clamp`, `abs`, `sign`): the one-sided
            /// quotients then disagree by far more than curvature explains, and
            /// the central one is no derivative.
            fn fd_jacobian<const R: usize, const C: usize>(
                x: &SVector<S, C>,
                f: impl Fn(&SVector<S, C>) -> SVector<S, R>,
            ) -> Option<(SMatrix<S, R, C>, SMatrix<S, R, C>)> {
                let mut out = SMatrix::<S, R, C>::zeros();
                let mut rounding = SMatrix::<S, R, C>::zeros();
                let f0 = f(x);
                for j in 0..C {
                    let h = FD_STEP * (1.0 + abs(x[j]));
                    let (mut xp, mut xm) = (*x, *x);
                    xp[j] += h;
                    xm[j] -= h;
                    let (fp, fm) = (f(&xp), f(&xm));
                    let col = (fp - fm) / (xp[j] - xm[j]);
                    for r in 0..R {
                        let big = if abs(fp[r]) > abs(fm[r]) { abs(fp[r]) } else { abs(fm[r]) };
                        rounding[(r, j)] = 4.0 * S::EPSILON * big / h;
                        let forward = (fp[r] - f0[r]) / (xp[j] - x[j]);
                        let backward = (f0[r] - fm[r]) / (x[j] - xm[j]);
                        if abs(forward - backward) > 0.25 * (1.0 + abs(col[r])) + 4.0 * rounding[(r, j)] {
                            return None;
                        }
                    }
                    out.set_column(j, &col);
                }
                Some((out, rounding))
            }

            /// `|J - J_fd| <= FD_TOLERANCE (1 + |J|)` entrywise (plus the rounding bound).
            fn assert_close_fd<const R: usize, const C: usize>(
                what: &str,
                j: &SMatrix<S, R, C>,
                (fd, rounding): &(SMatrix<S, R, C>, SMatrix<S, R, C>),
            ) {
                for r in 0..R {
                    for c in 0..C {
                        let (a, b) = (j[(r, c)], fd[(r, c)]);
                        assert!(
                            abs(a - b) <= FD_TOLERANCE * (1.0 + abs(a)) + rounding[(r, c)],
                            "{what}[({r}, {c})]: generated {a} vs finite differences {b}"
                        );
                    }
                }
            }

            /// Equal to `RELATIVE` relative to the largest entry of `want`.
            fn assert_close_rel<const R: usize, const C: usize>(what: &str, got: &SMatrix<S, R, C>, want: &SMatrix<S, R, C>) {
                let scale = want.iter().fold(1.0 as S, |m, v| if abs(*v) > m { abs(*v) } else { m });
                for r in 0..R {
                    for c in 0..C {
                        let (a, b) = (got[(r, c)], want[(r, c)]);
                        assert!(abs(a - b) <= RELATIVE * scale, "{what}[({r}, {c})]: generated {a} vs dense {b}");
                    }
                }
            }

            fn assert_sparsity<const R: usize, const C: usize>(what: &str, j: &SMatrix<S, R, C>, sparsity: &[[bool; C]; R]) {
                for r in 0..R {
                    for c in 0..C {
                        assert!(sparsity[r][c] || j[(r, c)] == 0.0, "{what}[({r}, {c})] is a structural zero but is {}", j[(r, c)]);
                    }
                }
            }

            #[test]
            fn jacobian_matches_finite_differences() {
                at_random_points(0x5eed_0000, |rng, x, u, p, dt| {
                                        let jac = <#name as Model<N, S>>::jacobian(&x, &u, &p, dt);
                    let f = |x: &SVector<S, N>| #f_of_x;
                    let Some(fd) = fd_jacobian(&x, f) else { return false };
                    if !finite(&f(&x)) || !finite(&jac) || !finite(&fd.0) {
                        return false;
                    }
                    assert_close_fd("jacobian", &jac, &fd);
                    assert_sparsity("jacobian", &jac, &<#name as Model<N, S>>::JACOBIAN_SPARSITY);
                    true
                });
            }

            #[test]
            fn noise_jacobian_matches_finite_differences() {
                at_random_points(0x5eed_0001, |rng, x, u, p, dt| {
                                        let g = #name::noise_jacobian(&x, &u, &p, dt);
                    let f = |w: &SVector<S, NW>| #noisy_f;
                    let w0 = SVector::<S, NW>::zeros();
                    let Some(fd) = fd_jacobian(&w0, f) else { return false };
                    if !finite(&f(&w0)) || !finite(&g) || !finite(&fd.0) {
                        return false;
                    }
                    assert_close_fd("noise_jacobian", &g, &fd);
                    true
                });
            }

            #[test]
            fn propagate_covariance_matches_dense_products() {
                at_random_points(0x5eed_0004, |rng, x, u, p, dt| {
                    let q: #noise_ty = <#noise_ty as Record>::from_fn(|_| ::nav_runtime::math::abs(rng.uniform()));
                    let cov = random_covariance(rng);
                    let jac = <#name as Model<N, S>>::jacobian(&x, &u, &p, dt);
                    let g = #name::noise_jacobian(&x, &u, &p, dt);
                    if !finite(&jac) || !finite(&g) {
                        return false;
                    }
                    let qdiag = SMatrix::<S, NW, NW>::from_fn(|i, j| if i == j { <S as ::nav_runtime::Real>::of(q.get(i)) } else { 0.0 });
                    let qd_dense = g * qdiag * g.transpose() * #qd_scale;
                    let qd = <#name as Model<N, S>>::process_noise(&x, &u, &p, &q, dt);
                    assert_close_rel("process_noise", &qd, &qd_dense);
                    let phi = #phi;
                    let dense = phi * cov * phi.transpose() + qd_dense;
                    let mut got = cov; // P symmetric (the kernel reads whole columns)
                    <#name as Model<N, S>>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                    assert_close_rel("propagate_covariance", &got, &dense);
                    assert_eq!(got, got.transpose(), "the propagated covariance must be symmetric");
                    // The observed variant: the same result, and the
                    // coefficients it hands over rebuild Phi on the structure.
                    let mut observed = cov;
                    let mut rebuilt: Option<SMatrix<S, N, N>> = None;
                    <#name as Model<N, S>>::propagate_covariance_observed(&mut observed, &x, &u, &p, &q, dt, |c| {
                        let s = <#name as Model<N, S>>::PROPAGATION.expect("observed only over a structure");
                        let mut m = SMatrix::<S, N, N>::identity();
                        for (r, &i) in s.rows.iter().enumerate() {
                            if !s.identity {
                                m[(i, i)] = 0.0;
                            }
                            for k in s.start[r]..s.start[r + 1] {
                                m[(i, s.columns[k])] += c[k];
                            }
                        }
                        rebuilt = Some(m);
                    });
                    assert_eq!(observed, got, "propagate_covariance_observed equals propagate_covariance");
                    assert_eq!(rebuilt.is_some(), <#name as Model<N, S>>::PROPAGATION.is_some(), "observed once over a structure");
                    if let Some(m) = rebuilt {
                        assert_close_rel("observed transition", &m, &phi);
                    }
                    true
                });
            }

            #[test]
            fn state_record_round_trips() {
                let mut rng = SplitMix64(0x5eed_0005);
                let x = random_vector::<N>(&mut rng);
                let s = #state_ty::from_vector(&x);
                assert_eq!(s.to_vector(), x);
                for i in 0..N {
                    assert_eq!(s.get(i), <S as ::nav_runtime::Real>::to_f64(x[i]));
                }
                assert_eq!(<<#name as Model<N, S>>::State as Record>::NAMES.len(), N);
                assert_eq!(<#name as Model<N, S>>::STATE_NAMES.len(), N);
            }

            #(#sensor_tests)*
        }
    }
}
