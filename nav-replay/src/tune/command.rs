//! `navsim tune LOG --model NAME` (and `tune` of a vehicle's replay
//! program): the tuning of [`super::tune`] with the preflight beside it, a
//! progress bar, the JSON or human report and `--write`.

use std::path::PathBuf;

use clap::Args;
use serde_json::Value;

use nav_runtime::log::{Warning, WarningKind};

use super::{
    tune, tuned_mapping_text, tuned_mapping_values, tuned_meta_text, LogTuning, Tunable,
    TuneOptions, Tuning,
};
use crate::preflight;
use crate::program::{emit, open_log, preflight_options, warnings_json};
use crate::{progress_bar, ReplayModel, ReplayOptions, RunError};

/// What every `tune` command takes: the parameters, the output and the
/// budget.
#[derive(Debug, Args)]
pub struct TuneFlags {
    /// The keys to tune, comma-separated (`sensors.dvl.noise_sigma`,
    /// `sensors.imu.accel_bias_sigma`; `sensors.Fix.sigma`, `noise.speed_noise`
    /// for a declared model's mapping); default: every sensor's noise sigma
    /// (and the IMU's two for an INS vehicle).
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub params: Vec<String>,
    /// Write the log's meta.toml (or the mapping) with the tuned values to
    /// this file.
    #[arg(long)]
    pub write: Option<PathBuf>,
    /// Most forward replays of the log.
    #[arg(long, default_value_t = super::DEFAULT_MAX_REPLAYS, value_name = "N")]
    pub max_replays: usize,
}

/// `navsim tune`.
#[derive(Debug, Args)]
pub struct TuneArgs {
    /// Log directory.
    pub dir: PathBuf,
    /// Model name.
    #[arg(long)]
    pub model: String,
    /// The parameters, the output and the budget.
    #[command(flatten)]
    pub flags: TuneFlags,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Skip (and count) bad CSV rows instead of stopping.
    #[arg(long)]
    pub lenient: bool,
    /// An IMU interval longer than this many IMU periods is a gap (an error,
    /// a warning with --lenient).
    #[arg(long, default_value_t = 10.0, value_name = "N")]
    pub max_gap_periods: f64,
    /// Write the log's replay.toml with the tuned sigmas of the sensors it
    /// feeds by name (a vehicle's own sensors) to this file.
    #[arg(long, value_name = "FILE")]
    pub write_mapping: Option<PathBuf>,
}

/// [`tune`] of `t` as `flags` ask, with a progress bar on a terminal.
///
/// # Errors
/// As [`tune`].
pub fn tune_with_progress(t: &dyn Tunable, flags: &TuneFlags) -> Result<Tuning, RunError> {
    let options = TuneOptions {
        params: flags.params.clone(),
        max_replays: flags.max_replays,
    };
    let bar = progress_bar(flags.max_replays, false);
    let progress = |done: usize, budget: usize| {
        bar.set_length(budget as u64);
        bar.set_position(done as u64);
    };
    let tuning = tune(t, &options, &progress);
    bar.finish_and_clear();
    tuning
}

/// The warnings of a tuning for its JSON: its notes, the parameters the
/// log does not identify, a budget of `max_replays` that ran out, and the
/// tuned run's own warnings but not its noise-sigma verdicts (the tuning's
/// report says what the log identifies). Printed on stderr as well.
pub fn tuning_warnings(tuning: &Tuning, max_replays: usize) -> Vec<Warning> {
    let mut warnings: Vec<Warning> = tuning
        .notes
        .iter()
        .map(|n| crate::model_note(n.clone()))
        .collect();
    warnings.extend(tuning.parameters.iter().filter_map(|p| {
        let why = p.not_identifiable.as_ref()?;
        Some(crate::model_note(format!("{}: not identifiable: {why}", p.key)).with_key(&p.key))
    }));
    if !tuning.converged {
        warnings.push(crate::model_note(format!(
            "the parameters still moved when the budget ran out (--max-replays {max_replays}: \
             {} replays made, the next step needing more): the values are the last step's",
            tuning.replays
        )));
    }
    warnings.extend(
        tuning
            .after
            .warnings
            .iter()
            .filter(|w| w.kind != WarningKind::NoiseSigma)
            .cloned(),
    );
    warnings.extend(tuned_through_recovery(tuning));
    warnings.extend(imu_noise_far_above_given(tuning));
    for w in &warnings {
        eprintln!("warning: {}", w.message);
    }
    warnings
}

/// A tuned noise sigma far (more than [`RECOVERY_SIGMA_FACTOR`] times either
/// way) from its given value, of a sensor from whose lock-out the replay
/// with the tuned values recovered: while the filter was wrong, that
/// sensor's innovations measured the filter's error rather than the
/// sensor's noise, and the sigma may describe the former (a wrong initial
/// state, most often). A warning keyed by the parameter, about the
/// sensor's file.
fn tuned_through_recovery(tuning: &Tuning) -> Vec<Warning> {
    let recovered: Vec<&Warning> = tuning
        .after
        .warnings
        .iter()
        .filter(|w| w.kind == WarningKind::LockoutRecovery)
        .collect();
    let mut out = Vec::new();
    for p in &tuning.parameters {
        let Some(sensor) = p
            .key
            .strip_prefix("sensors.")
            .and_then(|k| k.strip_suffix(".noise_sigma"))
        else {
            continue;
        };
        let file = format!("{sensor}.csv");
        let factor = p.value / p.initial;
        let far = !(1.0 / RECOVERY_SIGMA_FACTOR..=RECOVERY_SIGMA_FACTOR).contains(&factor);
        if !far
            || !recovered
                .iter()
                .any(|w| w.file.as_deref() == Some(file.as_str()))
        {
            continue;
        }
        out.push(
            Warning::about(
                WarningKind::Suspicious,
                &file,
                format!(
                    "{}: tuned to {:.4} ({factor:.1} times the given {}) with a replay that \
                     recovered from a lock-out of the {sensor}: while the filter was wrong its \
                     {sensor} innovations measured the filter's error, not the {sensor}'s noise, \
                     and the value may describe that; check the initial state (meta.toml \
                     [initial]) before using it",
                    p.key, p.value, p.initial
                ),
            )
            .with_key(&p.key),
        );
    }
    out
}

/// An IMU noise sigma (`sensors.imu.gyro_noise_sigma`,
/// `accel_noise_sigma`) identified at more than [`IMU_NOISE_FACTOR`] times
/// its given value. An IMU's noise is known to a factor of two from its
/// data sheet or an Allan deviation ([`crate::allan`]); the likelihood
/// raises it further when the aiding disagrees with the INS in a way the
/// model does not describe (a DVL lever arm, misalignment or clock), and a
/// gyro that noisy lets the aiding pull the attitude, the heading first.
/// A warning keyed by the parameter, in `meta.toml`.
fn imu_noise_far_above_given(tuning: &Tuning) -> Vec<Warning> {
    tuning
        .parameters
        .iter()
        .filter(|p| {
            matches!(
                p.key.as_str(),
                "sensors.imu.gyro_noise_sigma" | "sensors.imu.accel_noise_sigma"
            ) && p.not_identifiable.is_none()
                && p.value > IMU_NOISE_FACTOR * p.initial
        })
        .map(|p| {
            Warning::about(
                WarningKind::Suspicious,
                "meta.toml",
                format!(
                    "{}: tuned to {:.3e}, {:.0} times the given {:.3e}: far above an IMU's \
                     data sheet, the likelihood is making up for aiding that disagrees with the \
                     INS in a way the model does not describe (a lever arm, a misalignment or a \
                     clock of the DVL, say), and so noisy an IMU lets the aiding pull the \
                     attitude; estimate the mounting (a vehicle with calibration states, \
                     docs/calibration.md) or declare it, and tune again",
                    p.key,
                    p.value,
                    p.value / p.initial,
                    p.initial
                ),
            )
            .with_key(&p.key)
        })
        .collect()
}

/// How far above its given value a tuned IMU noise sigma must be for
/// [`imu_noise_far_above_given`] to doubt it.
pub const IMU_NOISE_FACTOR: f64 = 10.0;

/// How far (a factor either way) a tuned sigma must move from its given
/// value for [`tuned_through_recovery`] to doubt it.
pub const RECOVERY_SIGMA_FACTOR: f64 = 3.0;

/// `navsim tune` with `model` (`args.model` is not looked up).
///
/// # Errors
/// As [`tune`], a log the preflight refuses, and a `--write` that fails.
pub fn tune_with(model: &dyn ReplayModel, args: &TuneArgs) -> Result<(), RunError> {
    let (preflight_options, strictness) =
        preflight_options(args.lenient, args.max_gap_periods, model.log_files())?;
    let files = open_log(&args.dir, strictness)?;
    let tunable = LogTuning::new(
        model,
        &files,
        ReplayOptions {
            lenient: args.lenient,
            ..ReplayOptions::default()
        },
    )?;
    let (tuning, report, summary) =
        preflight::check_alongside(&files, &preflight_options, false, || {
            tune_with_progress(&tunable, &args.flags)
        })?;
    let mut value = tuning.json();
    let mut warnings = summary.warnings.clone();
    warnings.extend(files.rejected_warnings());
    warnings.extend(report.warnings().cloned());
    warnings.extend(tuning_warnings(&tuning, args.flags.max_replays));
    let identified = tuning.identified_values();
    if let Some(path) = &args.flags.write {
        let source = files.dir().join("meta.toml");
        let text = std::fs::read_to_string(&source).map_err(|e| RunError::io(&source, e))?;
        let tuned = tuned_meta_text(&text, &identified)?;
        std::fs::write(path, tuned).map_err(|e| RunError::io(path, e))?;
        value["written"] = Value::from(path.display().to_string());
    }
    // The sigmas of sensors fed by name and the own noise.
    let own = tuned_mapping_values(&tunable, &identified);
    match &args.write_mapping {
        Some(path) => {
            let source = files.dir().join(crate::model_replay::MAPPING_FILE);
            let text = std::fs::read_to_string(&source).map_err(|e| RunError::io(&source, e))?;
            let tuned = tuned_mapping_text(&text, crate::model_replay::MAPPING_FILE, &own)?;
            std::fs::write(path, tuned).map_err(|e| RunError::io(path, e))?;
            value["written_mapping"] = Value::from(path.display().to_string());
        }
        None if args.flags.write.is_some() && !own.is_empty() => warnings.push(
            Warning::about(
                WarningKind::Model,
                crate::model_replay::MAPPING_FILE,
                format!(
                    "{} tuned in {}: --write writes meta.toml only; --write-mapping FILE writes these",
                    own.iter().map(|(k, _)| k.as_str()).collect::<Vec<_>>().join(", "),
                    crate::model_replay::MAPPING_FILE
                ),
            )
            .with_key(&own[0].0),
        ),
        None => {}
    }
    if let Value::Object(m) = &mut value {
        m.insert("warnings".into(), warnings_json(&warnings));
    }
    emit(&value, args.json);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::{ParameterKind, Replayed, TunedParameter};
    use super::*;

    /// A tuning of one parameter, `key`, from `given` to `tuned`.
    fn tuning_of(key: &str, given: f64, tuned: f64, identified: bool) -> Tuning {
        Tuning {
            model: "m".into(),
            parameters: vec![TunedParameter {
                key: key.into(),
                kind: ParameterKind::Likelihood,
                initial: given,
                value: tuned,
                log_standard_error: 0.05,
                not_identifiable: (!identified).then(|| "flat".to_string()),
            }],
            replays: 10,
            converged: true,
            log_likelihood: (None, 0.0),
            notes: Vec::new(),
            nis: Default::default(),
            after: Replayed {
                innovations: Vec::new(),
                warnings: Vec::new(),
            },
        }
    }

    /// (key, given, tuned, identified, doubted): a gyro noise tuned from a
    /// FOG's 1e-5 to 1e-3 rad/s per sample is doubted; ten times or less, a
    /// sigma not identified (kept as given) or a sensor's sigma are not.
    #[test]
    fn an_imu_noise_tuned_far_above_its_data_sheet_is_doubted() {
        let cases: [(&str, f64, f64, bool, bool); 6] = [
            ("sensors.imu.gyro_noise_sigma", 1e-5, 1e-3, true, true),
            ("sensors.imu.accel_noise_sigma", 2e-3, 0.05, true, true),
            ("sensors.imu.gyro_noise_sigma", 1e-5, 9e-5, true, false),
            ("sensors.imu.gyro_noise_sigma", 1e-5, 1e-3, false, false),
            ("sensors.imu.gyro_noise_sigma", 1e-3, 1e-5, true, false),
            ("sensors.dvl.noise_sigma", 0.002, 0.2, true, false),
        ];
        for (key, given, tuned, identified, doubted) in cases {
            let w = imu_noise_far_above_given(&tuning_of(key, given, tuned, identified));
            assert_eq!(
                w.len(),
                usize::from(doubted),
                "{key} {given} {tuned}: {w:?}"
            );
            if let Some(w) = w.first() {
                assert_eq!(w.key.as_deref(), Some(key));
                assert_eq!(w.file.as_deref(), Some("meta.toml"));
                assert_eq!(w.kind, WarningKind::Suspicious);
            }
        }
    }

    /// (the DVL sigma's given and tuned values, which files recovered,
    /// whether the tuned sigma is doubted)
    #[test]
    fn a_sigma_tuned_through_a_recovery_is_doubted() {
        let cases: [(f64, f64, &[&str], bool); 6] = [
            (0.02, 0.148, &["dvl.csv"], true),
            (0.02, 0.005, &["dvl.csv"], true),
            (0.02, 0.03, &["dvl.csv"], false),
            (0.02, 0.148, &[], false),
            (0.02, 0.148, &["usbl.csv"], false),
            (0.02, 0.148, &["dvl.csv", "usbl.csv"], true),
        ];
        for (given, tuned, recovered, doubted) in cases {
            let mut tuning = tuning_of("sensors.dvl.noise_sigma", given, tuned, true);
            tuning.parameters[0].kind = ParameterKind::SensorNoise;
            tuning.after.warnings = recovered
                .iter()
                .map(|f| Warning::about(WarningKind::LockoutRecovery, f, "recovered"))
                .collect();
            let w = tuned_through_recovery(&tuning);
            assert_eq!(
                w.len(),
                usize::from(doubted),
                "{given} {tuned} {recovered:?}: {w:?}"
            );
            if let Some(w) = w.first() {
                assert_eq!(w.key.as_deref(), Some("sensors.dvl.noise_sigma"));
                assert_eq!(w.file.as_deref(), Some("dvl.csv"));
                assert_eq!(w.kind, WarningKind::Suspicious);
            }
        }
    }
}
