//! The files a replay of an imported log writes under `--out`: each table
//! as CSV and the plots of the reference differences and the truth errors.
//! Shared by the `ahrs` and `gnss-ins` replays.

use std::path::Path;

use crate::harness::plot;
use crate::harness::{ReplayOutput, RunError, RunTable};

/// Writes every table of `output` as CSV and its plots ([`write_plots`]).
///
/// # Errors
/// A file cannot be written.
pub fn write_outputs(name: &str, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
    for t in &output.tables {
        t.write_csv(&dir.join(format!("{}.csv", t.name)))?;
    }
    write_plots(name, &output.tables, dir)
}

/// The plots of model `name`'s tables (a bounded copy of a long series
/// plots as well as the whole): `attitude_difference.svg` and, with
/// positions, `horizontal_difference.svg` from `reference_difference`;
/// `attitude_errors.svg` from `attitude_errors`.
///
/// # Errors
/// A file cannot be written.
pub fn write_plots(name: &str, tables: &[RunTable], dir: &Path) -> Result<(), RunError> {
    for t in tables {
        let time = t.column("t");
        let plot3 = |file: &str, title: &str, y: &str, cols: [&str; 3]| -> Result<(), RunError> {
            let ys: Vec<Vec<f64>> = cols.iter().map(|c| t.column(c)).collect();
            let labels = ["roll", "pitch", "yaw"];
            let lines: Vec<plot::Line<'_>> = ys
                .iter()
                .zip(labels)
                .map(|(y, label)| plot::Line { label, x: &time, y })
                .collect();
            plot::lines(&dir.join(file), title, "t [s]", y, &lines)
        };
        match t.name.as_str() {
            "reference_difference" => {
                plot3(
                    "attitude_difference.svg",
                    &format!("{name}: attitude minus PX4's estimate"),
                    "difference [deg]",
                    ["diff_roll_deg", "diff_pitch_deg", "diff_yaw_deg"],
                )?;
                let (n, e) = (t.column("diff_n_m"), t.column("diff_e_m"));
                if n.iter().any(|v| v.is_finite()) {
                    let lines = [
                        plot::Line {
                            label: "north",
                            x: &time,
                            y: &n,
                        },
                        plot::Line {
                            label: "east",
                            x: &time,
                            y: &e,
                        },
                    ];
                    plot::lines(
                        &dir.join("horizontal_difference.svg"),
                        &format!("{name}: position minus PX4's estimate"),
                        "t [s]",
                        "difference [m]",
                        &lines,
                    )?;
                }
            }
            "attitude_errors" => plot3(
                "attitude_errors.svg",
                &format!("{name}: attitude error against truth.csv"),
                "error [deg]",
                ["err_roll_deg", "err_pitch_deg", "err_yaw_deg"],
            )?,
            _ => {}
        }
    }
    Ok(())
}
