//! The tuning loop on a model whose likelihood is known: a DVL-like sensor
//! with a true sigma of 0.1 and a filter uncertainty that hides part of it,
//! a parameter that changes nothing (flat likelihood), and a filter that
//! diverges below a sigma.

use nav_runtime::innovations::{InnovationStatistics, InnovationTotals};
use nav_runtime::log::{LogFiles, LogSource, Strictness};
use nav_runtime::nalgebra::{SMatrix, SVector};

use super::*;
use crate::innovations::SensorInnovations;
use crate::temp_dir::TempDir;
use crate::{ReplayModel, ReplayOptions, ReplayOutput};

/// The true noise sigma of the sensor.
const TRUE_SIGMA: f64 = 0.1;
/// `H P H^T` of every update (the filter's own share of `S`).
const HPH: f64 = 0.002;

/// Innovations of a consistent world: `nu ~ N(0, HPH + TRUE_SIGMA^2)`,
/// drawn once (a fixed sequence of standard normal quantiles), weighed by
/// a filter that assumes `sigma`.
struct Known {
    /// Below this sigma the filter "diverges".
    diverges_below: f64,
}

/// Replayed from the log read whole ([`LogSource::whole`]), with the sigmas
/// the tuning sets, not those on disk.
impl ReplayModel for Known {
    fn name(&self) -> &'static str {
        "known"
    }
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        _: &ReplayOptions,
        _: Option<&std::path::Path>,
    ) -> Result<ReplayOutput, RunError> {
        let log = source.whole()?;
        let sigma = log.meta.sensors.dvl.map_or(f64::NAN, |s| s.noise_sigma);
        if sigma < self.diverges_below {
            return Err(RunError::diverged(format!("sigma {sigma} too small")));
        }
        let mut totals = InnovationTotals::default();
        for z in standard_normals(2000) {
            let nu = z * (HPH + TRUE_SIGMA * TRUE_SIGMA).sqrt();
            totals.add(&InnovationStatistics::of(
                &SVector::<f64, 1>::new(nu),
                &SMatrix::<f64, 1, 1>::new(HPH + sigma * sigma),
                &SMatrix::<f64, 1, 1>::new(sigma * sigma),
            ));
        }
        Ok(dvl_output(sigma, totals))
    }
}

/// A replay whose one sensor, the DVL with noise sigma `sigma`, had
/// innovations `totals`.
fn dvl_output(sigma: f64, totals: InnovationTotals) -> ReplayOutput {
    ReplayOutput {
        innovations: vec![SensorInnovations {
            sensor: "dvl".into(),
            noise_sigma: Some(sigma),
            gated: 0,
            setting: ("meta.toml".into(), "sensors.dvl.noise_sigma".into()),
            totals,
        }],
        ..ReplayOutput::default()
    }
}

/// `n` evenly spaced quantiles of the logistic approximation of N(0, 1),
/// scaled to a sample variance of exactly 1: deterministic draws.
fn standard_normals(n: usize) -> Vec<f64> {
    let z: Vec<f64> = (0..n)
        .map(|k| {
            let p = (k as f64 + 0.5) / n as f64;
            (p / (1.0 - p)).ln()
        })
        .collect();
    let scale = (z.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
    z.into_iter().map(|z| z / scale).collect()
}

/// The sensor of [`Known`] where, on every other update, the filter's own
/// share of `S` is the gyro noise's, `K q` (`q` the gyro noise variance):
/// the sensor's sigma and the gyro noise act on the same innovations there
/// and trade against each other. The truth: `TRUE_SIGMA` and a gyro sigma
/// of `GYRO_SIGMA`, whose share equals the noise's.
struct Confounded {
    updates: usize,
    /// Every other update has the filter's share `HPH` (the sensor alone);
    /// otherwise every update is the gyro noise's.
    plain_half: bool,
}

const GYRO_SIGMA: f64 = 1e-6;
const K: f64 = TRUE_SIGMA * TRUE_SIGMA / (GYRO_SIGMA * GYRO_SIGMA);

impl ReplayModel for Confounded {
    fn name(&self) -> &'static str {
        "confounded"
    }
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        _: &ReplayOptions,
        _: Option<&std::path::Path>,
    ) -> Result<ReplayOutput, RunError> {
        let sigma = source
            .meta()
            .sensors
            .dvl
            .map_or(f64::NAN, |s| s.noise_sigma);
        let gyro = source
            .meta()
            .sensors
            .imu
            .map_or(f64::NAN, |s| s.gyro_noise_sigma);
        let mut totals = InnovationTotals::default();
        let r = |s: f64| s * s;
        for (k, z) in standard_normals(self.updates).into_iter().enumerate() {
            let (filter_share, true_share) = if self.plain_half && k % 2 == 0 {
                (HPH, HPH)
            } else {
                (K * gyro * gyro, K * GYRO_SIGMA * GYRO_SIGMA)
            };
            let nu = z * (true_share + r(TRUE_SIGMA)).sqrt();
            totals.add(&InnovationStatistics::of(
                &SVector::<f64, 1>::new(nu),
                &SMatrix::<f64, 1, 1>::new(filter_share + r(sigma)),
                &SMatrix::<f64, 1, 1>::new(r(sigma)),
            ));
        }
        Ok(dvl_output(sigma, totals))
    }
}

/// Eq. T5: the standard errors of the sensor's sigma and the gyro noise
/// are those of their joint information, larger than each one's own. The
/// expected values are worked out from the model (the tuning's secant
/// curvature and cross term over a factor of 2, eq. T4 for the sensor).
#[test]
fn parameters_on_the_same_innovations_report_their_joint_standard_errors() {
    let (_d, files) = log_with(TRUE_SIGMA);
    let t = tune_confounded(
        &files,
        Confounded {
            updates: 2000,
            plain_half: true,
        },
        &["sensors.dvl.noise_sigma", "sensors.imu.gyro_noise_sigma"],
    );
    let n = 1000.0;
    let r = TRUE_SIGMA * TRUE_SIGMA;
    let s_plain = HPH + r;
    let s_mixed = 2.0 * r;
    // A half's log-likelihood per update at `S` with innovation variance `v`.
    let l = |s: f64, v: f64| -0.5 * (s.ln() + v / s);
    let (up, down) = (4.0 * r + r, 0.25 * r + r);
    let step = core::f64::consts::LN_2;
    let j_gyro =
        -n * (l(up, s_mixed) - 2.0 * l(s_mixed, s_mixed) + l(down, s_mixed)) / (step * step);
    let gradient = |s: f64| r * (s_mixed / (s * s) - 1.0 / s);
    let j_cross = -n * (gradient(up) - gradient(down)) / (2.0 * step);
    let j_dvl = 2.0 * n * ((r / s_plain).powi(2) + (r / s_mixed).powi(2));
    let det = j_dvl * j_gyro - j_cross * j_cross;
    let expected = [
        (
            "sensors.dvl.noise_sigma",
            (j_gyro / det).sqrt(),
            j_dvl.sqrt().recip(),
        ),
        (
            "sensors.imu.gyro_noise_sigma",
            (j_dvl / det).sqrt(),
            j_gyro.sqrt().recip(),
        ),
    ];
    for (key, joint, own) in expected {
        let p = t.parameters.iter().find(|p| p.key == key).unwrap();
        assert!(p.not_identifiable.is_none(), "{p:?}");
        assert!((p.value / p.initial - 1.0).abs() < 0.05, "{p:?}");
        assert!(
            (p.log_standard_error / joint - 1.0).abs() < 0.05,
            "{key}: {} against {joint} (own {own})",
            p.log_standard_error
        );
        assert!(joint > 1.1 * own, "{key}: {joint} {own}");
    }
}

/// Two parameters that each 100 updates tell on its own (standard errors
/// of about 0.1) but that act on the same innovations at every update are
/// not identified taken together: both keep their given values and say why.
#[test]
fn parameters_that_trade_against_each_other_are_not_identified() {
    let (_d, files) = log_with(TRUE_SIGMA);
    let t = tune_confounded(
        &files,
        Confounded {
            updates: 100,
            plain_half: false,
        },
        &["sensors.dvl.noise_sigma", "sensors.imu.gyro_noise_sigma"],
    );
    for p in &t.parameters {
        let why = p.not_identifiable.as_deref().unwrap_or_default();
        assert!(why.contains("act on the same innovations"), "{p:?}");
        assert_eq!(p.value, p.initial, "{p:?}");
        assert!(p.log_standard_error > MAX_LOG_SIGMA_ERROR, "{p:?}");
    }
}

/// A parameter the log tells only roughly (15 updates on the gyro noise: a
/// standard error of `ln sigma` near 0.37, above the 0.25 that counts as
/// identified) keeps its tuned value when the log rejects the given one
/// (started 100 times too large, more than 3 standard errors away), with
/// a note saying how roughly it is known; started 1.3 times off, within
/// what the log can tell, it goes back to the given value, said so.
#[test]
fn a_roughly_known_parameter_keeps_its_value_when_the_log_rejects_the_given_one() {
    // (start over the truth, kept)
    let cases = [(100.0, true), (1.3, false)];
    for (factor, kept) in cases {
        let start = factor * GYRO_SIGMA;
        let t = tune_gyro_from(start, 30);
        let p = &t.parameters[0];
        let se = p.log_standard_error;
        assert!((MAX_LOG_SIGMA_ERROR..0.6).contains(&se), "{factor}: {p:?}");
        let note = t.notes.iter().any(|n| n.contains("known only to a factor"));
        if kept {
            assert!(p.not_identifiable.is_none(), "{p:?}");
            assert!(note, "{:?}", t.notes);
            let off = (p.value / GYRO_SIGMA).ln().abs();
            assert!(off < REJECTED_AT * se, "{p:?}: {off} in ln from the truth");
        } else {
            assert!(p.not_identifiable.is_some(), "{p:?}");
            assert!(!note, "{:?}", t.notes);
            assert_eq!(p.value, start);
        }
    }
}

/// A parameter the log identifies, started within a factor of 2 of its
/// optimum, where neither probe (doubled, halved) is better by
/// `SIGNIFICANT`, is still taken to the top of its likelihood, not left
/// where it started (5.4 standard errors from the optimum). The top of the
/// secant over the first probes, the point whose doubled and halved
/// values are equally likely, is 3.9 standard errors off, as the skew of a
/// variance's likelihood sets it; over the refining probes (a quarter as
/// far) a sixteenth of that, and the convergence rule stops within a
/// quarter of a standard error: within half of one in all. The standard
/// error is the secant's over a factor of 2, within 20 % of the local
/// Fisher information's, `1 / sqrt(1000 / 2)`.
#[test]
fn an_identified_parameter_near_its_optimum_reaches_it() {
    // The log-likelihood in `theta = ln q_sigma` of the odd updates (the
    // ones the gyro acts on), whose mean square innovation is exactly
    // `2 r`; the even ones do not depend on it. Its top is at the truth.
    let r = TRUE_SIGMA * TRUE_SIGMA;
    let l = |theta: f64| {
        let s = K * (2.0 * theta).exp() + r;
        -0.5 * 1000.0 * (s.ln() + 2.0 * r / s)
    };
    let optimum = GYRO_SIGMA.ln();
    let h = core::f64::consts::LN_2;
    // The wide secant's top: l(theta + h) = l(theta - h), by bisection.
    let (mut lo, mut hi) = (optimum - 1.0, optimum + 1.0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if l(mid + h) > l(mid - h) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let fisher = (1000.0f64 / 2.0).sqrt().recip();
    let secant_top = (0.5 * (lo + hi) - optimum) / fisher;
    assert!((-4.0..-3.9).contains(&secant_top), "{secant_top}");
    for start in [1.3 * GYRO_SIGMA, GYRO_SIGMA / 1.3] {
        let t = tune_gyro_from(start, 2000);
        let p = &t.parameters[0];
        assert!(p.not_identifiable.is_none(), "{p:?}");
        assert_eq!(p.initial, start);
        assert!(t.converged, "{t:?}");
        let se = p.log_standard_error;
        assert!((se / fisher - 1.0).abs() < 0.2, "{se} against {fisher}");
        assert!((start.ln() - optimum).abs() > 5.0 * se);
        let off = (p.value.ln() - optimum).abs();
        assert!(
            off < 0.5 * se,
            "start {start}: {} ({off} in ln from the optimum, standard error {se})",
            p.value
        );
    }
}

/// The tuning of the gyro noise alone of the [`Confounded`] model with
/// every other update on it, over `updates` updates, started at `start`.
fn tune_gyro_from(start: f64, updates: usize) -> Tuning {
    let (d, _) = log_with(TRUE_SIGMA);
    let meta = std::fs::read_to_string(d.0.join("meta.toml")).unwrap();
    let meta = meta.replace(
        "gyro_noise_sigma = 1e-6",
        &format!("gyro_noise_sigma = {start:?}"),
    );
    std::fs::write(d.0.join("meta.toml"), meta).unwrap();
    let files = LogFiles::open(&d.0, Strictness::Strict).unwrap();
    tune_confounded(
        &files,
        Confounded {
            updates,
            plain_half: true,
        },
        &["sensors.imu.gyro_noise_sigma"],
    )
}

/// The tuning of `params` of the [`Confounded`] model over `files`.
fn tune_confounded(files: &LogFiles, model: Confounded, params: &[&str]) -> Tuning {
    tune(
        &LogTuning::new(&model, files, ReplayOptions::default()).unwrap(),
        &TuneOptions {
            params: params.iter().map(|p| p.to_string()).collect(),
            ..TuneOptions::default()
        },
        &|_, _| {},
    )
    .unwrap()
}

fn log_with(dvl_sigma: f64) -> (TempDir, LogFiles) {
    let d = TempDir::new("tune-known");
    let meta = format!(
        "[initial]\nlat = 0.6\nlon = 2.2\ndepth = 10.0\n\n[sensors.imu]\ngyro_noise_sigma = 1e-6\naccel_noise_sigma = 1e-3\n\n[sensors.dvl]\nnoise_sigma = {dvl_sigma:?}\n"
    );
    std::fs::write(d.0.join("meta.toml"), meta).unwrap();
    let imu = "t,gx,gy,gz,ax,ay,az\n0.0,0,0,0,0,0,-9.8\n0.01,0,0,0,0,0,-9.8\n";
    std::fs::write(d.0.join("imu.csv"), imu).unwrap();
    let files = LogFiles::open(&d.0, Strictness::Strict).unwrap();
    (d, files)
}

#[test]
fn a_sensor_sigma_is_found_from_ten_times_either_side_and_a_flat_parameter_stays() {
    // (given sigma, the filter diverges below)
    let cases = [(1.0, 0.0), (0.01, 0.0), (0.001, 0.005)];
    for (given, diverges_below) in cases {
        let (_d, files) = log_with(given);
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let known = Known { diverges_below };
        let t = tune(
            &LogTuning::new(&known, &files, ReplayOptions::default()).unwrap(),
            &TuneOptions::default(),
            &|done, budget| {
                assert!(done <= budget);
                calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            },
        )
        .unwrap();
        assert!(t.replays <= 30, "{given}: {}", t.replays);
        assert!(calls.into_inner() > 0);
        let dvl = &t
            .parameters
            .iter()
            .find(|p| p.key == "sensors.dvl.noise_sigma")
            .unwrap();
        assert!(dvl.not_identifiable.is_none(), "{given}: {dvl:?}");
        assert!(
            (dvl.value / TRUE_SIGMA - 1.0).abs() < 0.05,
            "{given}: {dvl:?}"
        );
        assert!(dvl.log_standard_error < 0.05, "{dvl:?}");
        // The IMU's sigmas change nothing here: flat, kept as given.
        for key in [
            "sensors.imu.gyro_noise_sigma",
            "sensors.imu.accel_noise_sigma",
        ] {
            let p = t.parameters.iter().find(|p| p.key == key).unwrap();
            assert!(
                p.not_identifiable.as_deref().unwrap().contains("flat"),
                "{p:?}"
            );
            assert_eq!(p.value, p.initial, "{p:?}");
        }
        assert!(t.converged, "{given}");
        let after = t.nis["dvl"].1.unwrap();
        assert!((after - 1.0).abs() < 0.05, "{given}: NIS after {after}");
        // A start where the filter diverged has no "before", and says so.
        assert_eq!(
            t.log_likelihood.0.is_none(),
            given < diverges_below,
            "{given}"
        );
        assert_eq!(
            t.notes.len(),
            usize::from(given < diverges_below),
            "{:?}",
            t.notes
        );
    }
}

#[test]
fn a_filter_that_diverges_from_every_start_is_an_error_saying_so() {
    let (_d, files) = log_with(0.001);
    let e = tune(
        &LogTuning::new(
            &Known {
                diverges_below: 10.0,
            },
            &files,
            ReplayOptions::default(),
        )
        .unwrap(),
        &TuneOptions::default(),
        &|_, _| {},
    )
    .unwrap_err();
    assert!(matches!(e, RunError::Diverged { .. }), "{e}");
    assert!(e.to_string().contains("nothing to tune from"), "{e}");
}

#[test]
fn the_budget_of_replays_is_kept() {
    for max_replays in [2, 3, 5, 8] {
        let (_d, files) = log_with(1.0);
        let t = tune(
            &LogTuning::new(
                &Known {
                    diverges_below: 0.0,
                },
                &files,
                ReplayOptions::default(),
            )
            .unwrap(),
            &TuneOptions {
                max_replays,
                ..TuneOptions::default()
            },
            &|_, _| {},
        )
        .unwrap();
        assert!(t.replays <= max_replays, "{max_replays}: {}", t.replays);
    }
}

/// A declared process noise is tuned per block: a scalar, or a vector's
/// scalars scaled together; a block with a zero has no scale to find.
#[test]
fn noise_is_tuned_per_block() {
    let names = [
        "speed_noise",
        "current_noise[0]",
        "current_noise[1]",
        "drift[0]",
        "drift[1]",
    ];
    let values = [0.1, 1e-8, 2e-8, 0.0, 1.0];
    assert_eq!(
        noise_parameters(&names, &values),
        vec![
            ("noise.speed_noise".to_string(), 0.1),
            ("noise.current_noise".to_string(), 1e-8),
        ]
    );
    let cases: [(&str, f64, [f64; 5]); 3] = [
        ("noise.current_noise", 1e-6, [0.1, 1e-6, 2e-6, 0.0, 1.0]),
        ("noise.speed_noise", 0.4, [0.4, 1e-8, 2e-8, 0.0, 1.0]),
        // A block with a zero first scalar is not scaled.
        ("noise.drift", 3.0, values),
    ];
    for (key, value, want) in cases {
        let mut got = values;
        with_noise_values(&names, &mut got, |k| (k == key).then_some(value));
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() <= 1e-15 * w.abs(), "{key}: {got:?}");
        }
    }
}
