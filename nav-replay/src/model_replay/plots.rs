//! The plots of a model replay written with `--out`: one per state, the
//! forward estimate with its `±3 sigma` band, the smoothed estimate with its
//! own band (`--smooth`), and the truth rows met (a truth file with the
//! state), drawn from the thinned copies of the tables
//! ([`crate::output::series::BoundedTable`]).

use std::path::Path;

use crate::output::plot::{self, Line};
use crate::{RunError, RunTable};

/// The thinned tables a run kept for its plots.
pub(super) struct Tables<'a> {
    /// `t`, each state, `sigma_<state>`.
    pub estimates: Option<&'a RunTable>,
    /// `t` and each state (NaN: the truth file lacks it).
    pub truth: Option<&'a RunTable>,
    /// As `estimates`, smoothed.
    pub smoothed: Option<&'a RunTable>,
}

/// The file name of state `name`'s plot: `state-<name>.svg`, an index
/// written `-k` (`position[0]` gives `state-position-0.svg`).
pub fn file_name(name: &str) -> String {
    let stem: String = name
        .chars()
        .filter(|c| *c != ']')
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect();
    format!("state-{stem}.svg")
}

/// One plot per state of `names` into `dir` (nothing without estimates).
///
/// # Errors
/// A plot that cannot be written.
pub(super) fn write(
    dir: &Path,
    model: &str,
    names: &[&str],
    tables: &Tables<'_>,
) -> Result<(), RunError> {
    let Some(estimates) = tables.estimates else {
        return Ok(());
    };
    /// A table's value, upper and lower `3 sigma` bound of one state.
    fn banded(table: &RunTable, name: &str) -> [Vec<f64>; 3] {
        let x = table.column(name);
        let s = table.column(&format!("sigma_{name}"));
        let bound = |k: f64| x.iter().zip(&s).map(|(x, s)| x + k * s).collect();
        [bound(0.0), bound(3.0), bound(-3.0)]
    }
    let t = estimates.column("t");
    let smoothed_t = tables.smoothed.map(|s| s.column("t")).unwrap_or_default();
    let truth_t = tables.truth.map(|s| s.column("t")).unwrap_or_default();
    for name in names {
        let forward = banded(estimates, name);
        let smoothed = tables.smoothed.map(|s| banded(s, name));
        let truth = tables.truth.map(|s| s.column(name)).unwrap_or_default();
        let mut lines = vec![
            Line {
                label: "estimate",
                x: &t,
                y: &forward[0],
            },
            Line {
                label: "estimate +3 sigma",
                x: &t,
                y: &forward[1],
            },
            Line {
                label: "estimate -3 sigma",
                x: &t,
                y: &forward[2],
            },
        ];
        if let Some(s) = &smoothed {
            for (label, y) in ["smoothed", "smoothed +3 sigma", "smoothed -3 sigma"]
                .into_iter()
                .zip(s)
            {
                lines.push(Line {
                    label,
                    x: &smoothed_t,
                    y,
                });
            }
        }
        if truth.iter().any(|v| v.is_finite()) {
            lines.push(Line {
                label: "truth",
                x: &truth_t,
                y: &truth,
            });
        }
        let title = if smoothed.is_some() {
            format!("{model}: {name}, forward and smoothed, with ±3 sigma")
        } else {
            format!("{model}: {name}, with ±3 sigma")
        };
        plot::lines(&dir.join(file_name(name)), &title, "t [s]", name, &lines)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn plot_file_names_of_states() {
        for (name, file) in [
            ("heading", "state-heading.svg"),
            ("position[0]", "state-position-0.svg"),
            ("q[3]", "state-q-3.svg"),
            ("gyro_bias", "state-gyro_bias.svg"),
        ] {
            assert_eq!(super::file_name(name), file);
        }
    }
}
