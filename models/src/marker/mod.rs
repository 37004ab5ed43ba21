//! MARKER-9 (docs/models/marker9.md): marker-aided navigation of a hover-capable
//! AUV at the test jacket, with planning and path following in closed loop; the
//! `marker-path` scenario of `navsim`.
//!
//! Each run plans once (RRT-Connect through the inspection waypoints), then flies
//! the same seed with each of the three path-following laws (LOS, improved LOS,
//! convex correction). The contract keys report the default law (the convex
//! correction); `by_law` holds every law's figures.

pub mod model;
pub mod simulation;

use std::path::Path as FsPath;

use nav_runtime::guidance::structure::Structure;
use nav_runtime::guidance::Law;
use nav_runtime::stats;
use plotters::prelude::*;
use serde_json::{json, Map, Value};

use crate::harness::report::summary_value;
use crate::harness::{metric_values, RunError, RunOptions, RunResult, RunTable, Scenario};
use simulation::{inspection_waypoints, plan, run_mission, MissionConfig};

pub use model::{Marker9, Marker9Depth, Marker9Dvl, Marker9MarkerFix};

/// The law whose figures fill the contract keys.
pub const DEFAULT_LAW: Law = Law::ConvexCorrection;

/// `navsim scenario marker-path`.
#[derive(Clone, Copy, Debug, Default)]
pub struct MarkerPath;

fn key(law: Law, name: &str) -> String {
    format!("{}.{name}", law.name())
}

/// Plans and flies run `seed` with every law.
pub fn run_one(seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
    let structure = Structure::test_jacket();
    let base = MissionConfig::default();
    let planned = plan(&structure, &base, seed)
        .map_err(|e| RunError::Invalid(format!("seed {seed}: {e}")))?;
    let mut r = RunResult::new(seed)
        .with_metric("planning_time_s", planned.time_s)
        .with_metric("plan_vertices", planned.path.len() as f64)
        .with_metric("plan_nodes", planned.nodes as f64)
        .with_metric(
            "plan_length_m",
            nav_runtime::guidance::Path::new(planned.path.clone()).length(),
        );
    let detour = nav_runtime::guidance::rrt::plan_through(
        &structure,
        &simulation::detour_waypoints(),
        &base.rrt,
        nav_runtime::sensors::derive_seed(seed, "marker-rrt-detour"),
    )
    .map_err(|e| RunError::Invalid(format!("seed {seed}: detour query: {e}")))?;
    r.metrics
        .insert("planning_time_detour_s".into(), detour.time_s);
    r.metrics
        .insert("plan_nodes_detour".into(), detour.nodes as f64);
    let mut extra = Map::new();
    for law in Law::ALL {
        let cfg = MissionConfig { law, ..base };
        let m = run_mission(&structure, &planned, &cfg, seed);
        for (name, v) in [
            ("path_rms_true_m", m.path_rms_true),
            ("path_rms_estimated_m", m.path_rms_estimated),
            ("collisions", f64::from(m.collisions)),
            ("min_clearance_m", m.min_clearance),
            ("finished", if m.finished { 1.0 } else { 0.0 }),
            ("duration_s", m.duration),
            ("qp_solved", m.qp_solved as f64),
            ("qp_fallbacks", m.qp_fallbacks as f64),
            ("fixes_accepted", m.fixes_accepted as f64),
            ("fixes_gated", m.fixes_gated as f64),
            ("current_error_mps", m.current_error),
            ("position_nees", m.position_nees),
        ] {
            r.metrics.insert(key(law, name), v);
        }
        if law == DEFAULT_LAW {
            extra.insert("qp_times_ms".into(), json!(m.qp_times_ms));
        }
        if options.keep_series {
            let mut table = RunTable::new(
                &format!("track-{}", law.name()),
                &[
                    "t",
                    "x",
                    "y",
                    "z",
                    "x_est",
                    "y_est",
                    "z_est",
                    "sigma_n",
                    "sigma_e",
                    "sigma_d",
                    "path_error_true",
                    "path_error_est",
                    "clearance",
                ],
            );
            for s in &m.track {
                table.push(&[
                    s.t,
                    s.truth.x,
                    s.truth.y,
                    s.truth.z,
                    s.estimate.x,
                    s.estimate.y,
                    s.estimate.z,
                    s.sigma.x,
                    s.sigma.y,
                    s.sigma.z,
                    s.path_error_true,
                    s.path_error_estimated,
                    s.clearance,
                ]);
            }
            r.tables.push(table);
        }
    }
    if options.keep_series {
        let mut table = RunTable::new("plan", &["x", "y", "z"]);
        for p in &planned.path {
            table.push(&[p.x, p.y, p.z]);
        }
        r.tables.push(table);
    }
    r.extra = Value::Object(extra);
    Ok(r)
}

/// The figures of one law over runs.
fn law_summary(runs: &[RunResult], law: Law) -> Value {
    let v = |name: &str| metric_values(runs, &key(law, name));
    let total = |name: &str| v(name).iter().sum::<f64>();
    let mut m = Map::new();
    m.insert(
        "path_rms_true_m".into(),
        summary_value(&v("path_rms_true_m")),
    );
    m.insert(
        "path_rms_estimated_m".into(),
        summary_value(&v("path_rms_estimated_m")),
    );
    m.insert("collisions".into(), json!(total("collisions")));
    m.insert(
        "min_clearance_m".into(),
        json!(stats::min(&v("min_clearance_m"))),
    );
    m.insert("finished_runs".into(), json!(total("finished")));
    m.insert("duration_s".into(), summary_value(&v("duration_s")));
    if law == Law::ConvexCorrection {
        m.insert("qp_solved".into(), json!(total("qp_solved")));
        m.insert("qp_fallbacks".into(), json!(total("qp_fallbacks")));
    }
    Value::Object(m)
}

/// The comparison table (text, for stderr / docs/results/marker9.md).
pub fn comparison_table(by_law: &Map<String, Value>) -> String {
    let mut out = String::from(
        "law           rms true med/max [m]   rms est med/max [m]   collisions  min clearance [m]  fallbacks\n",
    );
    for law in Law::ALL {
        let Some(l) = by_law.get(law.name()) else {
            continue;
        };
        let f = |k: &str, s: &str| l[k][s].as_f64().unwrap_or(f64::NAN);
        out.push_str(&format!(
            "{:<13} {:>8.3} / {:<8.3}     {:>8.3} / {:<8.3}    {:>6}      {:>8.3}         {}\n",
            law.name(),
            f("path_rms_true_m", "median"),
            f("path_rms_true_m", "max"),
            f("path_rms_estimated_m", "median"),
            f("path_rms_estimated_m", "max"),
            l["collisions"],
            l["min_clearance_m"].as_f64().unwrap_or(f64::NAN),
            l.get("qp_fallbacks")
                .map_or("-".to_string(), |v| v.to_string()),
        ));
    }
    out
}

impl Scenario for MarkerPath {
    fn name(&self) -> &'static str {
        "marker-path"
    }
    fn description(&self) -> &'static str {
        "MARKER-9 at the test jacket: RRT plan, LOS / improved LOS / convex correction in closed loop"
    }
    fn default_runs(&self) -> usize {
        10
    }
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
        run_one(seed, options)
    }
    fn summarize(
        &self,
        runs: &[RunResult],
        _options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError> {
        let d = DEFAULT_LAW;
        let mut m = Map::new();
        m.insert("law".into(), json!(d.name()));
        m.insert(
            "path_rms_true_m".into(),
            summary_value(&metric_values(runs, &key(d, "path_rms_true_m"))),
        );
        m.insert(
            "path_rms_estimated_m".into(),
            summary_value(&metric_values(runs, &key(d, "path_rms_estimated_m"))),
        );
        m.insert(
            "planning_time_s".into(),
            summary_value(&metric_values(runs, "planning_time_s")),
        );
        let collisions: f64 = metric_values(runs, &key(d, "collisions")).iter().sum();
        m.insert("collisions".into(), json!(collisions));
        // Pooled over every call of every run.
        let times: Vec<f64> = runs
            .iter()
            .filter_map(|r| r.extra.get("qp_times_ms").and_then(Value::as_array))
            .flat_map(|a| a.iter().filter_map(Value::as_f64))
            .collect();
        m.insert("qp_solve_time_ms".into(), summary_value(&times));
        m.insert("qp_calls".into(), json!(times.len()));
        m.insert(
            "qp_fallbacks".into(),
            json!(metric_values(runs, &key(d, "qp_fallbacks"))
                .iter()
                .sum::<f64>()),
        );
        m.insert(
            "planning_time_detour_s".into(),
            summary_value(&metric_values(runs, "planning_time_detour_s")),
        );
        m.insert(
            "plan_nodes_detour".into(),
            summary_value(&metric_values(runs, "plan_nodes_detour")),
        );
        m.insert(
            "plan_vertices".into(),
            summary_value(&metric_values(runs, "plan_vertices")),
        );
        m.insert(
            "plan_length_m".into(),
            summary_value(&metric_values(runs, "plan_length_m")),
        );
        m.insert(
            "position_nees".into(),
            summary_value(&metric_values(runs, &key(d, "position_nees"))),
        );
        m.insert(
            "current_error_mps".into(),
            summary_value(&metric_values(runs, &key(d, "current_error_mps"))),
        );
        m.insert(
            "fixes_accepted".into(),
            summary_value(&metric_values(runs, &key(d, "fixes_accepted"))),
        );
        let mut by_law = Map::new();
        for law in Law::ALL {
            by_law.insert(law.name().into(), law_summary(runs, law));
        }
        eprint!("{}", comparison_table(&by_law));
        m.insert("by_law".into(), Value::Object(by_law));
        Ok(m)
    }
    fn write_outputs(&self, runs: &[RunResult], dir: &FsPath) -> Result<(), RunError> {
        crate::harness::write_run_tables(runs, dir)?;
        if let Some(first) = runs.first() {
            draw_run(
                first,
                &dir.join(format!("marker-path-run-{}.svg", first.seed)),
            )?;
        }
        Ok(())
    }
}

/// Plan view and side view of the structure, the plan, and the true and estimated
/// tracks of the default law for one run.
pub fn draw_run(run: &RunResult, file: &FsPath) -> Result<(), RunError> {
    let err = |e: &dyn std::fmt::Display| RunError::Plot {
        path: file.to_path_buf(),
        message: e.to_string(),
    };
    let table = |name: &str| run.tables.iter().find(|t| t.name == name);
    let plan_t = table("plan").ok_or_else(|| err(&"no plan table (run with --out)"))?;
    let track =
        table(&format!("track-{}", DEFAULT_LAW.name())).ok_or_else(|| err(&"no track table"))?;
    let s = Structure::test_jacket();
    let root = SVGBackend::new(file, (1200, 620)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (left, right) = root.split_horizontally(600);
    // (horizontal axis column, vertical axis column, axis labels, ranges, flip)
    let views = [
        (
            left,
            "y",
            "x",
            "east [m]",
            "north [m]",
            (-4.5, 4.5),
            (-4.5, 4.5),
        ),
        (
            right,
            "x",
            "z",
            "north [m]",
            "depth [m] (down)",
            (-4.5, 4.5),
            (22.5, 9.5),
        ),
    ];
    for (area, hc, vc, hl, vl, hr, vr) in views {
        let mut chart = ChartBuilder::on(&area)
            .caption(
                format!(
                    "marker-path seed {}: {} view",
                    run.seed,
                    if vc == "z" { "side" } else { "plan" }
                ),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(48)
            .build_cartesian_2d(hr.0..hr.1, vr.0..vr.1)
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc(hl)
            .y_desc(vl)
            .draw()
            .map_err(|e| err(&e))?;
        let pick = |v: &nav_runtime::nalgebra::Vector3<f64>, c: &str| match c {
            "x" => v.x,
            "y" => v.y,
            _ => v.z,
        };
        for c in &s.capsules {
            let w = (c.radius * 2.0 * 600.0 / 9.0).max(2.0) as u32;
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![
                        (pick(&c.a, hc), pick(&c.a, vc)),
                        (pick(&c.b, hc), pick(&c.b, vc)),
                    ],
                    RGBColor(120, 120, 120).stroke_width(w),
                )))
                .map_err(|e| err(&e))?;
        }
        chart
            .draw_series(s.markers.iter().map(|m| {
                Circle::new(
                    (pick(&m.position, hc), pick(&m.position, vc)),
                    3,
                    RGBColor(255, 127, 14).filled(),
                )
            }))
            .map_err(|e| err(&e))?
            .label("markers")
            .legend(|(x, y)| Circle::new((x + 8, y), 3, RGBColor(255, 127, 14).filled()));
        let col = |t: &RunTable, name: &str| t.column(name);
        let series = [
            (
                col(plan_t, hc),
                col(plan_t, vc),
                RGBColor(44, 160, 44),
                "plan",
                3u32,
            ),
            (
                col(track, hc),
                col(track, vc),
                RGBColor(31, 119, 180),
                "true",
                1,
            ),
            (
                col(track, &format!("{hc}_est")),
                col(track, &format!("{vc}_est")),
                RGBColor(214, 39, 40),
                "estimated",
                1,
            ),
        ];
        for (xs, ys, color, label, width) in series {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    xs.iter()
                        .zip(&ys)
                        .map(|(a, b)| (*a, *b))
                        .collect::<Vec<_>>(),
                    color.stroke_width(width),
                )))
                .map_err(|e| err(&e))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
                });
        }
        let w: Vec<(f64, f64)> = inspection_waypoints()
            .iter()
            .map(|p| (pick(p, hc), pick(p, vc)))
            .collect();
        chart
            .draw_series(
                w.into_iter()
                    .map(|p| Cross::new(p, 5, BLACK.stroke_width(2))),
            )
            .map_err(|e| err(&e))?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerRight)
            .draw()
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::guidance::rrt::RrtConfig;

    /// MARKER-9 consistency on a short run: the horizontal position NEES over the
    /// first 60 s of a mission stays near its 2 degrees of freedom, and the error
    /// stays within 3 sigma almost always.
    #[test]
    fn filter_is_consistent_on_a_short_run() {
        let s = Structure::test_jacket();
        let cfg = MissionConfig {
            max_time: 60.0,
            rrt: RrtConfig::default(),
            ..MissionConfig::default()
        };
        let mut nees = Vec::new();
        let mut outside = 0usize;
        let mut total = 0usize;
        for seed in 1..=4 {
            let p = plan(&s, &cfg, seed).unwrap();
            let m = run_mission(&s, &p, &cfg, seed);
            nees.push(m.position_nees);
            for t in &m.track {
                total += 2;
                for (e, sg) in [
                    (t.truth.x - t.estimate.x, t.sigma.x),
                    (t.truth.y - t.estimate.y, t.sigma.y),
                ] {
                    if e.abs() > 3.0 * sg {
                        outside += 1;
                    }
                }
            }
            assert!(
                m.fixes_accepted > 20,
                "seed {seed}: {} fixes",
                m.fixes_accepted
            );
        }
        let median = stats::median(&nees);
        eprintln!("MARKER-9 short-run NEES {nees:?}, {outside} of {total} beyond 3 sigma");
        // Samples are strongly correlated in time (a few independent values per
        // run), so no chi-square band applies to one run; the filter's position
        // covariance must be within a factor of two of the error's: NEES in
        // [1, 4] for 2 degrees of freedom, for the median and for every seed.
        assert!(
            (1.0..=4.0).contains(&median),
            "median NEES {median} ({nees:?})"
        );
        assert!(nees.iter().all(|&v| (1.0..=4.0).contains(&v)), "{nees:?}");
        // 2-D Gaussian errors leave 0.27 % of each axis beyond 3 sigma.
        assert!(
            (outside as f64) < 0.02 * total as f64,
            "{outside} of {total} beyond 3 sigma"
        );
    }
}
