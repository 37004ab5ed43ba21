use super::*;
use crate::imu::{ImuModel, ImuRate, ImuSpec};
use crate::testmodels::Gauss;
use nalgebra::Vector3;

const G: f64 = 9.80665;

/// Issue 35, item 2: the estimator against an established implementation.
/// The fixture (tests/fixtures/allan, made by its `make_fixture.py` with
/// `allantools` 2024.06) holds a 3000-sample series and allantools' `oadev`
/// of it at 131 cluster sizes; ours must agree to 1e-9 relative, and count
/// the same number of second differences.
#[test]
fn oadev_matches_allantools() {
    let series: Vec<f64> = include_str!("../../../tests/fixtures/allan/series.csv")
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.parse().unwrap())
        .collect();
    assert_eq!(series.len(), 3000);
    let x = phase(&series, 0.01);
    let mut compared = 0;
    for line in include_str!("../../../tests/fixtures/allan/oadev.csv")
        .lines()
        .filter(|l| !l.starts_with('#'))
    {
        let f: Vec<&str> = line.split(',').collect();
        let (m, tau, dev, terms): (usize, f64, f64, usize) = (
            f[0].parse().unwrap(),
            f[1].parse().unwrap(),
            f[2].parse().unwrap(),
            f[3].parse().unwrap(),
        );
        let p = overlapping(&x, 0.01, m).unwrap();
        assert!((p.tau_s - tau).abs() <= 1e-12 * tau, "m {m}");
        assert_eq!(p.terms, terms, "m {m}");
        let rel = (p.deviation - dev).abs() / dev;
        assert!(
            rel <= 1e-9,
            "m {m}: ours {} allantools {dev} (relative {rel:e})",
            p.deviation
        );
        compared += 1;
    }
    assert_eq!(compared, 131);
}

/// Allan variance of a first-order Gauss-Markov rate of variance `s2` and
/// correlation time `t` (s) at cluster time `tau`:
/// `(2 s2 t^2 / tau^2) (tau/t - 3/2 + 2 e^(-tau/t) - e^(-2 tau/t) / 2)`.
fn gauss_markov_avar(s2: f64, t: f64, tau: f64) -> f64 {
    let a = tau / t;
    2.0 * s2 * t * t / (tau * tau) * (a - 1.5 + 2.0 * (-a).exp() - 0.5 * (-2.0 * a).exp())
}

/// The simulated record: a static IMU (FRD, gravity `f = [0, 0, -g]`) with
/// the white noise and constant bias of [`ImuModel`] (the simulation's error
/// model), plus per axis a rate random walk and three Gauss-Markov
/// processes (correlation times 5, 25, 125 s: a bias that wanders, which
/// gives the curve a bottom).
struct Truth {
    period: f64,
    /// White noise density per triad (gyro, accel), unit/s^(1/2).
    white: [f64; 2],
    /// Rate random walk per axis, unit/s^(3/2).
    walk: [f64; 6],
    /// Gauss-Markov sigma per axis (each of the three processes), unit.
    markov: [f64; 6],
}

const MARKOV_TIMES: [f64; 3] = [5.0, 25.0, 125.0];

impl Truth {
    fn record(&self, samples: usize, seed: u64) -> Vec<[f64; 6]> {
        let dt = self.period;
        let spec = ImuSpec {
            gyro_noise: self.white[0] / dt.sqrt(),
            accel_noise: self.white[1] / dt.sqrt(),
            gyro_bias: 1e-4,
            accel_bias: 1e-2,
            ..ImuSpec::default()
        };
        let mut imu = ImuModel::new(spec, seed);
        let mut g = Gauss::new(seed ^ 0x5eed);
        let mut walk = [0.0; 6];
        let mut markov = [[0.0; 3]; 6];
        let truth = ImuRate {
            t: 0.0,
            w_ib_b: Vector3::zeros(),
            f_b: Vector3::new(0.0, 0.0, -G),
        };
        (0..samples)
            .map(|_| {
                let s = imu.corrupt_rate(&truth);
                let mut row = [
                    s.w_ib_b.x, s.w_ib_b.y, s.w_ib_b.z, s.f_b.x, s.f_b.y, s.f_b.z,
                ];
                for j in 0..6 {
                    walk[j] += self.walk[j] * dt.sqrt() * g.normal();
                    row[j] += walk[j];
                    for (i, t) in MARKOV_TIMES.iter().enumerate() {
                        let phi = (-dt / t).exp();
                        markov[j][i] = phi * markov[j][i]
                            + self.markov[j] * (1.0 - phi * phi).sqrt() * g.normal();
                        row[j] += markov[j][i];
                    }
                }
                row
            })
            .collect()
    }

    /// The true Allan variance of axis `j` at `tau`.
    fn avar(&self, j: usize, tau: f64) -> f64 {
        self.white[j / 3].powi(2) / tau
            + self.walk[j].powi(2) * tau / 3.0
            + MARKOV_TIMES
                .iter()
                .map(|&t| gauss_markov_avar(self.markov[j].powi(2), t, tau))
                .sum::<f64>()
    }
}

/// Issue 35, item 2: the coefficients of a simulated IMU are recovered
/// within three of the estimator's own sigmas (the reported relative
/// confidence of the point or stretch read), over five seeds (40-44), and
/// a rate random walk is found on at least 9 of the 10 axes that have one. Two
/// hours at 50 Hz. The x axes have white noise only (the flat part and the
/// rate random walk must be "not reached"), the y axes white noise and a
/// rate random walk crossing at 17 s (no flat part between: "not
/// reached"), the z axes white noise, a wandering bias flat over two decades
/// and a weak rate random walk. The true bias instability is the bottom of the true curve over
/// the report's cluster times / 0.664 (the quantity the method defines).
#[test]
fn recovers_the_noise_of_a_simulated_imu() {
    let truth = Truth {
        period: 0.02,
        white: [2e-4, 1e-3],
        walk: [0.0, 2e-5, 5e-6, 0.0, 1e-4, 2.5e-5],
        markov: [0.0, 0.0, 1e-4, 0.0, 0.0, 5e-4],
    };
    let mut worst = [0.0f64; 3];
    let mut missed = Vec::new();
    for seed in 40..45 {
        let report = analyse(&truth.record(360_000, seed), truth.period).unwrap();
        assert!(
            report.warnings.is_empty(),
            "seed {seed}: {:?}",
            report.warnings
        );
        for (j, axis) in report.axes.iter().enumerate() {
            let Reading::Found(n) = axis.white else {
                panic!("seed {seed} {}: white noise not found", axis.name);
            };
            let want = truth.white[j / 3];
            let err = (n.value - want).abs() / want / n.relative_error;
            worst[0] = worst[0].max(err);
            assert!(
                err <= 3.0,
                "seed {seed} {}: N {} vs {want}",
                axis.name,
                n.value
            );
            match (j % 3, axis.random_walk) {
                (0, Reading::NotReached(_)) | (2, _) => {}
                (1, Reading::Found(k)) => {
                    let want = truth.walk[j];
                    let err = (k.value - want).abs() / want / k.relative_error;
                    worst[1] = worst[1].max(err);
                    assert!(
                        err <= 3.0,
                        "seed {seed} {}: K {} vs {want} ({k:?})",
                        axis.name,
                        k.value
                    );
                }
                (1, Reading::NotReached(why)) => missed.push((seed, axis.name, why)),
                (_, r) => panic!("seed {seed} {}: rate random walk {r:?}", axis.name),
            }
            match (j % 3, axis.bias_instability) {
                (0 | 1, Reading::NotReached(_)) => {}
                (2, Reading::Found(b)) => {
                    let floor = axis
                        .curve
                        .iter()
                        .map(|p| truth.avar(j, p.tau_s).sqrt())
                        .fold(f64::INFINITY, f64::min);
                    let want = floor / FLICKER_FLOOR;
                    let err = (b.value - want).abs() / want / b.relative_error;
                    worst[2] = worst[2].max(err);
                    assert!(
                        err <= 3.0,
                        "seed {seed} {}: B {} vs {want} ({b:?})",
                        axis.name,
                        b.value
                    );
                }
                (_, r) => panic!("seed {seed} {}: bias instability {r:?}", axis.name),
            }
        }
    }
    println!(
        "worst errors in estimator sigmas over 5 seeds: N {:.2}, K {:.2}, B {:.2}; \
         rate random walks not reached: {missed:?}",
        worst[0], worst[1], worst[2]
    );
    // A random walk's realization over one record can run off the +1/2
    // slope for a decade (seed 44, gyro: 0.3 from 40 to 500 s); the method
    // then says "not reached" rather than read a wrong line. Measured: 1 of
    // the 10 rate random walks (seeds 40-44).
    assert!(missed.len() <= 1, "{missed:?}");
}

/// A static record of white noise only, at 100 Hz for `seconds`.
fn white_record(samples: usize, seed: u64) -> Vec<[f64; 6]> {
    let mut g = Gauss::new(seed);
    (0..samples)
        .map(|_| {
            [
                1e-3 * g.normal(),
                1e-3 * g.normal(),
                1e-3 * g.normal(),
                0.01 * g.normal(),
                0.01 * g.normal(),
                -G + 0.01 * g.normal(),
            ]
        })
        .collect()
}

/// Bad input: each case is refused with the error that names it.
#[test]
fn bad_records_are_refused_with_the_cause() {
    let base = white_record(20_000, 7);
    let edit = |f: &dyn Fn(usize, &mut [f64; 6])| -> Vec<[f64; 6]> {
        let mut r = base.clone();
        for (k, row) in r.iter_mut().enumerate() {
            f(k, row);
        }
        r
    };
    let turning = edit(&|k, r| r[2] += if k > 10_000 { 0.1 } else { 0.0 });
    let tilted = edit(&|k, r| {
        let a = 0.2 * k as f64 / 20_000.0;
        let (fx, fz) = (r[3], r[5]);
        r[3] = fx * a.cos() - fz * a.sin();
        r[5] = fx * a.sin() + fz * a.cos();
    });
    let accelerating = edit(&|k, r| r[5] -= if k > 15_000 { 2.0 } else { 0.0 });
    let nan = edit(&|k, r| r[4] = if k == 119 { f64::NAN } else { r[4] });
    let infinite = edit(&|k, r| r[0] = if k == 5 { f64::INFINITY } else { r[0] });
    let frozen_gyro = edit(&|_, r| r[1] = 1e-4);
    let zeros = edit(&|_, r| *r = [0.0; 6]);
    let gyro_in_millirad = edit(&|_, r| r[2] += 1e5);
    let huge_force = edit(&|_, r| r[3] = 1e150 * (1.0 + r[3]));
    let cases: [(&str, &[[f64; 6]], f64, &str); 14] = [
        (
            "zero period",
            &base,
            0.0,
            "expected a finite period above 0 s",
        ),
        (
            "NaN period",
            &base,
            f64::NAN,
            "expected a finite period above 0 s",
        ),
        (
            "too short",
            &base[..99],
            0.01,
            "99 IMU samples: an Allan analysis needs at least 100",
        ),
        (
            "NaN cell",
            &nan,
            0.01,
            "sample 120 (from 1), column ay: NaN is not a finite number",
        ),
        (
            "infinite cell",
            &infinite,
            0.01,
            "sample 6 (from 1), column gx: inf is not a finite number",
        ),
        ("turning", &turning, 0.01, "the mean of gz changes by 0.1"),
        (
            "tilted",
            &tilted,
            0.01,
            "the direction of gravity changes by",
        ),
        (
            "accelerating",
            &accelerating,
            0.01,
            "the specific force magnitude changes by 2.0",
        ),
        (
            "times in milliseconds",
            &base,
            10.0,
            "sampling period 10 s, slower than 1 s: times in milliseconds",
        ),
        (
            "one gyro frozen",
            &frozen_gyro,
            0.01,
            "column gy: 0.0001 in every sample: a frozen or disconnected sensor",
        ),
        ("all zeros", &zeros, 0.01, "column gx: 0 in every sample"),
        (
            "gyro beyond any rate",
            &gyro_in_millirad,
            0.01,
            "column gz: mean 1.000e5 beyond 35 rad/s: not a physical rate",
        ),
        (
            "specific force beyond any",
            &huge_force,
            0.01,
            "column ax: mean 1.000e150 beyond 1000 m/s^2: not a physical specific force",
        ),
        ("just above 1 s", &base, 1.5, "slower than 1 s"),
    ];
    for (name, record, period, want) in cases {
        let err = analyse(record, period).expect_err(name).to_string();
        assert!(err.contains(want), "{name}: {err}");
    }
    assert!(
        analyse(&base, 0.01).is_ok(),
        "the unedited record is static"
    );
}

/// Records that are analysed with a warning, or with terms not reached.
#[test]
fn short_or_drifting_records_are_qualified() {
    // 20 s at 100 Hz of white noise: the white noise is read, the flat part
    // and the rate random walk are not reached.
    let short = analyse(&white_record(2_000, 8), 0.01).unwrap();
    for axis in &short.axes {
        assert!(matches!(axis.white, Reading::Found(_)), "{}", axis.name);
        assert!(
            matches!(axis.bias_instability, Reading::NotReached(_)),
            "{} {:?}",
            axis.name,
            axis.bias_instability
        );
        assert!(
            matches!(axis.random_walk, Reading::NotReached(_)),
            "{} {:?}",
            axis.name,
            axis.random_walk
        );
    }
    assert!(short.warnings.is_empty(), "{:?}", short.warnings);
    // The same in g instead of m/s^2.
    let in_g: Vec<[f64; 6]> = white_record(2_000, 9)
        .into_iter()
        .map(|mut r| {
            r[3..].iter_mut().for_each(|v| *v /= G);
            r
        })
        .collect();
    let w = analyse(&in_g, 0.01).unwrap().warnings;
    assert!(
        matches!(w[..], [AllanWarning::GravityMagnitude { norm }] if (norm - 1.0).abs() < 0.01),
        "{w:?}"
    );
    // A gyro warming up: its rate drifts by 0.5 deg/s over the record
    // (under the turn threshold, far above the noise at long cluster times).
    let drifting: Vec<[f64; 6]> = white_record(20_000, 10)
        .into_iter()
        .enumerate()
        .map(|(k, mut r)| {
            r[1] += 0.5f64.to_radians() * k as f64 / 20_000.0;
            r
        })
        .collect();
    let w = analyse(&drifting, 0.01).unwrap().warnings;
    assert!(
        matches!(w[..], [AllanWarning::Drift { axis: "gy", slope, .. }] if slope > 0.9),
        "{w:?}"
    );
    assert!(w[0]
        .to_string()
        .contains("gy: the Allan deviation climbs at slope"));
}

/// The `[sensors.imu]` section: per-sample sigmas at the record's rate
/// (N / sqrt(period)), parsed back by a TOML reader with the keys of
/// docs/log-format.md; a term not reached is a comment, not a value.
#[cfg(feature = "log")]
#[test]
fn imu_section_holds_per_sample_sigmas() {
    let report = analyse(&white_record(20_000, 11), 0.01).unwrap();
    let text = report.imu_section();
    let table: toml::Table = text.parse().unwrap();
    let imu = table["sensors"]["imu"].as_table().unwrap();
    let gyro = imu["gyro_noise_sigma"].as_float().unwrap();
    let accel = imu["accel_noise_sigma"].as_float().unwrap();
    // The white record has sigma 1e-3 rad/s and 1e-2 m/s^2 per sample.
    assert!((gyro - 1e-3).abs() < 0.05e-3, "{text}");
    assert!((accel - 1e-2).abs() < 0.05e-2, "{text}");
    assert!(!imu.contains_key("gyro_bias_sigma"), "{text}");
    assert!(text.contains("# gyro_bias_sigma: not reached"), "{text}");
    let largest = report.axes[..3]
        .iter()
        .map(|a| a.white.value().unwrap() / 0.01f64.sqrt())
        .fold(0.0, f64::max);
    let e = report.noise();
    assert_eq!(e.gyro_noise_sigma, Some(largest));
    assert!(
        (gyro - largest).abs() <= 1e-6 * largest,
        "written with 7 digits"
    );
}

/// The plot data: the fitted lines pass through the value they were read at.
#[test]
fn fit_lines_pass_through_their_readings() {
    let report = analyse(&white_record(20_000, 12), 0.01).unwrap();
    let axis = &report.axes[0];
    let [(t0, s0), (t1, s1)] = axis.fit_line(Term::White).unwrap();
    let n = axis.white.value().unwrap();
    assert!((s0 - n / t0.sqrt()).abs() < 1e-15 && (s1 - n / t1.sqrt()).abs() < 1e-15);
    assert_eq!(axis.fit_line(Term::RandomWalk), None);
}

/// The time column: its median step, or the row where it goes wrong.
#[test]
fn sampling_period_refuses_gaps_and_time_going_back() {
    let even: Vec<f64> = (0..200).map(|k| 10.0 + 0.01 * k as f64).collect();
    let mut gap = even.clone();
    gap[150..].iter_mut().for_each(|t| *t += 0.5);
    let mut back = even.clone();
    back[42] = back[41];
    let mut nan = even.clone();
    nan[7] = f64::NAN;
    let cases: [(&str, &[f64], Result<f64, &str>); 5] = [
        ("even", &even, Ok(0.01)),
        (
            "gap",
            &gap,
            Err(
                "sample 151 (from 1), column t: a gap of 0.510000 s where the period is 0.010000 s",
            ),
        ),
        (
            "backwards",
            &back,
            Err("sample 43 (from 1), column t: time does not increase"),
        ),
        (
            "NaN",
            &nan,
            Err("sample 8 (from 1), column t: NaN is not a finite number"),
        ),
        (
            "one stamp",
            &even[..1],
            Err("1 IMU samples: an Allan analysis needs at least 100"),
        ),
    ];
    for (name, times, want) in cases {
        match (sampling_period(times), want) {
            (Ok(p), Ok(w)) => assert!((p - w).abs() < 1e-12, "{name}: {p}"),
            (Err(e), Err(w)) => assert!(e.to_string().starts_with(w), "{name}: {e}"),
            (got, _) => panic!("{name}: {got:?}"),
        }
    }
}
