//! The `#[cfg(test)]` module emitted with every model: generated Jacobians
//! against central finite differences and the generated covariance algebra
//! against dense products, at seeded pseudo-random points (an inline splitmix64,
//! so the user's crate needs no extra dependency).

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

use crate::front::names::snake_case;
use crate::front::parse::ModelDecl;
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
        quote!(<#name as Model<N>>::transition(x, &u, &p, dt))
    };
    let phi = if continuous {
        quote!(SMatrix::<f64, N, N>::identity() + jac * dt)
    } else {
        quote!(jac)
    };
    let qd_scale = if continuous { quote!(dt) } else { quote!(1.0) };

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
                    let aux: <#ty as Sensor<N, #m>>::Aux = random_record(rng);
                    let jac = <#ty as Sensor<N, #m>>::jacobian(&x, &u, &p, &aux);
                    let h = |x: &SVector<f64, N>| <#ty as Sensor<N, #m>>::predict(x, &u, &p, &aux);
                    let fd = fd_jacobian(&x, h);
                    if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                        return false;
                    }
                    assert_close_fd(concat!(stringify!(#ty), "::jacobian"), &jac, &fd);
                    assert_sparsity(concat!(stringify!(#ty), "::jacobian"), &jac, &<#ty as Sensor<N, #m>>::JACOBIAN_SPARSITY);
                    true
                });
            }

            #[test]
            fn #t_inn() {
                at_random_points(0x5eed_0003, |rng, x, u, p, dt| {
                    let aux: <#ty as Sensor<N, #m>>::Aux = random_record(rng);
                    let cov = random_covariance(rng);
                    let hjac = <#ty as Sensor<N, #m>>::jacobian(&x, &u, &p, &aux);
                    let pred = <#ty as Sensor<N, #m>>::predict(&x, &u, &p, &aux);
                    if !finite(&hjac) || !finite(&pred) {
                        return false;
                    }
                    let (h, pht, s) = <#ty as Sensor<N, #m>>::innovation_terms(&upper_only(&cov), &x, &u, &p, &aux);
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

            const N: usize = #n;
            const NW: usize = #nw;
            /// Points checked per test.
            const POINTS: usize = 6;
            /// Random draws tried to find them (points with non-finite values are skipped).
            const ATTEMPTS: usize = 400;

            /// Calls `check` at random `(x, u, p, dt)` (it draws anything else from
            /// `rng`) until `POINTS` points had finite values (`check` returns true
            /// for those); fails if none had.
            fn at_random_points(
                seed: u64,
                mut check: impl FnMut(&mut SplitMix64, SVector<f64, N>, #input_ty, #params_ty, f64) -> bool,
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

            fn abs(v: f64) -> f64 {
                ::nav_runtime::math::abs(v)
            }

            fn random_record<R: Record>(rng: &mut SplitMix64) -> R {
                R::from_fn(|_| rng.uniform())
            }

            fn random_vector<const K: usize>(rng: &mut SplitMix64) -> SVector<f64, K> {
                SVector::<f64, K>::from_fn(|_, _| rng.uniform())
            }

            fn random_dt(rng: &mut SplitMix64) -> f64 {
                0.01 + 0.1 * abs(rng.uniform())
            }

            /// A random symmetric positive definite matrix `L L^T + I`.
            fn random_covariance(rng: &mut SplitMix64) -> SMatrix<f64, N, N> {
                let l = SMatrix::<f64, N, N>::from_fn(|_, _| rng.uniform());
                l * l.transpose() + SMatrix::<f64, N, N>::identity()
            }

            /// The upper triangle of `m`, NaN below (generated code must not read it).
            fn upper_only(m: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
                SMatrix::<f64, N, N>::from_fn(|i, j| if i <= j { m[(i, j)] } else { f64::NAN })
            }

            fn finite<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> bool {
                m.iter().all(|v| v.is_finite())
            }

            /// Central differences with step `1e-6 (1 + |x_j|)`, and for each entry
            /// the rounding bound `4 eps |f| / step` of the difference quotient
            /// (it matters only for outputs of order 1e6, such as Earth radii).
            fn fd_jacobian<const R: usize, const C: usize>(
                x: &SVector<f64, C>,
                f: impl Fn(&SVector<f64, C>) -> SVector<f64, R>,
            ) -> (SMatrix<f64, R, C>, SMatrix<f64, R, C>) {
                let mut out = SMatrix::<f64, R, C>::zeros();
                let mut rounding = SMatrix::<f64, R, C>::zeros();
                for j in 0..C {
                    let h = 1e-6 * (1.0 + abs(x[j]));
                    let (mut xp, mut xm) = (*x, *x);
                    xp[j] += h;
                    xm[j] -= h;
                    let (fp, fm) = (f(&xp), f(&xm));
                    let col = (fp - fm) / (xp[j] - xm[j]);
                    out.set_column(j, &col);
                    for r in 0..R {
                        let big = if abs(fp[r]) > abs(fm[r]) { abs(fp[r]) } else { abs(fm[r]) };
                        rounding[(r, j)] = 4.0 * f64::EPSILON * big / h;
                    }
                }
                (out, rounding)
            }

            /// `|J - J_fd| <= 1e-6 (1 + |J|)` entrywise (plus the rounding bound).
            fn assert_close_fd<const R: usize, const C: usize>(
                what: &str,
                j: &SMatrix<f64, R, C>,
                (fd, rounding): &(SMatrix<f64, R, C>, SMatrix<f64, R, C>),
            ) {
                for r in 0..R {
                    for c in 0..C {
                        let (a, b) = (j[(r, c)], fd[(r, c)]);
                        assert!(
                            abs(a - b) <= 1e-6 * (1.0 + abs(a)) + rounding[(r, c)],
                            "{what}[({r}, {c})]: generated {a} vs finite differences {b}"
                        );
                    }
                }
            }

            /// Equal to `1e-12` relative to the largest entry of `want`.
            fn assert_close_rel<const R: usize, const C: usize>(what: &str, got: &SMatrix<f64, R, C>, want: &SMatrix<f64, R, C>) {
                let scale = want.iter().fold(1.0f64, |m, v| if abs(*v) > m { abs(*v) } else { m });
                for r in 0..R {
                    for c in 0..C {
                        let (a, b) = (got[(r, c)], want[(r, c)]);
                        assert!(abs(a - b) <= 1e-12 * scale, "{what}[({r}, {c})]: generated {a} vs dense {b}");
                    }
                }
            }

            fn assert_sparsity<const R: usize, const C: usize>(what: &str, j: &SMatrix<f64, R, C>, sparsity: &[[bool; C]; R]) {
                for r in 0..R {
                    for c in 0..C {
                        assert!(sparsity[r][c] || j[(r, c)] == 0.0, "{what}[({r}, {c})] is a structural zero but is {}", j[(r, c)]);
                    }
                }
            }

            #[test]
            fn jacobian_matches_finite_differences() {
                at_random_points(0x5eed_0000, |rng, x, u, p, dt| {
                                        let jac = <#name as Model<N>>::jacobian(&x, &u, &p, dt);
                    let f = |x: &SVector<f64, N>| #f_of_x;
                    let fd = fd_jacobian(&x, f);
                    if !finite(&f(&x)) || !finite(&jac) || !finite(&fd.0) {
                        return false;
                    }
                    assert_close_fd("jacobian", &jac, &fd);
                    assert_sparsity("jacobian", &jac, &<#name as Model<N>>::JACOBIAN_SPARSITY);
                    true
                });
            }

            #[test]
            fn noise_jacobian_matches_finite_differences() {
                at_random_points(0x5eed_0001, |rng, x, u, p, dt| {
                                        let g = #name::noise_jacobian(&x, &u, &p, dt);
                    let f = |w: &SVector<f64, NW>| #name::process_with_noise(&x, &u, &p, w, dt);
                    let w0 = SVector::<f64, NW>::zeros();
                    let fd = fd_jacobian(&w0, f);
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
                    let q: #noise_ty = <#noise_ty as Record>::from_fn(|_| abs(rng.uniform()));
                    let cov = random_covariance(rng);
                    let jac = <#name as Model<N>>::jacobian(&x, &u, &p, dt);
                    let g = #name::noise_jacobian(&x, &u, &p, dt);
                    if !finite(&jac) || !finite(&g) {
                        return false;
                    }
                    let qdiag = SMatrix::<f64, NW, NW>::from_fn(|i, j| if i == j { q.get(i) } else { 0.0 });
                    let qd_dense = g * qdiag * g.transpose() * #qd_scale;
                    let qd = <#name as Model<N>>::process_noise(&x, &u, &p, &q, dt);
                    assert_close_rel("process_noise", &qd, &qd_dense);
                    let phi = #phi;
                    let dense = phi * cov * phi.transpose() + qd_dense;
                    let mut got = cov; // P symmetric (the kernel reads whole columns)
                    <#name as Model<N>>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                    assert_close_rel("propagate_covariance", &got, &dense);
                    assert_eq!(got, got.transpose(), "the propagated covariance must be symmetric");
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
                    assert_eq!(s.get(i), x[i]);
                }
                assert_eq!(<<#name as Model<N>>::State as Record>::NAMES.len(), N);
                assert_eq!(<#name as Model<N>>::STATE_NAMES.len(), N);
            }

            #(#sensor_tests)*
        }
    }
}
