//! Sensor files without their `[sensors.*]` section: the model's built-in
//! noise is used, which the user should know.

use nav_runtime::log::{Meta, Warning, WarningKind};

use super::Report;

/// One warning per sensor file with rows and no `[sensors.<name>]` section
/// (among `model_files`, when given); with `model_files`, one per present file
/// the model does not read; one per present file the model reads that has
/// no rows (a header only, or every row skipped): the run is not aided by
/// that sensor, which its result would not say.
/// `present`, `has_rows`: whether each sensor file is there and has rows,
/// in the order imu, dvl, depth, heading, usbl, speed, rpm, altitude.
pub(super) fn check(
    meta: &Meta,
    present: [bool; 8],
    has_rows: [bool; 8],
    model_files: Option<&[&str]>,
    report: &mut Report,
) {
    let s = &meta.sensors;
    let sections = [
        s.imu.is_some(),
        s.dvl.is_some(),
        s.depth.is_some(),
        s.heading.is_some(),
        s.usbl.is_some(),
        s.speed.is_some(),
        s.rpm.is_some(),
        s.altitude.is_some(),
    ];
    let names = [
        "imu", "dvl", "depth", "heading", "usbl", "speed", "rpm", "altitude",
    ];
    let files = (0..8).map(|i| (names[i], present[i], has_rows[i], sections[i]));
    for (name, present, has_rows, has_section) in files {
        let file = format!("{name}.csv");
        let used = model_files.is_none_or(|m| m.contains(&file.as_str()));
        // The IMU's own check refuses fewer than 2 rows.
        if used && present && !has_rows && name != "imu" {
            report.warn(Warning::about(
                WarningKind::Suspicious,
                &file,
                format!("{file} has no rows (a header only, or every row skipped): the run is not aided by it"),
            ));
        }
        if has_rows && !used {
            report.warn(Warning::about(
                WarningKind::UnusedFile,
                &file,
                "not read by this model: its rows are not used",
            ));
        }
        // The echo sounder's altitude only gates the DVL: it has no noise.
        if used && has_rows && !has_section && name != "altitude" {
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
