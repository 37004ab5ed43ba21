//! Sensor files without their `[sensors.*]` section: the model's built-in
//! noise is used, which the user should know.

use nav_runtime::log::{Meta, Warning, WarningKind};

use super::Report;

/// One warning per sensor file with rows and no `[sensors.<name>]` section
/// (among `model_files`, when given); with `model_files`, one per present file
/// the model does not read.
/// `has_rows`: whether each sensor file has rows, in the order imu, dvl,
/// depth, heading, usbl, speed, rpm, altitude.
pub(super) fn check(
    meta: &Meta,
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
    let present = (0..8).map(|i| (names[i], has_rows[i], sections[i]));
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
