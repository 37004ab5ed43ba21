//! The plots of an INS run: the estimated track and its horizontal sigma
//! (with or without truth), and of a scored run the track against truth,
//! errors with their sigma bounds, NEES, and forward against smoothed.

use std::path::Path;

use super::score::{self, NEES_DOF};
use super::SMOOTHED_TABLE;
use crate::output::plot::{self, Line};
use crate::{RunError, RunTable};

/// Horizontal error of the forward and the smoothed estimates with their
/// 1-sigma bands (`<prefix>-smoothed-horizontal.svg`), when `tables` holds
/// both error tables; nothing otherwise.
pub fn write_smoothed_plot(
    name: &str,
    prefix: &str,
    tables: &[RunTable],
    dir: &Path,
) -> Result<(), RunError> {
    let find = |n: &str| tables.iter().find(|t| t.name == n);
    let (Some(forward), Some(smoothed)) = (find(score::TABLE), find(SMOOTHED_TABLE)) else {
        return Ok(());
    };
    let horizontal = |t: &RunTable, a: &str, b: &str| -> Vec<f64> {
        t.column(a)
            .iter()
            .zip(t.column(b))
            .map(|(x, y)| x.hypot(y))
            .collect()
    };
    let time = forward.column("t");
    let (fe, fs) = (
        horizontal(forward, "err_n", "err_e"),
        horizontal(forward, "sig_n", "sig_e"),
    );
    let (se, ss) = (
        horizontal(smoothed, "err_n", "err_e"),
        horizontal(smoothed, "sig_n", "sig_e"),
    );
    let line = |label, y| Line { label, x: &time, y };
    plot::lines(
        &dir.join(format!("{prefix}-smoothed-horizontal.svg")),
        &format!("{name}: horizontal error, forward and smoothed, with 1-sigma"),
        "t [s]",
        "horizontal error [m]",
        &[
            line("forward error", &fe),
            line("forward 1-sigma", &fs),
            line("smoothed error", &se),
            line("smoothed 1-sigma", &ss),
        ],
    )
}

/// Track, position / velocity / attitude errors with their `±3 sigma` bounds
/// and the NEES with its 95 % band, from one run's table.
pub fn write_plots(name: &str, prefix: &str, t: &RunTable, dir: &Path) -> Result<(), RunError> {
    let time = t.column("t");
    let file = |s: &str| dir.join(format!("{prefix}-{s}.svg"));
    let (tn, te, en, ee) = (
        t.column("true_n"),
        t.column("true_e"),
        t.column("est_n"),
        t.column("est_e"),
    );
    plot::tracks(
        &file("track"),
        &format!("{name} {prefix}: horizontal track"),
        "east [m]",
        "north [m]",
        &[
            Line {
                label: "truth",
                x: &te,
                y: &tn,
            },
            Line {
                label: "estimate",
                x: &ee,
                y: &en,
            },
        ],
    )?;
    let groups = [
        (
            "position",
            "m",
            ["n", "e", "d"],
            ["north", "east", "down"],
            "",
        ),
        (
            "velocity",
            "m/s",
            ["vn", "ve", "vd"],
            ["north", "east", "down"],
            "",
        ),
        (
            "attitude",
            "deg",
            ["roll", "pitch", "yaw"],
            ["roll", "pitch", "yaw"],
            "_deg",
        ),
    ];
    for (group, unit, keys, labels, suffix) in groups {
        for (k, label) in keys.iter().zip(labels) {
            let e = t.column(&format!("err_{k}{suffix}"));
            let s = t.column(&format!("sig_{k}{suffix}"));
            plot::error_with_sigma(
                &file(&format!("{group}-{label}")),
                &format!("{name} {prefix}: {group} error, {label}, with ±3 sigma"),
                &format!("{label} error [{unit}]"),
                &time,
                &e,
                &s,
            )?;
        }
    }
    let band = (
        nav_runtime::gate::chi_square_quantile(0.025, NEES_DOF).unwrap_or(f64::NAN),
        nav_runtime::gate::chi_square_quantile(0.975, NEES_DOF).unwrap_or(f64::NAN),
    );
    plot::nees(
        &file("nees"),
        &format!("{name} {prefix}: NEES of the 9 navigation states (95 % band, 9 dof)"),
        &time,
        &t.column("nees"),
        Some(band),
    )
}

/// North and east (m) of the rows of a trajectory table from its first
/// row (a local flat approximation, for a plot).
fn north_east(t: &RunTable) -> (Vec<f64>, Vec<f64>) {
    let (lat, lon) = (t.column("lat"), t.column("lon"));
    let (Some(&lat0), Some(&lon0)) = (lat.first(), lon.first()) else {
        return (Vec::new(), Vec::new());
    };
    let (m, n) = (
        nav_runtime::earth::meridian_radius(lat0),
        nav_runtime::earth::transverse_radius(lat0),
    );
    let north = lat.iter().map(|l| (l - lat0) * m).collect();
    let east = lon.iter().map(|l| (l - lon0) * n * lat0.cos()).collect();
    (north, east)
}

/// The estimated track (`<prefix>-estimated-track.svg`, north and east
/// from the first estimate) and the horizontal 1-sigma over time
/// (`<prefix>-horizontal-sigma.svg`) of the trajectory table `forward`,
/// with the smoothed one beside it when given: what a log without truth
/// can show.
///
/// # Errors
/// A file cannot be written.
pub fn write_trajectory_plots(
    name: &str,
    prefix: &str,
    forward: &RunTable,
    smoothed: Option<&RunTable>,
    dir: &Path,
) -> Result<(), RunError> {
    let runs: Vec<(&str, &RunTable)> = std::iter::once(("forward", forward))
        .chain(smoothed.map(|s| ("smoothed", s)))
        .collect();
    // Each run's (x, y) series: east and north; time and sigma.
    let tracks: Vec<(Vec<f64>, Vec<f64>)> = runs
        .iter()
        .map(|(_, t)| {
            let (n, e) = north_east(t);
            (e, n)
        })
        .collect();
    let sigma: Vec<(Vec<f64>, Vec<f64>)> = runs
        .iter()
        .map(|(_, t)| {
            let s = t
                .column("sig_n")
                .iter()
                .zip(t.column("sig_e"))
                .map(|(n, e)| n.hypot(e))
                .collect();
            (t.column("t"), s)
        })
        .collect();
    plot::tracks(
        &dir.join(format!("{prefix}-estimated-track.svg")),
        &format!("{name} {prefix}: estimated track from the first estimate"),
        "east [m]",
        "north [m]",
        &labelled(&runs, &tracks),
    )?;
    plot::lines(
        &dir.join(format!("{prefix}-horizontal-sigma.svg")),
        &format!("{name} {prefix}: horizontal 1-sigma"),
        "t [s]",
        "horizontal 1-sigma [m]",
        &labelled(&runs, &sigma),
    )
}

/// One line per run: its label and its `(x, y)` series.
fn labelled<'a>(
    runs: &[(&'a str, &RunTable)],
    series: &'a [(Vec<f64>, Vec<f64>)],
) -> Vec<Line<'a>> {
    runs.iter()
        .zip(series)
        .map(|((label, _), (x, y))| Line { label, x, y })
        .collect()
}
