//! Covariance propagation `P <- Phi P Phi^T + Qd`: the generated sparse code
//! against dense nalgebra products in the same run (and, for SDINS-25, against a
//! hand-written structure-aware version).
//!
//! Variants per model (group `propagate/<model>`):
//! - `generated`: `Model::propagate_covariance`, which evaluates `F` and `Qd`
//!   itself from `(x, u, p, q, dt)`;
//! - `dense`: `Phi P Phi^T + Qd` with `Phi` and `Qd` precomputed outside the
//!   timing (the product alone; the baseline the ratios are taken against);
//! - `dense_with_model`: the same plus evaluating `jacobian` and `process_noise`
//!   each call (what a dense filter actually pays per step);
//! - `handwritten` (SDINS-25 only): blocks of `F dt` and `Qd` precomputed, only
//!   the 9 changed rows computed.
//!
//! Group `propagate/sdins25_precision`: the composed SDINS-25 generated in
//! `f64` (`generated_f64`, the baseline) and in `f32` (`generated_f32`,
//! `scalar f32;`) at the same operating point; `propagate/px4_ekf24_precision`
//! the same for PX4's 24-state model (`models::px4_ekf24`), which also has
//! the group `propagate/px4_ekf24` of the variants above, and two more:
//! `rotation_matrix` and `homogeneous_matrix`, the same model declared in
//! this crate with the rotation written as a matrix of the quaternion's
//! components (`common/px4_rotation_matrix.rs`).
//!
//! Run: `cargo bench -p models --bench propagation` (ratios: `scripts/bench.sh`).

mod common;
#[path = "common/px4_rotation_matrix.rs"]
mod px4_rotation_matrix;

use common::*;
use criterion::{criterion_group, Criterion};
use models::leveling::model::Leveling6;
use models::marker::model::Marker9;
use models::px4_ekf24::{Px4Ekf24, Px4Ekf24Single};
use models::sdins25::model::Sdins25;
use models::vehicles::sdins::{Sdins25Composed, Sdins25Single};
use nav_runtime::model::Model;
use nav_runtime::model::Record;
use nav_runtime::nalgebra::{SMatrix, SVector};
use px4_rotation_matrix::{
    homogeneous_matrix_point, rotation_matrix_point, Px4HomogeneousMatrix, Px4RotationMatrix,
};
use std::hint::black_box;

/// Covariance steps between restores of the initial `P` (10 s at 100 Hz).
const RESET_EVERY: u64 = 1000;

fn bench_model<Mo: Model<N>, const N: usize>(
    c: &mut Criterion,
    name: &str,
    point: (SVector<f64, N>, Mo::Input, Mo::Params, Mo::Noise),
    p0: SMatrix<f64, N, N>,
    dt: f64,
    extra: impl FnOnce(&mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>),
) {
    let (x, u, par, q) = point;
    let phi = dense_phi::<Mo, N>(&x, &u, &par, dt);
    let qd = Mo::process_noise(&x, &u, &par, &q, dt);

    // The variants agree before anything is timed.
    let mut generated = p0;
    generated_propagate::<Mo, N>(&mut generated, &x, &u, &par, &q, dt);
    let mut dense = p0;
    dense_propagate(&mut dense, &phi, &qd);
    let mut dense_model = p0;
    dense_propagate_with_model::<Mo, N>(&mut dense_model, &x, &u, &par, &q, dt);
    assert!(
        rel_diff(&generated, &dense) < 1e-12,
        "{name}: generated != dense"
    );
    assert!(
        rel_diff(&dense_model, &dense) < 1e-12,
        "{name}: dense variants differ"
    );

    let mut g = c.benchmark_group(format!("propagate/{name}"));
    g.bench_function("generated", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &p0, RESET_EVERY, |p| {
                generated_propagate::<Mo, N>(
                    p,
                    black_box(&x),
                    black_box(&u),
                    black_box(&par),
                    black_box(&q),
                    dt,
                )
            })
        })
    });
    g.bench_function("dense", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &p0, RESET_EVERY, |p| {
                dense_propagate(p, black_box(&phi), black_box(&qd))
            })
        })
    });
    g.bench_function("dense_with_model", |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, &p0, RESET_EVERY, |p| {
                dense_propagate_with_model::<Mo, N>(
                    p,
                    black_box(&x),
                    black_box(&u),
                    black_box(&par),
                    black_box(&q),
                    dt,
                )
            })
        })
    });
    extra(&mut g);
    g.finish();
}

fn propagation(c: &mut Criterion) {
    let (x, u, par, q) = sdins25_point();
    let p0 = sdins25_covariance();
    let f = Sdins25::jacobian(&x, &u, &par, DT_SDINS);
    let qd = Sdins25::process_noise(&x, &u, &par, &q, DT_SDINS);
    let hand = HandWrittenSdins25::new(&f, &qd, DT_SDINS);
    let mut by_hand = p0;
    hand.propagate(&mut by_hand);
    let mut generated = p0;
    Sdins25::propagate_covariance(&mut generated, &x, &u, &par, &q, DT_SDINS);
    assert!(
        rel_diff(&by_hand, &generated) < 1e-12,
        "hand-written != generated"
    );

    bench_model::<Sdins25, 25>(c, "sdins25", (x, u, par, q), p0, DT_SDINS, |g| {
        g.bench_function("handwritten", |b| {
            b.iter_custom(|iters| {
                time_in_place(iters, &p0, RESET_EVERY, |p| black_box(&hand).propagate(p))
            })
        });
    });
    precision(c);
    bench_model::<Leveling6, 6>(
        c,
        "leveling6",
        leveling6_point(),
        leveling6_covariance(),
        0.01,
        |_| {},
    );
    bench_model::<Marker9, 9>(
        c,
        "marker9",
        marker9_point(),
        marker9_covariance(),
        0.02,
        |_| {},
    );
    let p0 = px4_ekf24_covariance();
    let (x, u, par, q) = px4_ekf24_point();
    let matrix = rotation_matrix_point(&u, &par, &q);
    let homogeneous = homogeneous_matrix_point(&u, &par, &q);
    // The textbook matrix is the builtin's function: the same result.
    let (mut builtin, mut written) = (p0, p0);
    generated_propagate::<Px4Ekf24, 24>(&mut builtin, &x, &u, &par, &q, 0.01);
    generated_propagate::<Px4RotationMatrix, 24>(
        &mut written,
        &x,
        &matrix.0,
        &matrix.1,
        &matrix.2,
        0.01,
    );
    assert!(
        rel_diff(&builtin, &written) < 1e-12,
        "rotation matrix != quat_to_dcm"
    );
    bench_model::<Px4Ekf24, 24>(c, "px4_ekf24", (x, u, par, q), p0, 0.01, |g| {
        bench_declaration::<Px4RotationMatrix>(g, "rotation_matrix", &x, &matrix, &p0);
        bench_declaration::<Px4HomogeneousMatrix>(g, "homogeneous_matrix", &x, &homogeneous, &p0);
    });
    px4_precision(c);
}

/// The generated propagation of another declaration of PX4's model, as
/// variant `name` of group `g`.
fn bench_declaration<Mo: Model<24>>(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    x: &SVector<f64, 24>,
    (u, par, q): &(Mo::Input, Mo::Params, Mo::Noise),
    p0: &SMatrix<f64, 24, 24>,
) {
    g.bench_function(name, |b| {
        b.iter_custom(|iters| {
            time_in_place(iters, p0, RESET_EVERY, |p| {
                generated_propagate::<Mo, 24>(
                    p,
                    black_box(x),
                    black_box(u),
                    black_box(par),
                    black_box(q),
                    0.01,
                )
            })
        })
    });
}

/// PX4's model in both precisions, at the same point.
type Px4Single = (
    SVector<f32, 24>,
    <Px4Ekf24Single as Model<24, f32>>::Input,
    <Px4Ekf24Single as Model<24, f32>>::Params,
    <Px4Ekf24Single as Model<24, f32>>::Noise,
);

fn px4_single_point() -> Px4Single {
    let (x, u, p, q) = px4_ekf24_point();
    (
        x.map(|v| v as f32),
        Record::from_fn(|i| u.get(i)),
        Record::from_fn(|i| p.get(i)),
        Record::from_fn(|i| q.get(i)),
    )
}

#[inline(never)]
fn px4_propagate_f64(
    cov: &mut SMatrix<f64, 24, 24>,
    point: &(
        SVector<f64, 24>,
        <Px4Ekf24 as Model<24>>::Input,
        <Px4Ekf24 as Model<24>>::Params,
        <Px4Ekf24 as Model<24>>::Noise,
    ),
) {
    let (x, u, p, q) = point;
    Px4Ekf24::propagate_covariance(cov, x, u, p, q, 0.01);
}

#[inline(never)]
fn px4_propagate_f32(cov: &mut SMatrix<f32, 24, 24>, point: &Px4Single) {
    let (x, u, p, q) = point;
    Px4Ekf24Single::propagate_covariance(cov, x, u, p, q, 0.01);
}

fn px4_precision(c: &mut Criterion) {
    let (p64, p32) = (px4_ekf24_point(), px4_single_point());
    let c64 = px4_ekf24_covariance();
    let c32 = c64.map(|v| v as f32);
    let (mut a, mut b) = (c64, c32);
    px4_propagate_f64(&mut a, &p64);
    px4_propagate_f32(&mut b, &p32);
    let worst = (0..24)
        .map(|i| (a[(i, i)] - f64::from(b[(i, i)])).abs() / a[(i, i)])
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "f32 propagation differs from f64 by {worst}");
    let mut g = c.benchmark_group("propagate/px4_ekf24_precision");
    g.bench_function("generated_f64", |bch| {
        bch.iter_custom(|iters| {
            time_in_place(iters, &c64, RESET_EVERY, |p| {
                px4_propagate_f64(p, black_box(&p64))
            })
        })
    });
    g.bench_function("generated_f32", |bch| {
        bch.iter_custom(|iters| {
            time_in_place(iters, &c32, RESET_EVERY, |p| {
                px4_propagate_f32(p, black_box(&p32))
            })
        })
    });
    g.finish();
}

/// The SDINS-25 operating point and covariance for the composed model in
/// both precisions (records converted by position: the composed records
/// have the monolithic names and order).
type PrecisionPoint = (
    <Sdins25Composed as Model<25>>::Input,
    <Sdins25Single as Model<25, f32>>::Input,
    <Sdins25Composed as Model<25>>::Noise,
    <Sdins25Single as Model<25, f32>>::Noise,
    SMatrix<f64, 25, 25>,
);

fn precision_point() -> PrecisionPoint {
    let (_, u, _, q) = sdins25_point();
    (
        Record::from_fn(|i| u.get(i)),
        Record::from_fn(|i| u.get(i)),
        Record::from_fn(|i| q.get(i)),
        Record::from_fn(|i| q.get(i)),
        sdins25_covariance(),
    )
}

#[inline(never)]
fn propagate_f64(
    cov: &mut SMatrix<f64, 25, 25>,
    u: &<Sdins25Composed as Model<25>>::Input,
    q: &<Sdins25Composed as Model<25>>::Noise,
) {
    Sdins25Composed::propagate_covariance(
        cov,
        &SVector::zeros(),
        u,
        &Default::default(),
        q,
        DT_SDINS,
    );
}

#[inline(never)]
fn propagate_f32(
    cov: &mut SMatrix<f32, 25, 25>,
    u: &<Sdins25Single as Model<25, f32>>::Input,
    q: &<Sdins25Single as Model<25, f32>>::Noise,
) {
    Sdins25Single::propagate_covariance(
        cov,
        &SVector::zeros(),
        u,
        &Default::default(),
        q,
        DT_SDINS as f32,
    );
}

fn precision(c: &mut Criterion) {
    let (u64_, u32_, q64, q32, p0) = precision_point();
    let p0_single = p0.map(|v| v as f32);
    let (mut a, mut b) = (p0, p0_single);
    propagate_f64(&mut a, &u64_, &q64);
    propagate_f32(&mut b, &u32_, &q32);
    let worst = (0..25)
        .map(|i| (a[(i, i)] - f64::from(b[(i, i)])).abs() / a[(i, i)])
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "f32 propagation differs from f64 by {worst}");
    let mut g = c.benchmark_group("propagate/sdins25_precision");
    g.bench_function("generated_f64", |bch| {
        bch.iter_custom(|iters| {
            time_in_place(iters, &p0, RESET_EVERY, |p| {
                propagate_f64(p, black_box(&u64_), black_box(&q64))
            })
        })
    });
    g.bench_function("generated_f32", |bch| {
        bch.iter_custom(|iters| {
            time_in_place(iters, &p0_single, RESET_EVERY, |p| {
                propagate_f32(p, black_box(&u32_), black_box(&q32))
            })
        })
    });
    g.finish();
}

/// `PROPAGATE_ONLY=<model>/<variant>` (e.g. `sdins25/generated`): skip criterion
/// and call that variant `PROPAGATE_CALLS` times (default 1000), for
/// instruction counting under callgrind with `--toggle-collect` on the variant's
/// function (see `scripts/bench.sh --callgrind`).
fn only(which: &str) {
    let calls: u64 = std::env::var("PROPAGATE_CALLS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000);
    fn run<Mo: Model<N>, const N: usize>(
        variant: &str,
        calls: u64,
        point: (SVector<f64, N>, Mo::Input, Mo::Params, Mo::Noise),
        p0: SMatrix<f64, N, N>,
        dt: f64,
    ) {
        let (x, u, par, q) = point;
        let phi = dense_phi::<Mo, N>(&x, &u, &par, dt);
        let qd = Mo::process_noise(&x, &u, &par, &q, dt);
        let hand = (N == 25).then(|| {
            let f = Mo::jacobian(&x, &u, &par, dt);
            let f = SMatrix::<f64, 25, 25>::from_fn(|i, j| f[(i, j)]);
            let qd = SMatrix::<f64, 25, 25>::from_fn(|i, j| qd[(i, j)]);
            HandWrittenSdins25::new(&f, &qd, dt)
        });
        let mut p25 =
            SMatrix::<f64, 25, 25>::from_fn(|i, j| if i < N && j < N { p0[(i, j)] } else { 0.0 });
        let mut p = p0;
        for _ in 0..calls {
            match variant {
                "generated" => {
                    generated_propagate::<Mo, N>(black_box(&mut p), &x, &u, &par, &q, dt)
                }
                "dense" => dense_propagate(black_box(&mut p), &phi, &qd),
                "dense_with_model" => {
                    dense_propagate_with_model::<Mo, N>(black_box(&mut p), &x, &u, &par, &q, dt)
                }
                "handwritten" => hand
                    .as_ref()
                    .expect("SDINS-25 only")
                    .propagate(black_box(&mut p25)),
                _ => panic!("unknown variant {variant}"),
            }
        }
        black_box((p, p25));
    }
    match which.split_once('/') {
        Some(("sdins25_precision", v)) => {
            let (u64_, u32_, q64, q32, p0) = precision_point();
            let (mut a, mut b) = (p0, p0.map(|v| v as f32));
            for _ in 0..calls {
                match v {
                    "generated_f64" => propagate_f64(black_box(&mut a), &u64_, &q64),
                    "generated_f32" => propagate_f32(black_box(&mut b), &u32_, &q32),
                    _ => panic!("unknown variant {v}"),
                }
            }
            black_box((a, b));
        }
        Some(("px4_ekf24_precision", v)) => {
            let (p64, p32) = (px4_ekf24_point(), px4_single_point());
            let mut a = px4_ekf24_covariance();
            let mut b = a.map(|v| v as f32);
            for _ in 0..calls {
                match v {
                    "generated_f64" => px4_propagate_f64(black_box(&mut a), &p64),
                    "generated_f32" => px4_propagate_f32(black_box(&mut b), &p32),
                    _ => panic!("unknown variant {v}"),
                }
            }
            black_box((a, b));
        }
        Some(("px4_ekf24", v)) => {
            run::<Px4Ekf24, 24>(v, calls, px4_ekf24_point(), px4_ekf24_covariance(), 0.01)
        }
        Some(("px4_rotation_matrix", v)) => {
            let (x, u, p, q) = px4_ekf24_point();
            let (u, p, q) = rotation_matrix_point(&u, &p, &q);
            run::<Px4RotationMatrix, 24>(v, calls, (x, u, p, q), px4_ekf24_covariance(), 0.01)
        }
        Some(("px4_homogeneous_matrix", v)) => {
            let (x, u, p, q) = px4_ekf24_point();
            let (u, p, q) = homogeneous_matrix_point(&u, &p, &q);
            run::<Px4HomogeneousMatrix, 24>(v, calls, (x, u, p, q), px4_ekf24_covariance(), 0.01)
        }
        Some(("sdins25", v)) => {
            run::<Sdins25, 25>(v, calls, sdins25_point(), sdins25_covariance(), DT_SDINS)
        }
        Some(("leveling6", v)) => {
            run::<Leveling6, 6>(v, calls, leveling6_point(), leveling6_covariance(), 0.01)
        }
        Some(("marker9", v)) => {
            run::<Marker9, 9>(v, calls, marker9_point(), marker9_covariance(), 0.02)
        }
        _ => panic!(
            "PROPAGATE_ONLY={which}: expected <sdins25|leveling6|marker9|px4_ekf24|px4_rotation_matrix|px4_homogeneous_matrix>/<variant>"
        ),
    }
}

criterion_group!(benches, propagation);

fn main() {
    if let Ok(which) = std::env::var("PROPAGATE_ONLY") {
        only(&which);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
