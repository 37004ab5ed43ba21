//! VKF (docs/models/vkf.md): the velocity Kalman filter, the switching box and
//! the 9-state integrated filter, their simulation, and the `vkf` scenario of
//! `navsim`, which runs pure INS, conventional INS-DVL, VKF-aided navigation and
//! the VKF with the speed map inside the integrated filter ([`coupled`])
//! on the same data, with a realistic DVL bias (+-0.005 m/s, the top-level
//! keys) and with the paper's +-0.5 m/s (the `paper_dvl_bias` object).

pub mod attitude_computer;
pub mod coupled;
pub mod filter;
pub mod model;
pub mod simulation;

use crate::harness::plot::{self, Line};
use crate::harness::{metric_values, RunError, RunOptions, RunResult, RunTable, Scenario};
use filter::{RunSettings, Source, VkfRun};
use nav_runtime::log::LogDir;
use nav_runtime::nalgebra::Vector3;
use nav_runtime::stats;
use serde_json::{json, Map, Value};
use simulation::{DvlBias, RunTruth};
use std::path::Path;

pub use model::{Nav9, Nav9Dvl, Nav9Rpm, VelocityFilter, VelocityFilterDvl};

/// The navigators, in the order of the JSON keys: pure INS, INS-DVL, the
/// paper's VKF, the VKF with the speed map and the DVL errors inside the
/// integrated filter ([`coupled`]), and INS-DVL with those DVL error states
/// (the same filter, the RPM never fused).
pub const SOLUTIONS: [&str; 5] = [
    "pure_ins",
    "ins_dvl",
    "vkf",
    "vkf_coupled",
    "ins_dvl_calibrated",
];

/// Number of navigators.
const S: usize = SOLUTIONS.len();
/// Width of a scored epoch: time, truth N and E, then N and E errors per navigator.
const W: usize = 3 + 2 * S;

/// The `vkf` scenario.
#[derive(Clone, Copy, Debug, Default)]
pub struct VkfScenario;

/// Errors of one navigator in one run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Score {
    /// Final horizontal error (m).
    pub final_m: f64,
    /// Largest horizontal error over the run (m).
    pub max_m: f64,
    /// RMS of the horizontal error over the 5 Hz epochs (m).
    pub rms_m: f64,
    /// Drift during the DVL outages: the largest change of the horizontal error
    /// vector from the last epoch before an outage to any epoch inside it (m).
    pub outage_drift_m: f64,
    /// RMS of the horizontal error over the epochs inside all outages (m).
    pub outage_rms_m: f64,
}

/// Errors of one navigator in one outage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutageScore {
    /// Growth of the horizontal error over the outage: norm of the change of the
    /// error vector from the last epoch before it to its last epoch (m).
    pub drift_m: f64,
    /// RMS of the horizontal error over the epochs inside it (m).
    pub rms_m: f64,
    /// Horizontal error 10 s after the DVL returns (m; NaN if the run ends first).
    pub after_m: f64,
}

/// One DVL outage seen by the switch.
#[derive(Clone, Debug, PartialEq)]
pub struct Outage {
    /// Start and end (s).
    pub span: (f64, f64),
    /// Per navigator, the order of [`SOLUTIONS`].
    pub scores: [OutageScore; S],
}

/// Scores of one run over one log.
#[derive(Clone, Debug, PartialEq)]
pub struct RunScores {
    /// The order of [`SOLUTIONS`].
    pub scores: [Score; S],
    /// Horizontal distance travelled (m).
    pub distance_m: f64,
    /// DVL outages seen by the switch, `(start, end)` (s).
    pub outages: Vec<(f64, f64)>,
    /// Per-outage scores, the order of `outages`.
    pub outage_scores: Vec<Outage>,
    /// RMS error of the RPM-derived forward speed while it is in use (m/s).
    pub rpm_speed_error_rms_m_s: f64,
    /// Horizontal norm of the DVL's own velocity error (measurement minus truth,
    /// rotated to n) integrated over the epochs it is in use (m): the position
    /// error any DVL-aided solution inherits.
    pub dvl_error_integral_m: f64,
    /// Horizontal position NEES (2 dof) of the map-state VKF at the last epoch:
    /// its error against its own covariance.
    pub coupled_nees_final: f64,
    /// The same of the calibrated INS-DVL.
    pub calibrated_nees_final: f64,
    /// Time, truth north/east and the horizontal error vectors (N, E) of the
    /// navigators, per epoch.
    pub series: Vec<[f64; W]>,
}

/// Truth position NED from the start (m): trapezoidal integral of the truth
/// velocity, the frame of the 9-state filter (flat, `d position/dt = v^n`).
fn truth_positions(log: &LogDir) -> Vec<(f64, Vector3<f64>)> {
    let rows = log.truth.as_deref().unwrap_or(&[]);
    let mut out = Vec::with_capacity(rows.len());
    let mut p = Vector3::zeros();
    for (i, r) in rows.iter().enumerate() {
        if i > 0 {
            let q = &rows[i - 1];
            p += 0.5 * (r.t - q.t) * Vector3::new(r.vn + q.vn, r.ve + q.ve, r.vd + q.vd);
        }
        out.push((r.t, p));
    }
    out
}

/// Scores a run against the log's truth.
pub fn score(run: &VkfRun, log: &LogDir) -> Result<RunScores, RunError> {
    let truth = truth_positions(log);
    let mut series: Vec<[f64; W]> = Vec::with_capacity(run.records.len());
    let mut j = 0usize;
    let mut distance_m = 0.0;
    let mut last_truth: Option<Vector3<f64>> = None;
    // Outages as epoch ranges: the last epoch before, and one past the last inside.
    let mut spans: Vec<(usize, usize)> = Vec::new();
    let mut outage_start: Option<usize> = None;
    let rows = log.truth.as_deref().unwrap_or(&[]);
    let mut rpm_errors = Vec::new();
    let mut dvl_integral = Vector3::zeros();
    let mut last_t: Option<f64> = None;
    for r in &run.records {
        while j + 1 < truth.len() && truth[j].0 < r.t - 1e-6 {
            j += 1;
        }
        let Some(&(tt, p)) = truth.get(j) else { break };
        if (tt - r.t).abs() > 1e-6 {
            continue;
        }
        if let Some(q) = last_truth {
            distance_m += (p - q).xy().norm();
        }
        last_truth = Some(p);
        let dt = last_t.map_or(0.0, |t0| r.t - t0);
        last_t = Some(r.t);
        let mut x = [0.0; W];
        x[..3].copy_from_slice(&[r.t, p.x, p.y]);
        let errors = [
            r.pure_error,
            r.ins_dvl - p,
            r.vkf - p,
            r.vkf_coupled - p,
            r.ins_dvl_calibrated - p,
        ];
        for (s, e) in errors.iter().enumerate() {
            x[3 + 2 * s] = e.x;
            x[4 + 2 * s] = e.y;
        }
        series.push(x);
        let k = series.len() - 1;
        if let Some(tr) = rows.get(j) {
            let v_true = Vector3::new(tr.vn, tr.ve, tr.vd);
            match r.source {
                Source::Rpm => rpm_errors.push(r.rpm_speed - v_true.norm()),
                Source::Dvl if r.dvl_n.iter().all(|v| v.is_finite()) => {
                    dvl_integral += dt * (r.dvl_n - v_true);
                }
                Source::Dvl => {}
            }
        }
        match (r.source, outage_start) {
            (Source::Rpm, None) => outage_start = Some(k.saturating_sub(1)),
            (Source::Dvl, Some(k0)) => {
                spans.push((k0, k));
                outage_start = None;
            }
            _ => {}
        }
    }
    if let Some(k0) = outage_start {
        spans.push((k0, series.len()));
    }
    let last = series
        .last()
        .ok_or_else(|| RunError::Invalid("no epoch matches a truth time".into()))?;
    let horizontal = |x: &[f64; W], s: usize| x[3 + 2 * s].hypot(x[4 + 2 * s]);
    let outage_scores: Vec<Outage> = spans
        .iter()
        .map(|&(k0, k1)| Outage {
            span: (
                series[(k0 + 1).min(k1 - 1)][0],
                series[k1.min(series.len() - 1)][0],
            ),
            scores: std::array::from_fn(|s| outage_score(&series, k0, k1, s)),
        })
        .collect();
    let inside: Vec<&[f64; W]> = spans
        .iter()
        .flat_map(|&(k0, k1)| series[k0 + 1..k1].iter())
        .collect();
    let scores = std::array::from_fn(|s| {
        let h: Vec<f64> = series.iter().map(|x| horizontal(x, s)).collect();
        let hin: Vec<f64> = inside.iter().map(|x| horizontal(x, s)).collect();
        Score {
            final_m: horizontal(last, s),
            max_m: stats::max(&h),
            rms_m: stats::rms(&h),
            outage_drift_m: spans
                .iter()
                .map(|&(k0, k1)| largest_change(&series[k0..k1], s))
                .fold(0.0, f64::max),
            outage_rms_m: stats::rms(&hin),
        }
    });
    // Horizontal NEES of navigator `s` at the last epoch, covariance `[nn, ne, ee]`.
    let nees_final = |s: usize, [nn, ne, ee]: [f64; 3]| {
        let (n, e) = (last[3 + 2 * s], last[4 + 2 * s]);
        let det = nn * ee - ne * ne;
        if det > 0.0 {
            (ee * n * n - 2.0 * ne * n * e + nn * e * e) / det
        } else {
            f64::NAN
        }
    };
    let (coupled_nees_final, calibrated_nees_final) =
        run.records.last().map_or((f64::NAN, f64::NAN), |r| {
            (
                nees_final(3, r.coupled_covariance),
                nees_final(4, r.calibrated_covariance),
            )
        });
    Ok(RunScores {
        scores,
        distance_m,
        coupled_nees_final,
        calibrated_nees_final,
        rpm_speed_error_rms_m_s: stats::rms(&rpm_errors),
        dvl_error_integral_m: dvl_integral.xy().norm(),
        outages: outage_scores.iter().map(|o| o.span).collect(),
        outage_scores,
        series,
    })
}

/// Largest change of navigator `s`'s horizontal error vector from the first
/// epoch of `epochs` to any of them (m).
fn largest_change(epochs: &[[f64; W]], s: usize) -> f64 {
    let Some(a) = epochs.first() else { return 0.0 };
    epochs
        .iter()
        .map(|b| (b[3 + 2 * s] - a[3 + 2 * s]).hypot(b[4 + 2 * s] - a[4 + 2 * s]))
        .fold(0.0, f64::max)
}

/// Navigator `s` over the outage whose last epoch before is `k0` and whose
/// epochs are `k0 + 1 .. k1`.
fn outage_score(series: &[[f64; W]], k0: usize, k1: usize, s: usize) -> OutageScore {
    let e = |x: &[f64; W]| Vector3::new(x[3 + 2 * s], x[4 + 2 * s], 0.0);
    let a = e(&series[k0]);
    let end = e(&series[k1 - 1]);
    let h: Vec<f64> = series[k0 + 1..k1].iter().map(|x| e(x).norm()).collect();
    let t_after = series[k1 - 1][0] + 10.0;
    let after = series[k1..]
        .iter()
        .find(|x| x[0] >= t_after - 1e-6)
        .map_or(f64::NAN, |x| e(x).norm());
    OutageScore {
        drift_m: (end - a).norm(),
        rms_m: stats::rms(&h),
        after_m: after,
    }
}

/// Runs the navigators over one log and scores them.
pub fn run_log(log: &LogDir) -> Result<(VkfRun, RunScores), RunError> {
    let run =
        filter::run(log, &RunSettings::default()).map_err(|e| RunError::Invalid(e.to_string()))?;
    let scores = score(&run, log)?;
    Ok((run, scores))
}

fn variant_prefix(bias: DvlBias) -> &'static str {
    match bias {
        DvlBias::Realistic => "realistic",
        DvlBias::Paper => "paper",
    }
}

fn put_scores(mut r: RunResult, bias: DvlBias, s: &RunScores) -> RunResult {
    let v = variant_prefix(bias);
    for (name, sc) in SOLUTIONS.iter().zip(&s.scores) {
        r = r
            .with_metric(&format!("{v}.{name}.final_m"), sc.final_m)
            .with_metric(&format!("{v}.{name}.rms_m"), sc.rms_m)
            .with_metric(&format!("{v}.{name}.max_m"), sc.max_m)
            .with_metric(&format!("{v}.{name}.outage_drift_m"), sc.outage_drift_m)
            .with_metric(&format!("{v}.{name}.outage_rms_m"), sc.outage_rms_m);
    }
    for (i, o) in s.outage_scores.iter().enumerate() {
        for (name, sc) in SOLUTIONS.iter().zip(&o.scores) {
            let k = format!("{v}.{name}.outage{i}");
            r = r
                .with_metric(&format!("{k}.drift_m"), sc.drift_m)
                .with_metric(&format!("{k}.rms_m"), sc.rms_m)
                .with_metric(&format!("{k}.after_m"), sc.after_m);
        }
    }
    r.with_metric(&format!("{v}.distance_m"), s.distance_m)
        .with_metric(&format!("{v}.outages"), s.outage_scores.len() as f64)
        .with_metric(&format!("{v}.dvl_error_integral_m"), s.dvl_error_integral_m)
        .with_metric(&format!("{v}.vkf_coupled_nees_final"), s.coupled_nees_final)
        .with_metric(
            &format!("{v}.ins_dvl_calibrated_nees_final"),
            s.calibrated_nees_final,
        )
}

const TABLE: &str = "vkf";
const COLUMNS: [&str; 34] = [
    "t",
    "truth_n",
    "truth_e",
    "pure_n",
    "pure_e",
    "ins_dvl_n",
    "ins_dvl_e",
    "vkf_n",
    "vkf_e",
    "pure_error_m",
    "ins_dvl_error_m",
    "vkf_error_m",
    "altitude_m",
    "dvl_in_use",
    "rpm",
    "dvl_vn",
    "dvl_ve",
    "dvl_forward",
    "rpm_speed",
    "rpm_vn",
    "rpm_ve",
    "sf",
    "b",
    "sf_sigma",
    "b_sigma",
    "sf_true_local",
    "b_true_local",
    "vkf_coupled_n",
    "vkf_coupled_e",
    "vkf_coupled_error_m",
    "coupled_map_speed",
    "ins_dvl_calibrated_n",
    "ins_dvl_calibrated_e",
    "ins_dvl_calibrated_error_m",
];
const PAPER_TABLE: &str = "vkf-paper-bias";
const PAPER_COLUMNS: [&str; 18] = [
    "t",
    "truth_n",
    "truth_e",
    "pure_n",
    "pure_e",
    "ins_dvl_n",
    "ins_dvl_e",
    "vkf_n",
    "vkf_e",
    "pure_error_m",
    "ins_dvl_error_m",
    "vkf_error_m",
    "vkf_coupled_n",
    "vkf_coupled_e",
    "vkf_coupled_error_m",
    "ins_dvl_calibrated_n",
    "ins_dvl_calibrated_e",
    "ins_dvl_calibrated_error_m",
];

/// Position columns of a scored epoch: truth, the first three estimates and
/// their errors (the original column order).
fn position_columns(x: &[f64; W]) -> [f64; 12] {
    [
        x[0],
        x[1],
        x[2],
        x[1] + x[3],
        x[2] + x[4],
        x[1] + x[5],
        x[2] + x[6],
        x[1] + x[7],
        x[2] + x[8],
        x[3].hypot(x[4]),
        x[5].hypot(x[6]),
        x[7].hypot(x[8]),
    ]
}

/// 1 Hz tables of a run (every fifth epoch).
fn tables(run: &VkfRun, s: &RunScores, paper: &RunScores, truth: &RunTruth) -> Vec<RunTable> {
    // Position and error of navigator `s`.
    let solution = |x: &[f64; W], s: usize| {
        let (n, e) = (x[3 + 2 * s], x[4 + 2 * s]);
        [x[1] + n, x[2] + e, n.hypot(e)]
    };
    let mut table = RunTable::new(TABLE, &COLUMNS);
    let mut paper_table = RunTable::new(PAPER_TABLE, &PAPER_COLUMNS);
    let by_time = |t: f64, xs: &[[f64; W]]| xs.iter().find(|x| (x[0] - t).abs() < 1e-6).copied();
    for r in run
        .records
        .iter()
        .filter(|r| (r.t - r.t.round()).abs() < 1e-6)
    {
        let Some(x) = by_time(r.t, &s.series) else {
            continue;
        };
        let (sf_true, b_true) = truth.map.tangent(r.rpm);
        let mut row = position_columns(&x).to_vec();
        row.extend([
            r.altitude,
            f64::from(u8::from(r.source == Source::Dvl)),
            r.rpm,
            r.dvl_n.x,
            r.dvl_n.y,
            r.dvl_forward,
            r.rpm_speed,
            r.rpm_n.x,
            r.rpm_n.y,
            r.sf,
            r.b,
            r.sf_sigma,
            r.b_sigma,
            sf_true,
            b_true,
        ]);
        row.extend(solution(&x, 3));
        row.push(r.coupled_map_speed);
        row.extend(solution(&x, 4));
        table.push(&row);
        if let Some(y) = by_time(r.t, &paper.series) {
            let mut row = position_columns(&y).to_vec();
            row.extend(solution(&y, 3));
            row.extend(solution(&y, 4));
            paper_table.push(&row);
        }
    }
    vec![table, paper_table]
}

impl Scenario for VkfScenario {
    fn name(&self) -> &'static str {
        "vkf"
    }
    fn description(&self) -> &'static str {
        "VKF: pure INS vs INS-DVL vs RPM/DVL velocity-filter aided INS, 27 min at 10 kn, DVL out of range twice"
    }
    fn default_runs(&self) -> usize {
        20
    }
    /// Every run scores both DVL-bias variants; the flag picks the
    /// variant a simulated log has (the paper's biases).
    fn draws_biases_in_log(&self) -> bool {
        true
    }
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
        let logs = simulation::simulate(seed);
        let (run, real) = run_log(&logs.realistic)?;
        let (_, paper) = run_log(&logs.paper)?;
        let mut r = put_scores(RunResult::new(seed), DvlBias::Realistic, &real);
        r = put_scores(r, DvlBias::Paper, &paper);
        if let Some(last) = run.records.last() {
            let (sf_true, b_true) = logs.truth.map.tangent(last.rpm);
            r = r
                .with_metric("sf_error_final", last.sf - sf_true)
                .with_metric("b_error_final_m_s", last.b - b_true)
                .with_metric("sf_sigma_final", last.sf_sigma)
                .with_metric("b_sigma_final_m_s", last.b_sigma);
        }
        r = r
            .with_metric("rpm_speed_error_rms_m_s", real.rpm_speed_error_rms_m_s)
            .with_metric("outage_s", real.outages.iter().map(|(a, b)| b - a).sum())
            .with_metric("refused_ins_dvl", run.refused.0 as f64)
            .with_metric("refused_vkf", run.refused.1 as f64)
            .with_metric("refused_vkf_coupled", run.refused_coupled as f64)
            .with_metric("refused_ins_dvl_calibrated", run.refused_calibrated as f64);
        r.extra = json!({ "outages_s": real.outages });
        if options.keep_series {
            r.tables = tables(&run, &real, &paper, &logs.truth);
        }
        Ok(r)
    }
    fn summarize(
        &self,
        runs: &[RunResult],
        _options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError> {
        let mut m = variant_summary(runs, DvlBias::Realistic);
        m.insert(
            "paper_dvl_bias".into(),
            Value::Object(variant_summary(runs, DvlBias::Paper)),
        );
        let med = |k: &str| stats::median(&metric_values(runs, k));
        m.insert(
            "velocity_filter".into(),
            json!({
                "sf_error_final_median_abs": stats::median(&metric_values(runs, "sf_error_final").iter().map(|x| x.abs()).collect::<Vec<_>>()),
                "b_error_final_median_abs_m_s": stats::median(&metric_values(runs, "b_error_final_m_s").iter().map(|x| x.abs()).collect::<Vec<_>>()),
                "sf_sigma_final": med("sf_sigma_final"),
                "b_sigma_final_m_s": med("b_sigma_final_m_s"),
                "rpm_speed_error_rms_in_outages_m_s": med("rpm_speed_error_rms_m_s"),
                "sf_error_over_sigma_median": stats::median(&metric_values(runs, "sf_error_final").iter().zip(metric_values(runs, "sf_sigma_final")).map(|(e, s)| e.abs() / s).collect::<Vec<_>>()),
            }),
        );
        m.insert("outage_s".into(), Value::from(med("outage_s")));
        if let Some(first) = runs.first() {
            m.insert(
                "outages_s".into(),
                first.extra.get("outages_s").cloned().unwrap_or(Value::Null),
            );
        }
        let refused: f64 = metric_values(runs, "refused_ins_dvl")
            .iter()
            .chain(&metric_values(runs, "refused_vkf"))
            .sum();
        m.insert("refused_updates".into(), Value::from(refused));
        let refused_coupled: f64 = metric_values(runs, "refused_vkf_coupled").iter().sum();
        m.insert(
            "refused_updates_vkf_coupled".into(),
            Value::from(refused_coupled),
        );
        let refused_calibrated: f64 = metric_values(runs, "refused_ins_dvl_calibrated")
            .iter()
            .sum();
        m.insert(
            "refused_updates_ins_dvl_calibrated".into(),
            Value::from(refused_calibrated),
        );
        Ok(m)
    }
    fn write_outputs(&self, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
        crate::harness::write_run_tables(runs, dir)?;
        match runs.iter().find(|r| !r.tables.is_empty()) {
            Some(r) => write_figures(r, dir),
            None => Ok(()),
        }
    }
    fn simulate_log(&self, seed: u64, options: &RunOptions) -> Option<Result<LogDir, RunError>> {
        let logs = simulation::simulate(seed);
        Some(Ok(if options.draw_biases {
            logs.paper
        } else {
            logs.realistic
        }))
    }
}

/// The JSON of one DVL-bias variant: `pure_ins`, `ins_dvl`, `vkf` (docs/cli-and-json.md)
/// plus the ratios the targets are stated in.
fn variant_summary(runs: &[RunResult], bias: DvlBias) -> Map<String, Value> {
    let v = variant_prefix(bias);
    let distance = stats::median(&metric_values(runs, &format!("{v}.distance_m")));
    let mut m = Map::new();
    let mut finals = Vec::new();
    let mut outage_rms = Vec::new();
    let outages = metric_values(runs, &format!("{v}.outages"))
        .into_iter()
        .fold(0.0, f64::max) as usize;
    // Median over the runs that have outage `i`.
    let med_present = |key: &str| {
        let xs: Vec<f64> = metric_values(runs, key)
            .into_iter()
            .filter(|x| x.is_finite())
            .collect();
        stats::median(&xs)
    };
    for name in SOLUTIONS {
        let f = metric_values(runs, &format!("{v}.{name}.final_m"));
        let rms = metric_values(runs, &format!("{v}.{name}.rms_m"));
        let drift = metric_values(runs, &format!("{v}.{name}.outage_drift_m"));
        let max = metric_values(runs, &format!("{v}.{name}.max_m"));
        finals.push(f.clone());
        let orms = metric_values(runs, &format!("{v}.{name}.outage_rms_m"));
        outage_rms.push(orms.clone());
        let per_outage: Vec<Value> = (0..outages)
            .map(|i| {
                let k = format!("{v}.{name}.outage{i}");
                json!({
                    "outage_drift_m": med_present(&format!("{k}.drift_m")),
                    "outage_rms_m": med_present(&format!("{k}.rms_m")),
                    "error_10s_after_m": med_present(&format!("{k}.after_m")),
                })
            })
            .collect();
        m.insert(
            name.into(),
            json!({
                "outage_rms_m": stats::median(&orms),
                "max_error_m": stats::median(&max),
                "outages": per_outage,
                "horizontal_error_final_m": stats::median(&f),
                "horizontal_error_rms_m": stats::median(&rms),
                "distance_travelled_m": distance,
                "horizontal_error_final_p95_m": stats::p95(&f),
                "horizontal_error_final_max_m": stats::max(&f),
                "outage_drift_m": stats::median(&drift),
                "horizontal_error_max_m": stats::median(&max),
                "final_percent_of_distance": 100.0 * stats::median(&f) / distance,
            }),
        );
    }
    let per_run = |a: &[f64], b: &[f64]| -> f64 {
        let r: Vec<f64> = a.iter().zip(b).map(|(a, b)| a / b).collect();
        stats::median(&r)
    };
    let ratios: Vec<f64> = finals[2]
        .iter()
        .zip(&finals[1])
        .map(|(a, b)| a / b)
        .collect();
    m.insert(
        "vkf_coupled_to_ins_dvl_final".into(),
        Value::from(stats::median(&finals[3]) / stats::median(&finals[1])),
    );
    m.insert(
        "vkf_coupled_to_ins_dvl_final_per_run_median".into(),
        Value::from(per_run(&finals[3], &finals[1])),
    );
    m.insert(
        "vkf_coupled_to_ins_dvl_outage_rms".into(),
        Value::from(stats::median(&outage_rms[3]) / stats::median(&outage_rms[1])),
    );
    m.insert(
        "vkf_to_ins_dvl_outage_rms".into(),
        Value::from(stats::median(&outage_rms[2]) / stats::median(&outage_rms[1])),
    );
    m.insert(
        "vkf_coupled_position_nees_final_median".into(),
        Value::from(med_present(&format!("{v}.vkf_coupled_nees_final"))),
    );
    m.insert(
        "ins_dvl_calibrated_position_nees_final_median".into(),
        Value::from(med_present(&format!("{v}.ins_dvl_calibrated_nees_final"))),
    );
    // The map-state VKF against INS-DVL with the same DVL error states: what
    // the RPM map adds beyond the DVL calibration.
    m.insert(
        "vkf_coupled_to_ins_dvl_calibrated_final".into(),
        Value::from(stats::median(&finals[3]) / stats::median(&finals[4])),
    );
    m.insert(
        "vkf_coupled_to_ins_dvl_calibrated_outage_rms".into(),
        Value::from(stats::median(&outage_rms[3]) / stats::median(&outage_rms[4])),
    );
    m.insert(
        "dvl_error_integral_m".into(),
        Value::from(stats::median(&metric_values(
            runs,
            &format!("{v}.dvl_error_integral_m"),
        ))),
    );
    m.insert(
        "dvl_bias_half_width_m_s".into(),
        Value::from(bias.half_width()),
    );
    m.insert(
        "vkf_to_ins_dvl_final".into(),
        Value::from(stats::median(&finals[2]) / stats::median(&finals[1])),
    );
    m.insert(
        "vkf_to_ins_dvl_final_per_run_median".into(),
        Value::from(stats::median(&ratios)),
    );
    m.insert(
        "vkf_to_pure_ins_final".into(),
        Value::from(stats::median(&finals[2]) / stats::median(&finals[0])),
    );
    m
}

/// The paper's Figs. 8-12 for one run.
fn write_figures(r: &RunResult, dir: &Path) -> Result<(), RunError> {
    let Some(tab) = r.tables.iter().find(|t| t.name == TABLE) else {
        return Ok(());
    };
    let c = |name: &str| tab.column(name);
    let t = c("t");
    let seed = r.seed;
    let svg = |name: &str| dir.join(format!("{name}.svg"));
    let line = |label: &'static str, x: &'static str, y: &'static str| (label, x, y);
    let draw_lines =
        |file: &str, title: String, x_label: &str, y_label: &str, specs: &[(&str, &str, &str)]| {
            let cols: Vec<(Vec<f64>, Vec<f64>)> =
                specs.iter().map(|(_, x, y)| (c(x), c(y))).collect();
            let ls: Vec<Line<'_>> = specs
                .iter()
                .zip(&cols)
                .map(|((label, _, _), (x, y))| Line { label, x, y })
                .collect();
            if x_label.contains("east") {
                plot::tracks(&svg(file), &title, x_label, y_label, &ls)
            } else {
                plot::lines(&svg(file), &title, x_label, y_label, &ls)
            }
        };
    // Fig. 8: the DVL in the navigation frame, noise beyond its range.
    draw_lines(
        "fig08-dvl-nav",
        format!("DVL velocity in the navigation frame (seed {seed})"),
        "t [s]",
        "velocity [m/s]",
        &[
            line("DVL north", "t", "dvl_vn"),
            line("DVL east", "t", "dvl_ve"),
        ],
    )?;
    // Fig. 9: RPM and the echo sounder.
    draw_lines(
        "fig09-rpm",
        format!("Propeller RPM (seed {seed})"),
        "t [s]",
        "rpm",
        &[line("rpm", "t", "rpm")],
    )?;
    let range = vec![simulation::DVL_RANGE; t.len()];
    let alt = c("altitude_m");
    plot::lines(
        &svg("fig09-altitude"),
        &format!("Echo-sounder altitude and DVL range (seed {seed})"),
        "t [s]",
        "altitude [m]",
        &[
            Line {
                label: "altitude",
                x: &t,
                y: &alt,
            },
            Line {
                label: "DVL range (switch)",
                x: &t,
                y: &range,
            },
        ],
    )?;
    // Fig. 10: the velocity filter: DVL forward speed and the map estimates.
    let dvl_fwd: Vec<f64> = c("dvl_forward")
        .iter()
        .zip(c("dvl_in_use"))
        .map(|(v, u)| if u > 0.5 { *v } else { f64::NAN })
        .collect();
    let rpm_speed = c("rpm_speed");
    plot::lines(
        &svg("fig10-speed"),
        &format!("Forward speed: DVL (in range) and RPM-derived (seed {seed})"),
        "t [s]",
        "speed [m/s]",
        &[
            Line {
                label: "DVL forward",
                x: &t,
                y: &dvl_fwd,
            },
            Line {
                label: "sf rpm + b",
                x: &t,
                y: &rpm_speed,
            },
        ],
    )?;
    let with_band =
        |file: &str, title: String, y_label: &str, est: &str, sig: &str, truth: &str| {
            let (e, s, tr) = (c(est), c(sig), c(truth));
            let hi: Vec<f64> = e.iter().zip(&s).map(|(e, s)| e + 3.0 * s).collect();
            let lo: Vec<f64> = e.iter().zip(&s).map(|(e, s)| e - 3.0 * s).collect();
            plot::lines(
                &svg(file),
                &title,
                "t [s]",
                y_label,
                &[
                    Line {
                        label: "estimate",
                        x: &t,
                        y: &e,
                    },
                    Line {
                        label: "true local tangent",
                        x: &t,
                        y: &tr,
                    },
                    Line {
                        label: "+3 sigma",
                        x: &t,
                        y: &hi,
                    },
                    Line {
                        label: "-3 sigma",
                        x: &t,
                        y: &lo,
                    },
                ],
            )
        };
    with_band(
        "fig10-scale-factor",
        format!("Velocity filter: scale factor sf (seed {seed})"),
        "sf [(m/s)/rpm]",
        "sf",
        "sf_sigma",
        "sf_true_local",
    )?;
    with_band(
        "fig10-bias",
        format!("Velocity filter: bias b (seed {seed})"),
        "b [m/s]",
        "b",
        "b_sigma",
        "b_true_local",
    )?;
    // Fig. 11: RPM-derived velocity vs DVL in the navigation frame.
    draw_lines(
        "fig11-rpm-velocity",
        format!("RPM-derived vs DVL velocity, navigation frame (seed {seed})"),
        "t [s]",
        "velocity [m/s]",
        &[
            line("DVL north", "t", "dvl_vn"),
            line("RPM north", "t", "rpm_vn"),
            line("DVL east", "t", "dvl_ve"),
            line("RPM east", "t", "rpm_ve"),
        ],
    )?;
    // Fig. 12: tracks and horizontal errors.
    let tracks = [
        line("truth", "truth_e", "truth_n"),
        line("pure INS", "pure_e", "pure_n"),
        line("INS-DVL", "ins_dvl_e", "ins_dvl_n"),
        line("VKF-aided", "vkf_e", "vkf_n"),
    ];
    draw_lines(
        "fig12-tracks",
        format!("Tracks, DVL bias +-0.005 m/s (seed {seed})"),
        "east [m]",
        "north [m]",
        &tracks,
    )?;
    draw_lines(
        "fig12-errors",
        format!("Horizontal error, DVL bias +-0.005 m/s (seed {seed})"),
        "t [s]",
        "horizontal error [m]",
        &[
            line("INS-DVL", "t", "ins_dvl_error_m"),
            line("VKF-aided", "t", "vkf_error_m"),
        ],
    )?;
    draw_lines(
        "fig12-errors-with-pure-ins",
        format!("Horizontal error incl. pure INS, DVL bias +-0.005 m/s (seed {seed})"),
        "t [s]",
        "horizontal error [m]",
        &[
            line("pure INS", "t", "pure_error_m"),
            line("INS-DVL", "t", "ins_dvl_error_m"),
            line("VKF-aided", "t", "vkf_error_m"),
        ],
    )?;
    if let Some(p) = r.tables.iter().find(|t| t.name == PAPER_TABLE) {
        let pc = |name: &str| p.column(name);
        let cols: Vec<(&str, Vec<f64>, Vec<f64>)> =
            tracks.iter().map(|(l, x, y)| (*l, pc(x), pc(y))).collect();
        let ls: Vec<Line<'_>> = cols
            .iter()
            .map(|(label, x, y)| Line { label, x, y })
            .collect();
        plot::tracks(
            &svg("fig12-tracks-paper-bias"),
            &format!("Tracks, paper DVL bias +-0.5 m/s (seed {seed})"),
            "east [m]",
            "north [m]",
            &ls,
        )?;
        let pt = pc("t");
        let errs: Vec<(&str, Vec<f64>)> = [
            ("pure INS", "pure_error_m"),
            ("INS-DVL", "ins_dvl_error_m"),
            ("VKF-aided", "vkf_error_m"),
        ]
        .iter()
        .map(|(l, k)| (*l, pc(k)))
        .collect();
        let ls: Vec<Line<'_>> = errs
            .iter()
            .map(|(label, y)| Line { label, x: &pt, y })
            .collect();
        plot::lines(
            &svg("fig12-errors-paper-bias"),
            &format!("Horizontal error, paper DVL bias +-0.5 m/s (seed {seed})"),
            "t [s]",
            "horizontal error [m]",
            &ls,
        )?;
    }
    Ok(())
}
