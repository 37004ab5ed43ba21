//! `[sensors.usbl] misalignment_sigma` sets the USBL array misalignment prior
//! of the SDINS-25 filter, independently of the USBL bias sigma; without the
//! key the older rule holds (a bias sigma above zero means the 0.5 deg
//! Trackpoint II prior).

use models::sdins25::filter::{initial_filter, FilterOptions};
use models::sdins25::simulation::{self, SimConfig, TRACKPOINT_MISALIGNMENT_SIGMA};
use models::sdins25::Sdins25;
use nav_runtime::log::SensorNoise;

#[test]
fn the_misalignment_prior_follows_the_explicit_key() {
    let config = SimConfig {
        duration: 2.0,
        ..SimConfig::usbl()
    };
    let base = simulation::simulate(&config, 1).log;
    // (USBL bias sigma, misalignment_sigma key, prior expected), rad.
    let cases = [
        (0.5, None, TRACKPOINT_MISALIGNMENT_SIGMA),
        (0.0, None, 0.0),
        (0.5, Some(0.0), 0.0),
        (0.5, Some(1e-3), 1e-3),
        (0.0, Some(2e-3), 2e-3),
    ];
    for (bias, key, want) in cases {
        let mut log = base.clone();
        log.meta.sensors.usbl = Some(SensorNoise {
            bias_sigma: bias,
            noise_sigma: 2.0,
        });
        log.meta.sensors.usbl_misalignment_sigma = key;
        let f = initial_filter(&log, &FilterOptions::default()).unwrap();
        let p = f.covariance();
        for i in Sdins25::USBL_MISALIGNMENT..Sdins25::USBL_MISALIGNMENT + 3 {
            // A zero prior is floored at 1e-9 by the filter's setup.
            let sigma = p[(i, i)].sqrt();
            assert!(
                (sigma - want).abs() <= 1e-8,
                "bias {bias}, key {key:?}: sigma {sigma}, expected {want}"
            );
        }
    }
}
