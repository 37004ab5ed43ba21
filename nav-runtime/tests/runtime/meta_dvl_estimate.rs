//! `[sensors.dvl] estimate` of meta.toml: what it accepts, its prior
//! sigmas, and each mistake as an error naming the key and line.

use nav_runtime::log::{
    DvlCalibration, LogError, Meta, LEVER_ARM_SIGMA_DEFAULT, MISALIGNMENT_SIGMA_DEFAULT,
    SCALE_SIGMA_DEFAULT, TIME_OFFSET_SIGMA_DEFAULT,
};

const HEAD: &str =
    "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.dvl]\nnoise_sigma = 0.02\n";

fn parse(keys: &str) -> Result<Meta, LogError> {
    Meta::parse(&format!("{HEAD}{keys}"))
}

#[test]
fn estimate_lists_any_subset_with_prior_sigmas() {
    // (keys, expected calibration)
    let cases = [
        ("", DvlCalibration::default()),
        ("estimate = []\n", DvlCalibration::default()),
        (
            "estimate = [\"scale\", \"lever_arm\"]\n",
            DvlCalibration {
                lever_arm: Some(LEVER_ARM_SIGMA_DEFAULT),
                misalignment: None,
                scale: Some(SCALE_SIGMA_DEFAULT),
                time_offset: None,
            },
        ),
        (
            "estimate = [\"lever_arm\", \"misalignment\", \"scale\"]\nlever_arm_sigma = 1.5\nmisalignment_sigma = 0.01\nscale_sigma = 0.005\n",
            DvlCalibration {
                lever_arm: Some(1.5),
                misalignment: Some(0.01),
                scale: Some(0.005),
                time_offset: None,
            },
        ),
        (
            "estimate = [\"misalignment\"]\n",
            DvlCalibration {
                lever_arm: None,
                misalignment: Some(MISALIGNMENT_SIGMA_DEFAULT),
                scale: None,
                time_offset: None,
            },
        ),
        (
            "estimate = [\"time_offset\"]\n",
            DvlCalibration {
                time_offset: Some(TIME_OFFSET_SIGMA_DEFAULT),
                ..DvlCalibration::default()
            },
        ),
        (
            "estimate = [\"time_offset\", \"scale\"]\ntime_offset_sigma = 2.5\n",
            DvlCalibration {
                scale: Some(SCALE_SIGMA_DEFAULT),
                time_offset: Some(2.5),
                ..DvlCalibration::default()
            },
        ),
    ];
    for (keys, expected) in cases {
        let meta = parse(keys).unwrap_or_else(|e| panic!("{keys:?}: {e}"));
        assert_eq!(meta.sensors.dvl_calibration, expected, "{keys:?}");
        // Written back and read again: the same.
        let again = Meta::parse(&meta.to_toml()).expect("round trip");
        assert_eq!(
            again.sensors.dvl_calibration, expected,
            "{keys:?} round trip"
        );
    }
}

#[test]
fn estimate_mistakes_are_errors_naming_the_key() {
    // (what, keys, key named, line, words of the message)
    let cases: [(&str, &str, &str, u64, &[&str]); 15] = [
        (
            "unknown name",
            "estimate = [\"lever_arms\"]\n",
            "sensors.dvl.estimate",
            7,
            &[
                "unknown name `lever_arms`",
                "lever_arm, misalignment, scale",
                "did you mean `lever_arm`",
            ],
        ),
        (
            "duplicate",
            "estimate = [\"scale\", \"scale\"]\n",
            "sensors.dvl.estimate",
            7,
            &["`scale` is listed twice"],
        ),
        (
            "a string, not an array",
            "estimate = \"scale\"\n",
            "sensors.dvl.estimate",
            7,
            &["expected an array", "found string"],
        ),
        (
            "a number in the list",
            "estimate = [\"scale\", 1]\n",
            "sensors.dvl.estimate",
            7,
            &["names (strings)", "integer"],
        ),
        (
            "a lag sigma in milliseconds",
            "estimate = [\"time_offset\"]\ntime_offset_sigma = 500\n",
            "sensors.dvl.time_offset_sigma",
            8,
            &["out of range", "<= 10 s", "milliseconds?"],
        ),
        (
            "a negative lag sigma",
            "estimate = [\"time_offset\"]\ntime_offset_sigma = -1\n",
            "sensors.dvl.time_offset_sigma",
            8,
            &["out of range"],
        ),
        (
            "no GNSS misalignment",
            "[sensors.gnss]\nnoise_sigma = 1\nestimate = [\"misalignment\"]\n",
            "sensors.gnss.estimate",
            9,
            &[
                "`misalignment` is not estimated for the gnss",
                "accepted: lever_arm, time_offset",
            ],
        ),
        (
            "a USBL scale sigma",
            "[sensors.usbl]\nnoise_sigma = 1\nestimate = [\"time_offset\"]\nscale_sigma = 0.01\n",
            "sensors.usbl.scale_sigma",
            10,
            &["unknown key"],
        ),
        (
            "sigma without the name",
            "estimate = [\"scale\"]\nlever_arm_sigma = 1\n",
            "sensors.dvl.lever_arm_sigma",
            8,
            &["`lever_arm`", "does not list"],
        ),
        (
            "zero prior sigma",
            "estimate = [\"scale\"]\nscale_sigma = 0\n",
            "sensors.dvl.scale_sigma",
            8,
            &["out of range"],
        ),
        (
            "misalignment sigma in degrees",
            "estimate = [\"misalignment\"]\nmisalignment_sigma = 5\n",
            "sensors.dvl.misalignment_sigma",
            8,
            &["degrees?"],
        ),
        (
            "the USBL's misalignment is its block's",
            "[sensors.usbl]\nnoise_sigma = 1\nestimate = [\"misalignment\"]\n",
            "sensors.usbl.estimate",
            9,
            &[
                "`misalignment` is not estimated for the usbl",
                "accepted: lever_arm",
                "misalignment_sigma",
            ],
        ),
        (
            "no GNSS scale",
            "[sensors.gnss]\nnoise_sigma = 1\nestimate = [\"scale\"]\n",
            "sensors.gnss.estimate",
            9,
            &[
                "`scale` is not estimated for the gnss",
                "accepted: lever_arm",
            ],
        ),
        (
            "no estimate for the depth meter",
            "[sensors.depth]\nnoise_sigma = 1\nestimate = [\"lever_arm\"]\n",
            "sensors.depth.estimate",
            9,
            &["unknown key"],
        ),
        (
            "misspelt sigma key",
            "estimate = [\"scale\"]\nscale_sigm = 0.01\n",
            "sensors.dvl.scale_sigm",
            8,
            &["unknown key", "did you mean `scale_sigma`"],
        ),
    ];
    for (what, keys, key, line, words) in cases {
        let Err(e) = parse(keys) else {
            panic!("{what}: accepted");
        };
        let LogError::Meta {
            key: k,
            line: l,
            problem,
        } = &e
        else {
            panic!("{what}: {e:?}");
        };
        assert_eq!(k, key, "{what}: {e}");
        assert_eq!(*l, Some(line), "{what}: {e}");
        for w in words {
            assert!(problem.contains(w), "{what}: {problem:?} lacks {w:?}");
        }
    }
    // Only the DVL's section has the key.
    let text = "[initial]\nlat = 0.1\nlon = 0.2\ndepth = 3\n[sensors.depth]\nnoise_sigma = 0.1\nestimate = [\"scale\"]\n";
    assert!(
        matches!(Meta::parse(text), Err(LogError::Meta { key, .. }) if key == "sensors.depth.estimate")
    );
}

/// `[sensors.usbl]` and `[sensors.gnss]` take `estimate = ["lever_arm",
/// "time_offset"]` (the transponder's or the antenna's arm, the lag of the
/// fixes' clock; any subset), with the DVL's default priors, and write it
/// back.
#[test]
fn usbl_and_gnss_estimate_their_lever_arm_and_clock_lag() {
    for sensor in ["usbl", "gnss"] {
        // (keys, lever-arm prior, lag prior)
        for (keys, arm, lag) in [
            (
                "estimate = [\"lever_arm\"]\n",
                Some(LEVER_ARM_SIGMA_DEFAULT),
                None,
            ),
            (
                "estimate = [\"lever_arm\"]\nlever_arm_sigma = 2.0\n",
                Some(2.0),
                None,
            ),
            (
                "estimate = [\"time_offset\"]\n",
                None,
                Some(TIME_OFFSET_SIGMA_DEFAULT),
            ),
            (
                "estimate = [\"time_offset\", \"lever_arm\"]\ntime_offset_sigma = 1.5\n",
                Some(LEVER_ARM_SIGMA_DEFAULT),
                Some(1.5),
            ),
        ] {
            let text = format!("[sensors.{sensor}]\nnoise_sigma = 1\n{keys}");
            let meta = parse(&text).unwrap_or_else(|e| panic!("{sensor} {keys:?}: {e}"));
            let expected = DvlCalibration {
                lever_arm: arm,
                time_offset: lag,
                ..DvlCalibration::default()
            };
            assert_eq!(meta.sensors.calibration(sensor), expected, "{sensor}");
            assert_eq!(meta.sensors.dvl_calibration, DvlCalibration::default());
            let again = Meta::parse(&meta.to_toml()).expect("round trip");
            assert_eq!(again.sensors.calibration(sensor), expected, "{sensor}");
        }
    }
}
