//! The generated process functions with an explicit noise sample say what they
//! return: `derivative_with_noise(x, u, p, w)` is `dx/dt` (continuous models
//! only, no `dt`), `step_with_noise(x, u, p, w, dt)` is the state after `dt`
//! (every model). Checked against closed-form solutions of small linear
//! models (issue: a derivative returned by a function taking `dt` was used as
//! a step). See `docs/language.md`, "What is generated".

use nav_runtime::model::Model;
use nav_runtime::nalgebra::SVector;

nav_runtime::model! {
    /// `dx/dt = -k x + w`: exponential decay towards `w / k`.
    pub model Decay {
        states { x }
        parameters { k }
        noise { w }
        continuous { d/dt x = -k * x + w; }
        sensor Level: 1 { h = x; }
    }

    /// `d/dt pos = vel`, `d/dt vel = -omega^2 pos + force`: an undamped spring.
    pub model Spring {
        states { pos, vel }
        parameters { omega }
        noise { force }
        continuous {
            d/dt pos = vel;
            d/dt vel = -omega * omega * pos + force;
        }
        sensor Position: 1 { h = pos; }
    }

    /// `x_k = x_{k-1} + (v + w) dt`: a discrete walk at a commanded speed.
    pub model Walk {
        states { x }
        inputs { v }
        noise { w }
        discrete { x = x + (v + w) * dt; }
        sensor Position: 1 { h = x; }
    }
}

/// One model: its step and derivative as plain vector functions of `(x, w,
/// dt)`, the exact solution `x(t)` from `x0` under a constant noise sample,
/// and the order of the step's global error (0: exact).
/// A state function of `(x, w)`: the derivative with a noise sample.
type Derivative = fn(&[f64], f64) -> Vec<f64>;

struct Case {
    name: &'static str,
    x0: Vec<f64>,
    w: f64,
    horizon: f64,
    step: fn(&[f64], f64, f64) -> Vec<f64>,
    transition: fn(&[f64], f64) -> Vec<f64>,
    derivative: Option<Derivative>,
    exact: fn(&[f64], f64, f64) -> Vec<f64>,
    order: u32,
}

const K: f64 = 0.7;
const OMEGA: f64 = 1.3;
const V: f64 = 0.4;

fn decay_exact(x0: &[f64], w: f64, t: f64) -> Vec<f64> {
    let eq = w / K;
    vec![eq + (x0[0] - eq) * (-K * t).exp()]
}

fn spring_exact(x0: &[f64], w: f64, t: f64) -> Vec<f64> {
    let eq = w / (OMEGA * OMEGA);
    let (s, c) = (OMEGA * t).sin_cos();
    let (p0, v0) = (x0[0] - eq, x0[1]);
    vec![eq + p0 * c + v0 / OMEGA * s, -p0 * OMEGA * s + v0 * c]
}

fn walk_exact(x0: &[f64], w: f64, t: f64) -> Vec<f64> {
    vec![x0[0] + (V + w) * t]
}

fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "Decay (continuous)",
            x0: vec![2.0],
            w: 0.3,
            horizon: 2.0,
            step: |x, w, dt| {
                let p = DecayParams { k: K };
                let x = SVector::<f64, 1>::from_column_slice(x);
                Decay::step_with_noise(&x, &DecayInput {}, &p, &SVector::from([w]), dt)
                    .as_slice()
                    .to_vec()
            },
            transition: |x, dt| {
                let p = DecayParams { k: K };
                let x = SVector::<f64, 1>::from_column_slice(x);
                Decay::transition(&x, &DecayInput {}, &p, dt)
                    .as_slice()
                    .to_vec()
            },
            derivative: Some(|x, w| {
                let p = DecayParams { k: K };
                let x = SVector::<f64, 1>::from_column_slice(x);
                Decay::derivative_with_noise(&x, &DecayInput {}, &p, &SVector::from([w]))
                    .as_slice()
                    .to_vec()
            }),
            exact: decay_exact,
            order: 1,
        },
        Case {
            name: "Spring (continuous)",
            x0: vec![0.5, -0.2],
            w: 0.8,
            horizon: 3.0,
            step: |x, w, dt| {
                let p = SpringParams { omega: OMEGA };
                let x = SVector::<f64, 2>::from_column_slice(x);
                Spring::step_with_noise(&x, &SpringInput {}, &p, &SVector::from([w]), dt)
                    .as_slice()
                    .to_vec()
            },
            transition: |x, dt| {
                let p = SpringParams { omega: OMEGA };
                let x = SVector::<f64, 2>::from_column_slice(x);
                Spring::transition(&x, &SpringInput {}, &p, dt)
                    .as_slice()
                    .to_vec()
            },
            derivative: Some(|x, w| {
                let p = SpringParams { omega: OMEGA };
                let x = SVector::<f64, 2>::from_column_slice(x);
                Spring::derivative_with_noise(&x, &SpringInput {}, &p, &SVector::from([w]))
                    .as_slice()
                    .to_vec()
            }),
            exact: spring_exact,
            order: 1,
        },
        Case {
            name: "Walk (discrete)",
            x0: vec![-1.0],
            w: 0.1,
            horizon: 5.0,
            step: |x, w, dt| {
                let x = SVector::<f64, 1>::from_column_slice(x);
                Walk::step_with_noise(
                    &x,
                    &WalkInput { v: V },
                    &WalkParams {},
                    &SVector::from([w]),
                    dt,
                )
                .as_slice()
                .to_vec()
            },
            transition: |x, dt| {
                let x = SVector::<f64, 1>::from_column_slice(x);
                Walk::transition(&x, &WalkInput { v: V }, &WalkParams {}, dt)
                    .as_slice()
                    .to_vec()
            },
            derivative: None,
            exact: walk_exact,
            order: 0,
        },
    ]
}

/// Largest absolute difference of two vectors.
fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// `steps` steps of `horizon / steps` from `x0`; the error against the exact solution.
fn integration_error(c: &Case, steps: u32) -> f64 {
    let dt = c.horizon / f64::from(steps);
    let mut x = c.x0.clone();
    for _ in 0..steps {
        x = (c.step)(&x, c.w, dt);
    }
    max_diff(&x, &(c.exact)(&c.x0, c.w, c.horizon))
}

/// The step advanced by `dt` integrates the model: its global error over a
/// fixed horizon falls with `dt` at the step's order (first order for the
/// Euler step of a continuous model: halving `dt` halves it), or is rounding
/// only for an exact discrete step. A derivative used as a step would not
/// converge at all.
#[test]
fn step_with_noise_integrates_the_model() {
    for c in cases() {
        let (coarse, fine) = (integration_error(&c, 400), integration_error(&c, 800));
        match c.order {
            0 => assert!(
                coarse < 1e-12 && fine < 1e-12,
                "{}: {coarse} {fine}",
                c.name
            ),
            1 => {
                let ratio = coarse / fine;
                assert!(
                    (1.9..2.1).contains(&ratio),
                    "{}: error {coarse} at 400 steps, {fine} at 800 (ratio {ratio}, first order gives 2)",
                    c.name
                );
                assert!(fine < 5e-3, "{}: error {fine} at 800 steps", c.name);
            }
            _ => unreachable!(),
        }
    }
}

/// The derivative is `dx/dt` of the exact solution (central differences in
/// time), at a few points along it.
#[test]
fn derivative_with_noise_is_the_time_derivative() {
    let h = 1e-5;
    for c in cases() {
        let Some(derivative) = c.derivative else {
            continue;
        };
        for t in [0.0, 0.37, 1.2] {
            let x = (c.exact)(&c.x0, c.w, t);
            let plus = (c.exact)(&c.x0, c.w, t + h);
            let minus = (c.exact)(&c.x0, c.w, t - h);
            let fd: Vec<f64> = plus
                .iter()
                .zip(&minus)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect();
            let got = derivative(&x, c.w);
            assert!(
                max_diff(&got, &fd) < 1e-8,
                "{} at t = {t}: {got:?} vs finite differences {fd:?}",
                c.name
            );
        }
    }
}

/// The step at zero noise is `transition`; a continuous model's step is
/// `x + derivative_with_noise * dt`.
#[test]
fn step_is_transition_at_zero_noise_and_euler_of_the_derivative() {
    for c in cases() {
        for dt in [0.01, 0.1, 0.5] {
            let x = (c.exact)(&c.x0, c.w, 0.3);
            assert!(
                max_diff(&(c.step)(&x, 0.0, dt), &(c.transition)(&x, dt)) < 1e-15,
                "{} dt = {dt}",
                c.name
            );
            if let Some(derivative) = c.derivative {
                let euler: Vec<f64> = x
                    .iter()
                    .zip(derivative(&x, c.w))
                    .map(|(xi, fi)| xi + fi * dt)
                    .collect();
                assert!(
                    max_diff(&(c.step)(&x, c.w, dt), &euler) < 1e-15,
                    "{} dt = {dt}",
                    c.name
                );
            }
        }
    }
}
