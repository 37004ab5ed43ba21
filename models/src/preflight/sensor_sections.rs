//! Sensor files without their `[sensors.*]` section: the model's built-in
//! noise is used, which the user should know.

use nav_runtime::log::{LogDir, Warning, WarningKind};

use super::Report;

/// One warning per sensor file with rows and no `[sensors.<name>]` section
/// (among `model_files`, when given); with `model_files`, one per present file
/// the model does not read.
pub(super) fn check(log: &LogDir, model_files: Option<&[&str]>, report: &mut Report) {
    let s = &log.meta.sensors;
    let present = [
        ("imu", !log.imu.is_empty(), s.imu.is_some()),
        (
            "dvl",
            log.dvl.as_ref().is_some_and(|r| !r.is_empty()),
            s.dvl.is_some(),
        ),
        (
            "depth",
            log.depth.as_ref().is_some_and(|r| !r.is_empty()),
            s.depth.is_some(),
        ),
        (
            "heading",
            log.heading.as_ref().is_some_and(|r| !r.is_empty()),
            s.heading.is_some(),
        ),
        (
            "usbl",
            log.usbl.as_ref().is_some_and(|r| !r.is_empty()),
            s.usbl.is_some(),
        ),
        (
            "speed",
            log.speed.as_ref().is_some_and(|r| !r.is_empty()),
            s.speed.is_some(),
        ),
        (
            "rpm",
            log.rpm.as_ref().is_some_and(|r| !r.is_empty()),
            s.rpm.is_some(),
        ),
        (
            "altitude",
            log.altitude.as_ref().is_some_and(|r| !r.is_empty()),
            s.altitude.is_some(),
        ),
    ];
    for (name, has_rows, has_section) in present {
        let file = format!("{name}.csv");
        let used = model_files.is_none_or(|m| m.contains(&file.as_str()));
        if has_rows && !used {
            report.warn(Warning::about(
                WarningKind::UnusedFile,
                &file,
                "not read by this model: its rows are not used",
            ));
        }
        if used && has_rows && !has_section {
            report.warn(
                Warning::about(
                    WarningKind::MissingSensorSection,
                    "meta.toml",
                    format!("no [sensors.{name}] section for {name}.csv: the model's built-in noise is used"),
                )
                .with_key(&format!("sensors.{name}")),
            );
        }
    }
}
