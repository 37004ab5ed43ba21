//! SVG plots of estimation results (time series with sigma bands, tracks, NEES).
//!
//! Every function takes plain slices, skips non-finite points (a line breaks there)
//! and writes one SVG file. Errors are [`RunError::Plot`] naming the file.

use std::ops::Range;
use std::path::Path;

use plotters::prelude::*;

use crate::RunError;

/// Plot size in pixels.
pub const SIZE: (u32, u32) = (960, 540);

/// One named line of `(x, y)` points.
#[derive(Debug, Clone, Copy)]
pub struct Line<'a> {
    /// Legend label.
    pub label: &'a str,
    /// x values.
    pub x: &'a [f64],
    /// y values (same length as `x`; extra values are ignored).
    pub y: &'a [f64],
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn plot_err(path: &Path, e: impl std::fmt::Display) -> RunError {
    RunError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Range covering the finite values, padded by 5 % (a unit range around a single value).
fn range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return 0.0..1.0;
    }
    let span = hi - lo;
    let pad = if span > 0.0 {
        0.05 * span
    } else {
        0.5 * lo.abs().max(1.0)
    };
    (lo - pad)..(hi + pad)
}

/// Finite `(x, y)` runs of a line: consecutive finite points, split at non-finite ones.
fn segments(x: &[f64], y: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut out = vec![Vec::new()];
    for (&a, &b) in x.iter().zip(y) {
        if a.is_finite() && b.is_finite() {
            out.last_mut().expect("non-empty").push((a, b));
        } else if !out.last().expect("non-empty").is_empty() {
            out.push(Vec::new());
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// Line chart of several series against a shared x axis kind.
pub fn lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line<'_>],
) -> Result<(), RunError> {
    let xr = range(lines.iter().flat_map(|l| l.x.iter().copied()));
    let yr = range(lines.iter().flat_map(|l| l.y.iter().copied()));
    draw(path, title, x_label, y_label, xr, yr, lines, &[], false)
}

/// Time series of an error with its `±3 sigma` envelope (`sigma` per sample).
pub fn error_with_sigma(
    path: &Path,
    title: &str,
    y_label: &str,
    t: &[f64],
    error: &[f64],
    sigma: &[f64],
) -> Result<(), RunError> {
    let upper: Vec<f64> = sigma.iter().map(|s| 3.0 * s).collect();
    let lower: Vec<f64> = sigma.iter().map(|s| -3.0 * s).collect();
    let ls = [
        Line {
            label: "error",
            x: t,
            y: error,
        },
        Line {
            label: "+3 sigma",
            x: t,
            y: &upper,
        },
        Line {
            label: "-3 sigma",
            x: t,
            y: &lower,
        },
    ];
    let xr = range(t.iter().copied());
    let yr = range(error.iter().chain(&upper).chain(&lower).copied());
    draw(path, title, "t [s]", y_label, xr, yr, &ls, &[], false)
}

/// A time series with an optional per-sample sigma, for [`series_with_sigma`].
#[derive(Debug, Clone, Copy)]
pub struct SigmaSeries<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Values, one per time.
    pub y: &'a [f64],
    /// One-sigma per time; draws `y ± 3 sigma` when given.
    pub sigma: Option<&'a [f64]>,
}

/// Several time series, each with its own `±3 sigma` envelope around the value
/// (`sigma` per sample), e.g. estimate and truth of one state.
pub fn series_with_sigma(
    path: &Path,
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[SigmaSeries<'_>],
) -> Result<(), RunError> {
    let mut owned: Vec<(String, Vec<f64>)> = Vec::new();
    for s in series {
        if let Some(sig) = s.sigma {
            let (label, y) = (s.label, s.y);
            owned.push((
                format!("{label} +3 sigma"),
                y.iter().zip(sig).map(|(y, s)| y + 3.0 * s).collect(),
            ));
            owned.push((
                format!("{label} -3 sigma"),
                y.iter().zip(sig).map(|(y, s)| y - 3.0 * s).collect(),
            ));
        }
    }
    let mut ls: Vec<Line<'_>> = series
        .iter()
        .map(|s| Line {
            label: s.label,
            x: t,
            y: s.y,
        })
        .collect();
    ls.extend(owned.iter().map(|(label, y)| Line { label, x: t, y }));
    let xr = range(t.iter().copied());
    let yr = range(ls.iter().flat_map(|l| l.y.iter().copied()));
    draw(path, title, "t [s]", y_label, xr, yr, &ls, &[], false)
}

/// 2-D tracks (e.g. east vs north in metres), truth and estimates, equal axis scales.
pub fn tracks(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    tracks: &[Line<'_>],
) -> Result<(), RunError> {
    let xr = range(tracks.iter().flat_map(|l| l.x.iter().copied()));
    let yr = range(tracks.iter().flat_map(|l| l.y.iter().copied()));
    // Equal scale: widen the narrower range to the plot's aspect ratio.
    let aspect = f64::from(SIZE.0) / f64::from(SIZE.1);
    let (w, h) = (xr.end - xr.start, yr.end - yr.start);
    let (xr, yr) = if w / h < aspect {
        let c = 0.5 * (xr.start + xr.end);
        let half = 0.5 * h * aspect;
        ((c - half)..(c + half), yr)
    } else {
        let c = 0.5 * (yr.start + yr.end);
        let half = 0.5 * w / aspect;
        (xr, (c - half)..(c + half))
    };
    draw(path, title, x_label, y_label, xr, yr, tracks, &[], true)
}

/// NEES over time with an optional consistency band `(lower, upper)` drawn as two
/// horizontal lines.
pub fn nees(
    path: &Path,
    title: &str,
    t: &[f64],
    nees: &[f64],
    band: Option<(f64, f64)>,
) -> Result<(), RunError> {
    let ls = [Line {
        label: "NEES",
        x: t,
        y: nees,
    }];
    let hl: Vec<(&str, f64)> = band.map_or(Vec::new(), |(lo, hi)| {
        vec![("band lower", lo), ("band upper", hi)]
    });
    let xr = range(t.iter().copied());
    let yr = range(
        nees.iter()
            .copied()
            .chain(hl.iter().map(|h| h.1))
            .chain(std::iter::once(0.0)),
    );
    draw(path, title, "t [s]", "NEES", xr, yr, &ls, &hl, false)
}

#[allow(clippy::too_many_arguments)]
fn draw(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    xr: Range<f64>,
    yr: Range<f64>,
    lines: &[Line<'_>],
    hlines: &[(&str, f64)],
    mark_start: bool,
) -> Result<(), RunError> {
    let e = |err| plot_err(path, err);
    let root = SVGBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(xr.clone(), yr)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .draw()
        .map_err(e)?;
    for (i, l) in lines.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        let segs = segments(l.x, l.y);
        for (j, seg) in segs.iter().enumerate() {
            let series = chart
                .draw_series(LineSeries::new(seg.iter().copied(), color.stroke_width(2)))
                .map_err(e)?;
            if j == 0 {
                series.label(l.label).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            }
        }
        if mark_start {
            if let Some(&p) = segs.first().and_then(|s| s.first()) {
                chart
                    .draw_series(std::iter::once(Circle::new(p, 4, color.filled())))
                    .map_err(e)?;
            }
        }
    }
    for (label, y) in hlines {
        let color = RGBColor(90, 90, 90);
        chart
            .draw_series(LineSeries::new(
                [(xr.start, *y), (xr.end, *y)],
                color.stroke_width(1),
            ))
            .map_err(e)?
            .label(*label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(1))
            });
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("navsim-plot-test-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    #[test]
    fn plots_write_svg_files() {
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
        let e: Vec<f64> = t.iter().map(|t| (t * 0.7).sin()).collect();
        let s: Vec<f64> = t.iter().map(|t| 0.5 + 0.01 * t).collect();
        let p = tmp("err.svg");
        error_with_sigma(&p, "error", "m", &t, &e, &s).unwrap();
        assert!(std::fs::read_to_string(&p).unwrap().contains("<svg"));
        let mut n = e.clone();
        n[10] = f64::NAN;
        nees(&tmp("nees.svg"), "nees", &t, &n, Some((1.5, 2.6))).unwrap();
        let y: Vec<f64> = t.iter().map(|t| t.cos()).collect();
        tracks(
            &tmp("track.svg"),
            "track",
            "east [m]",
            "north [m]",
            &[
                Line {
                    label: "truth",
                    x: &e,
                    y: &y,
                },
                Line {
                    label: "estimate",
                    x: &y,
                    y: &e,
                },
            ],
        )
        .unwrap();
        series_with_sigma(
            &tmp("s.svg"),
            "s",
            "m",
            &t,
            &[
                SigmaSeries {
                    label: "est",
                    y: &e,
                    sigma: Some(&s),
                },
                SigmaSeries {
                    label: "truth",
                    y: &y,
                    sigma: None,
                },
            ],
        )
        .unwrap();
        // Degenerate input: empty and constant series.
        lines(&tmp("empty.svg"), "empty", "x", "y", &[]).unwrap();
        lines(
            &tmp("const.svg"),
            "c",
            "x",
            "y",
            &[Line {
                label: "c",
                x: &[1.0, 1.0],
                y: &[2.0, 2.0],
            }],
        )
        .unwrap();
        let _ = std::fs::remove_dir_all(p.parent().unwrap());
    }
}
