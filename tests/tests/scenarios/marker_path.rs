//! `marker-path` on two seeds: the closed loop (MARKER-9 estimate -> guidance ->
//! vehicle) flies the planned inspection route without touching the jacket.
//!
//! Thresholds, from the geometry: the plan keeps 0.3 m of clearance beyond
//! contact (capsule radius plus the 0.3 m vehicle radius), so a route flown with
//! a path RMS below 0.3 m and no excursion beyond that margin never touches;
//! MARKER-9 with fixes every few seconds and a 0.01 m/s DVL keeps the estimate
//! within about 0.1 m, so estimated and true RMS differ by less than that.

use models::harness::RunOptions;
use models::registry::find_scenario;

#[test]
fn marker_path_two_seeds() {
    let s = find_scenario("marker-path").expect("registered");
    let options = RunOptions::default();
    let runs: Vec<_> = [1u64, 2]
        .iter()
        .map(|&seed| s.run_one(seed, &options).expect("run"))
        .collect();
    for r in &runs {
        let m = |k: &str| r.metric(k);
        assert!(
            m("planning_time_s") < 0.5,
            "planning {} s",
            m("planning_time_s")
        );
        for law in ["los", "improved_los", "convex"] {
            assert_eq!(
                m(&format!("{law}.finished")),
                1.0,
                "seed {} {law} did not finish",
                r.seed
            );
        }
        assert_eq!(m("convex.collisions"), 0.0, "seed {}", r.seed);
        assert!(m("convex.min_clearance_m") > 0.0);
        assert!(
            m("convex.path_rms_true_m") < 0.3,
            "seed {}: {}",
            r.seed,
            m("convex.path_rms_true_m")
        );
        let gap = (m("convex.path_rms_true_m") - m("convex.path_rms_estimated_m")).abs();
        assert!(
            gap < 0.1,
            "seed {}: true vs estimated RMS gap {gap}",
            r.seed
        );
        let calls = m("convex.qp_solved") + m("convex.qp_fallbacks");
        assert!(
            m("convex.qp_fallbacks") <= 0.01 * calls,
            "fallbacks {}",
            m("convex.qp_fallbacks")
        );
        assert!(m("convex.fixes_accepted") > 50.0);
    }
    let summary = s.summarize(&runs, &options).expect("summary");
    for k in [
        "path_rms_true_m",
        "path_rms_estimated_m",
        "planning_time_s",
        "qp_solve_time_ms",
    ] {
        for stat in ["median", "p95", "max"] {
            assert!(summary[k][stat].is_number(), "{k}.{stat}");
        }
    }
    assert!(summary["collisions"].is_number());
    assert!(summary["by_law"]["improved_los"]["path_rms_true_m"]["median"].is_number());
}
