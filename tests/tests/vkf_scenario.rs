//! The VKF scenario (docs/results/vkf.md) on a few seeds: pure INS, conventional
//! INS-DVL and VKF-aided navigation on the same data, realistic DVL bias.
//!
//! Physical margins:
//! - pure INS drifts by kilometres: a 0.1 deg/h gyro bias alone gives
//!   `g eps t^3 / 6` = 3.4 km in 27 min (Schuler-limited to about 2.7 km),
//!   while both aided solutions stay near the DVL's own error (scale factor
//!   +-0.2 % and bias +-0.005 m/s over 8.3 km: at most about 25 m);
//! - during the outages the INS-DVL solution drifts with the unestimated tilt
//!   (`g eps t^3 / 6` = 5 m per axis over 190 s) and the frozen accelerometer-bias
//!   estimate, while the VKF solution drifts only with the RPM-derived speed
//!   error (about 1 cm/s, i.e. about 2 m over 190 s).

use models::vkf::{run_log, simulation, SOLUTIONS};

const SEEDS: [u64; 3] = [1, 2, 3];

#[test]
fn ordering_vkf_ins_dvl_pure_ins() {
    let mut drift = [[0.0; 3]; SEEDS.len()];
    let mut finals = [[0.0; 3]; SEEDS.len()];
    let mut coupled_scores = Vec::new();
    for (i, &seed) in SEEDS.iter().enumerate() {
        let logs = simulation::simulate(seed);
        let (run, s) = run_log(&logs.realistic).unwrap();
        assert!(
            run.refused.0 + run.refused.1 <= 2,
            "seed {seed}: {:?}",
            run.refused
        );
        assert!((8000.0..8700.0).contains(&s.distance_m), "{}", s.distance_m);
        // Two outages near 5-8 min and 15-16 min.
        assert_eq!(s.outages.len(), 2, "seed {seed}: {:?}", s.outages);
        for (sc, name) in s.scores.iter().zip(SOLUTIONS) {
            eprintln!(
                "seed {seed} {name}: final {:.2} m, rms {:.2} m, max {:.2} m, outage drift {:.2} m",
                sc.final_m, sc.rms_m, sc.max_m, sc.outage_drift_m
            );
        }
        let [pure, ins_dvl, vkf, coupled] = s.scores;
        coupled_scores.push((coupled, ins_dvl, s.dvl_error_integral_m));
        eprintln!(
            "seed {seed}: outage rms coupled {:.2} / ins-dvl {:.2} m, final coupled {:.2} / ins-dvl {:.2} m, DVL error integral {:.2} m",
            coupled.outage_rms_m, ins_dvl.outage_rms_m, coupled.final_m, ins_dvl.final_m, s.dvl_error_integral_m
        );
        for (o, span) in s.outage_scores.iter().zip(&s.outages) {
            eprintln!("  outage {span:?}: {:?}", o.scores);
        }
        drift[i] = [
            pure.outage_drift_m,
            ins_dvl.outage_drift_m,
            vkf.outage_drift_m,
        ];
        finals[i] = [pure.final_m, ins_dvl.final_m, vkf.final_m];
        // Pure INS: kilometres against tens of metres.
        assert!(
            pure.final_m > 20.0 * ins_dvl.final_m.max(vkf.final_m),
            "seed {seed}"
        );
        assert!(pure.final_m > 300.0, "seed {seed}");
        // VKF: within 0.3 % of the distance travelled.
        assert!(
            vkf.final_m < 3e-3 * s.distance_m,
            "seed {seed}: {}",
            vkf.final_m
        );
        // During the outages the RPM-derived velocity holds the VKF solution;
        // the conventional filter coasts on the inertial solution.
        assert!(
            vkf.outage_drift_m < 4.0,
            "seed {seed}: {}",
            vkf.outage_drift_m
        );
        assert!(
            vkf.outage_drift_m < 0.5 * ins_dvl.outage_drift_m,
            "seed {seed}"
        );
        assert!(vkf.max_m <= ins_dvl.max_m + 0.5, "seed {seed}");
    }
    // Over the seeds: VKF < INS-DVL < pure INS in the outage drift (pure INS
    // coasts on its accumulated velocity error, 0.5-1.5 m/s by 5 min), and in the
    // final error VKF is not worse than INS-DVL by more than the RPM-speed
    // error over the outages (2 cm/s x 260 s = 5 m).
    let median = |k: usize, xs: &[[f64; 3]]| {
        let mut v: Vec<f64> = xs.iter().map(|x| x[k]).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    assert!(median(2, &drift) < 0.5 * median(1, &drift));
    assert!(median(1, &drift) < median(0, &drift) / 3.0);
    assert!(median(2, &finals) < median(1, &finals) + 5.0);
    assert!(median(1, &finals) < 0.05 * median(0, &finals));
    // The speed map inside the integrated filter (20-seed medians, docs:
    // outage RMS 0.45 of INS-DVL's): inside the outages its error stays under
    // half of INS-DVL's on every seed here (measured 0.18, 0.46, 0.40), and
    // its final error is the DVL's own integrated error plus at most 0.5 m
    // (measured -0.13, -0.02, +0.23 m): what the outages added was taken back.
    for (i, (coupled, ins_dvl, dvl_floor)) in coupled_scores.iter().enumerate() {
        let seed = SEEDS[i];
        assert!(
            coupled.outage_rms_m < 0.5 * ins_dvl.outage_rms_m,
            "seed {seed}: {} vs {}",
            coupled.outage_rms_m,
            ins_dvl.outage_rms_m
        );
        assert!(
            coupled.final_m < dvl_floor + 0.5,
            "seed {seed}: final {} vs DVL error integral {dvl_floor}",
            coupled.final_m
        );
    }
}
