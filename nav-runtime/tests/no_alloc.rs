//! Proves that prediction and update never touch the heap.
//!
//! A global allocator is per binary, so this test has its own binary: every
//! allocation made by the test thread while counting is on is counted, and
//! 1000 predict/update cycles (every discretization, batch and sequential
//! updates, gated, refused and error-state updates, an error-state filter
//! whose sensors read the input rebuilt from its nominal, and one recording
//! for the smoother) must make none.

use nav_runtime::ekf::{Discretization, Ekf};
use nav_runtime::error_state::{ErrorStateFilter, NominalState};
use nav_runtime::gate::Gate;
use nav_runtime::model::{Model, Record, Sensor};
use nav_runtime::nalgebra::{SMatrix, SVector};
use nav_runtime::propagation::{propagate, Structure};
use nav_runtime::smoother::EpochFile;

#[path = "support/counting_allocator.rs"]
mod counting_allocator;

/// Number of allocations made by the current thread while running `f`.
fn allocations(f: impl FnOnce()) -> usize {
    counting_allocator::allocations(f).0
}

/// Records of named scalars, written by hand as generated code would be.
macro_rules! record {
    ($name:ident { $($field:ident),+ }) => {
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        struct $name { $($field: f64),+ }
        impl Record for $name {
            const LEN: usize = [$(stringify!($field)),+].len();
            const NAMES: &'static [&'static str] = &[$(stringify!($field)),+];
            fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
                let mut i = 0;
                $(let $field = f(i); i += 1;)+
                let _ = i;
                Self { $($field),+ }
            }
            fn get(&self, i: usize) -> f64 {
                [$(self.$field),+].get(i).copied().unwrap_or(f64::NAN)
            }
        }
    };
}

record!(Accel { ax, ay, az });
record!(Psd { q });
record!(Lever { l });

/// 3-D constant velocity driven by a measured acceleration: x = (p, v).
struct Cv3;

fn f_matrix() -> SMatrix<f64, 6, 6> {
    SMatrix::<f64, 6, 6>::from_fn(|r, c| if c == r + 3 { 1.0 } else { 0.0 })
}

impl Model<6> for Cv3 {
    type Input = Accel;
    type Params = ();
    type Noise = Psd;
    type State = ();
    const NAME: &'static str = "Cv3";
    const DISCRETE: bool = false;
    const STATE_NAMES: [&'static str; 6] = ["px", "py", "pz", "vx", "vy", "vz"];
    const JACOBIAN_SPARSITY: [[bool; 6]; 6] = {
        let mut s = [[false; 6]; 6];
        s[0][3] = true;
        s[1][4] = true;
        s[2][5] = true;
        s
    };
    const OPS_PROPAGATE_COVARIANCE: usize = 0;
    const OPS_JACOBIAN: usize = 0;
    // The first-order step runs the row kernel, as a generated model of
    // this size would, so a smoother's recording takes its transition.
    const PROPAGATION: Option<Structure<'static>> = Some(Structure {
        identity: true,
        rows: &[0, 1, 2],
        start: &[0, 1, 2, 3],
        columns: &[3, 4, 5],
        noise: &[(3, 3), (4, 4), (5, 5)],
    });

    fn transition(x: &SVector<f64, 6>, u: &Accel, _: &(), dt: f64) -> SVector<f64, 6> {
        let a = SVector::<f64, 6>::new(0.0, 0.0, 0.0, u.ax, u.ay, u.az);
        x + (f_matrix() * x + a) * dt
    }

    fn jacobian(_: &SVector<f64, 6>, _: &Accel, _: &(), _: f64) -> SMatrix<f64, 6, 6> {
        f_matrix()
    }

    fn process_noise(
        _: &SVector<f64, 6>,
        _: &Accel,
        _: &(),
        q: &Psd,
        dt: f64,
    ) -> SMatrix<f64, 6, 6> {
        SMatrix::<f64, 6, 6>::from_fn(|r, c| if r == c && r >= 3 { q.q * dt } else { 0.0 })
    }

    fn propagate_covariance_observed<F: FnOnce(&[f64])>(
        cov: &mut SMatrix<f64, 6, 6>,
        _: &SVector<f64, 6>,
        _: &Accel,
        _: &(),
        q: &Psd,
        dt: f64,
        observe: F,
    ) {
        let coefficients = [dt; 3];
        observe(&coefficients);
        let structure = Self::PROPAGATION.expect("declared above");
        propagate::<f64, 6, 3>(cov, &structure, &coefficients, &[q.q * dt; 3]);
    }

    fn propagate_covariance(
        cov: &mut SMatrix<f64, 6, 6>,
        x: &SVector<f64, 6>,
        u: &Accel,
        p: &(),
        q: &Psd,
        dt: f64,
    ) {
        let phi = SMatrix::<f64, 6, 6>::identity() + f_matrix() * dt;
        let mut out = phi * *cov * phi.transpose() + Self::process_noise(x, u, p, q, dt);
        for c in 0..6 {
            for r in 0..c {
                out[(c, r)] = out[(r, c)];
            }
        }
        *cov = out;
    }
}

fn terms<const M: usize>(
    cov: &SMatrix<f64, 6, 6>,
    h: SVector<f64, M>,
    hm: SMatrix<f64, M, 6>,
) -> (SVector<f64, M>, SMatrix<f64, 6, M>, SMatrix<f64, M, M>) {
    let u = cov * hm.transpose();
    (h, u, hm * u)
}

/// Position, M = 3.
struct Position;

impl Sensor<6, 3> for Position {
    type Model = Cv3;
    type Aux = ();
    const NAME: &'static str = "position";
    const ANGLES: [bool; 3] = [false; 3];
    const JACOBIAN_SPARSITY: [[bool; 6]; 3] = [[true, false, false, false, false, false]; 3];
    const OPS_INNOVATION_TERMS: usize = 0;
    fn predict(x: &SVector<f64, 6>, _: &Accel, _: &(), _: &()) -> SVector<f64, 3> {
        x.fixed_rows::<3>(0).into_owned()
    }
    fn jacobian(_: &SVector<f64, 6>, _: &Accel, _: &(), _: &()) -> SMatrix<f64, 3, 6> {
        SMatrix::<f64, 3, 6>::from_fn(|r, c| if r == c { 1.0 } else { 0.0 })
    }
    fn innovation_terms(
        cov: &SMatrix<f64, 6, 6>,
        x: &SVector<f64, 6>,
        u: &Accel,
        p: &(),
        aux: &(),
    ) -> (SVector<f64, 3>, SMatrix<f64, 6, 3>, SMatrix<f64, 3, 3>) {
        terms(
            cov,
            Self::predict(x, u, p, aux),
            Self::jacobian(x, u, p, aux),
        )
    }
}

/// Range from the origin plus a lever `l`, M = 1 (nonlinear).
struct Range;

impl Sensor<6, 1> for Range {
    type Model = Cv3;
    type Aux = Lever;
    const NAME: &'static str = "range";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 6]; 1] = [[true, true, true, false, false, false]];
    const OPS_INNOVATION_TERMS: usize = 0;
    fn predict(x: &SVector<f64, 6>, _: &Accel, _: &(), aux: &Lever) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(x.fixed_rows::<3>(0).norm() + aux.l)
    }
    fn jacobian(x: &SVector<f64, 6>, _: &Accel, _: &(), _: &Lever) -> SMatrix<f64, 1, 6> {
        let p = x.fixed_rows::<3>(0);
        let n = p.norm().max(1e-9);
        SMatrix::<f64, 1, 6>::new(p[0] / n, p[1] / n, p[2] / n, 0.0, 0.0, 0.0)
    }
    fn innovation_terms(
        cov: &SMatrix<f64, 6, 6>,
        x: &SVector<f64, 6>,
        u: &Accel,
        p: &(),
        aux: &Lever,
    ) -> (SVector<f64, 1>, SMatrix<f64, 6, 1>, SMatrix<f64, 1, 1>) {
        terms(
            cov,
            Self::predict(x, u, p, aux),
            Self::jacobian(x, u, p, aux),
        )
    }
}

#[derive(Clone, Copy, Debug, Default)]
struct Nominal {
    x: [f64; 6],
}

impl NominalState<6> for Nominal {
    fn inject(&mut self, e: &SVector<f64, 6>) {
        for (v, d) in self.x.iter_mut().zip(e.iter()) {
            *v -= d;
        }
    }
}

fn new_filter(d: Discretization) -> Ekf<Cv3, 6> {
    let x0 = SVector::<f64, 6>::new(100.0, -50.0, 10.0, 1.0, 0.5, 0.0);
    let p0 = SMatrix::<f64, 6, 6>::from_diagonal(&SVector::<f64, 6>::new(
        25.0, 25.0, 25.0, 1.0, 1.0, 1.0,
    ));
    Ekf::new(x0, p0, (), Psd { q: 0.01 })
        .expect("valid setup")
        .with_discretization(d)
}

#[test]
fn predict_and_update_do_not_allocate() {
    // Everything constructed before counting starts.
    let mut filters = [
        new_filter(Discretization::FirstOrder),
        new_filter(Discretization::SecondOrder),
        new_filter(Discretization::VanLoan),
    ];
    filters[1]
        .set_sensor_gate::<Range, 1>(Some(Gate::new(0.99).expect("valid")))
        .expect("capacity");
    let mut esf = ErrorStateFilter::new(new_filter(Discretization::FirstOrder), Nominal::default());
    // Sensors reading the input rebuilt from the nominal before each update.
    let mut refreshed =
        ErrorStateFilter::new(new_filter(Discretization::FirstOrder), Nominal::default())
            .with_sensor_input(|n: &Nominal| Accel {
                ax: n.x[3],
                ay: n.x[4],
                az: n.x[5],
            });
    // A smoother's recording beside the filter (its epoch buffer sized at
    // the start).
    let mut recording =
        ErrorStateFilter::new(new_filter(Discretization::FirstOrder), Nominal::default());
    recording
        .start_recording(EpochFile::create(None).expect("temporary file"), 0.0)
        .expect("first order");
    let r3 = SMatrix::<f64, 3, 3>::identity() * 4.0;
    let r3_diag = SVector::<f64, 3>::new(4.0, 4.0, 4.0);
    let r1 = SMatrix::<f64, 1, 1>::new(1.0);
    let lever = Lever { l: 0.5 };
    let mut outcomes = [0usize; 4];

    let count = allocations(|| {
        for k in 0..1000 {
            let t = k as f64 * 0.01;
            let u = Accel {
                ax: t.sin(),
                ay: 0.1,
                az: -0.05,
            };
            for f in filters.iter_mut() {
                f.predict(0.01, &u).expect("finite step");
                let x = *f.state();
                let z3 = SVector::<f64, 3>::new(x[0] + 0.3, x[1] - 0.2, x[2] + 0.1);
                let rep = f
                    .update::<Position, 3>(&z3, &r3, &())
                    .expect("valid update");
                outcomes[usize::from(rep.accepted)] += 1;
                let rep = f
                    .update_sequential::<Position, 3>(&z3, &r3_diag, &())
                    .expect("valid update");
                outcomes[usize::from(rep.accepted)] += 1;
                let range = Range::predict(&x, &u, &(), &lever)[0];
                // Alternately consistent and a gross outlier (gated).
                let z1 = SVector::<f64, 1>::new(range + if k % 2 == 0 { 0.5 } else { 500.0 });
                let rep = f
                    .update::<Range, 1>(&z1, &r1, &lever)
                    .expect("valid update");
                outcomes[usize::from(rep.accepted)] += 1;
                // Refused inputs take the error path.
                outcomes[2] += usize::from(f.predict(-0.01, &u).is_err());
                let bad = SVector::<f64, 3>::new(f64::NAN, 0.0, 0.0);
                outcomes[3] += usize::from(f.update::<Position, 3>(&bad, &r3, &()).is_err());
            }
            let z3 = SVector::<f64, 3>::new(0.3, -0.2, 0.1);
            for f in [&mut esf, &mut recording, &mut refreshed] {
                f.predict(0.01, &u).expect("finite step");
                f.update::<Position, 3>(&z3, &r3, &())
                    .expect("valid update");
            }
        }
    });
    assert_eq!(count, 0, "heap allocations in predict/update");
    // The loop did what it claims: accepted, gated and refused updates.
    assert!(outcomes[0] >= 1500 && outcomes[1] >= 7500, "{outcomes:?}");
    assert_eq!((outcomes[2], outcomes[3]), (3000, 3000));
    // One reset at construction (non-zero initial error), one per update.
    assert_eq!(esf.resets(), 1001);
    assert_eq!(refreshed.resets(), 1001);
    // The recording took every step and every update.
    let file = recording.finish_recording().expect("recorded").expect("on");
    assert_eq!(file.borrow().len(), 1001);
    // Sanity: the counter does see allocations.
    assert!(allocations(|| drop(std::hint::black_box(vec![1u8; 16]))) >= 1);
}
