//! `--shard K/N`: deterministic slices of a run's seeds, the shard files
//! they write, and their merge back into one run.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::{RunError, RunOptions, RunResult};

/// `--shard K/N`: the K-th (1-based) of N deterministic slices of the seeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// 1-based shard index.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

impl Shard {
    /// Whether seed index `i` (0-based, seed = base + i) belongs to this shard.
    pub fn contains(&self, i: usize) -> bool {
        i % self.n == self.k - 1
    }

    /// File name of this shard's results.
    pub fn file_name(&self) -> String {
        format!("shard-{}-of-{}.json", self.k, self.n)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}` is not K/N with 1 <= K <= N (e.g. 2/4)");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// The seeds of a (possibly sharded) run, in increasing index order.
pub fn seeds(seed: u64, runs: usize, shard: Option<Shard>) -> Vec<u64> {
    (0..runs)
        .filter(|&i| match shard {
            None => true,
            Some(s) => s.contains(i),
        })
        .map(|i| seed.wrapping_add(i as u64))
        .collect()
}

/// The content of a shard file (`shard-K-of-N.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardFile {
    /// Format version (1).
    pub format: u32,
    /// Scenario name.
    pub scenario: String,
    /// First seed of the whole (unsharded) run.
    pub seed: u64,
    /// Number of runs of the whole (unsharded) run.
    pub runs: usize,
    /// `K/N`.
    pub shard: String,
    /// Options of the run.
    pub options: RunOptions,
    /// This shard's runs, in seed order.
    pub results: Vec<RunResult>,
}

/// Current [`ShardFile::format`] (2: runs carry their typed health counts).
pub const SHARD_FORMAT: u32 = 2;

impl ShardFile {
    /// Reads a shard file.
    pub fn read(path: &Path) -> Result<ShardFile, RunError> {
        /// The format field alone, read first: a file of another format is
        /// refused as such, not for the fields it lacks.
        #[derive(Deserialize)]
        struct Format {
            format: u32,
        }
        let text = std::fs::read_to_string(path).map_err(|e| RunError::io(path, e))?;
        let not_shard = |e: serde_json::Error| RunError::Shard {
            path: path.to_path_buf(),
            message: format!("not a shard file: {e}"),
        };
        let Format { format } = serde_json::from_str(&text).map_err(not_shard)?;
        if format != SHARD_FORMAT {
            return Err(RunError::Shard {
                path: path.to_path_buf(),
                message: format!(
                    "shard format {format}; this navsim reads format {SHARD_FORMAT} (rerun the shard)"
                ),
            });
        }
        serde_json::from_str(&text).map_err(not_shard)
    }

    /// Writes the shard file as JSON.
    pub fn write(&self, path: &Path) -> Result<(), RunError> {
        let text = serde_json::to_string(self).map_err(|e| RunError::Shard {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        std::fs::write(path, text + "\n").map_err(|e| RunError::io(path, e))
    }
}

/// Finds shard files: each path is a shard file or a directory whose
/// `shard-*-of-*.json` files are taken (sorted by name).
pub fn find_shard_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, RunError> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| RunError::io(p, e))?;
        if meta.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| RunError::io(p, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    f.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                        n.starts_with("shard-") && n.contains("-of-") && n.ends_with(".json")
                    })
                })
                .collect();
            if found.is_empty() {
                return Err(RunError::Shard {
                    path: p.clone(),
                    message: "no shard-K-of-N.json files in this directory".into(),
                });
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// Merged shards: the whole run's parameters and every result in seed order.
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    /// Scenario name.
    pub scenario: String,
    /// First seed.
    pub seed: u64,
    /// Options of the run.
    pub options: RunOptions,
    /// All results, in seed order.
    pub results: Vec<RunResult>,
}

/// Checks that shard files belong to one run and cover each of its seeds exactly
/// once; returns the results in seed order.
pub fn merge_shards(files: &[(PathBuf, ShardFile)]) -> Result<Merged, RunError> {
    let Some((first_path, first)) = files.first() else {
        return Err(RunError::Invalid("no shard files to merge".into()));
    };
    let mut by_index: BTreeMap<u64, (&Path, &RunResult)> = BTreeMap::new();
    for (path, f) in files {
        let mismatch = |what: &str, a: String, b: String| RunError::Shard {
            path: path.clone(),
            message: format!(
                "{what} is {b} but {} has {a}: shards of different runs",
                first_path.display()
            ),
        };
        if f.scenario != first.scenario {
            return Err(mismatch(
                "scenario",
                first.scenario.clone(),
                f.scenario.clone(),
            ));
        }
        if f.seed != first.seed {
            return Err(mismatch("seed", first.seed.to_string(), f.seed.to_string()));
        }
        if f.runs != first.runs {
            return Err(mismatch("runs", first.runs.to_string(), f.runs.to_string()));
        }
        if f.options != first.options {
            return Err(mismatch(
                "options",
                format!("{:?}", first.options),
                format!("{:?}", f.options),
            ));
        }
        for r in &f.results {
            let index = r.seed.wrapping_sub(f.seed);
            if index >= f.runs as u64 {
                return Err(RunError::Shard {
                    path: path.clone(),
                    message: format!("seed {} is outside of the run's seeds", r.seed),
                });
            }
            if let Some((other, _)) = by_index.insert(index, (path, r)) {
                return Err(RunError::Shard {
                    path: path.clone(),
                    message: format!("seed {} is also in {}", r.seed, other.display()),
                });
            }
        }
    }
    if by_index.len() != first.runs {
        let missing: Vec<String> = (0..first.runs as u64)
            .filter(|i| !by_index.contains_key(i))
            .take(5)
            .map(|i| first.seed.wrapping_add(i).to_string())
            .collect();
        return Err(RunError::Shard {
            path: first_path.clone(),
            message: format!(
                "shards cover {} of {} runs; missing seeds include {}",
                by_index.len(),
                first.runs,
                missing.join(", ")
            ),
        });
    }
    // Every run of a scenario reports the same metrics: one without a
    // metric the others have would make that metric's summary null.
    let lacks = |a: &RunResult, b: &RunResult| {
        a.metrics
            .keys()
            .find(|k| !b.metrics.contains_key(*k))
            .cloned()
    };
    let results: Vec<(&Path, &RunResult)> = by_index.values().copied().collect();
    if let Some(&(model_path, model)) = results.first() {
        for &(path, r) in &results {
            if let Some(metric) = lacks(model, r).or_else(|| lacks(r, model)) {
                let (with, without, path) = if r.metrics.contains_key(&metric) {
                    (r.seed, model.seed, model_path)
                } else {
                    (model.seed, r.seed, path)
                };
                return Err(RunError::Shard {
                    path: path.to_path_buf(),
                    message: format!(
                        "seed {without} has no metric `{metric}`, seed {with} has: an edited or \
                         damaged shard (its summary would be null)"
                    ),
                });
            }
        }
    }
    Ok(Merged {
        scenario: first.scenario.clone(),
        seed: first.seed,
        options: first.options.clone(),
        results: by_index.into_values().map(|(_, r)| r.clone()).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A shard of the previous format (no typed health) is refused for its
    /// format, naming the file; the current format reads back.
    #[test]
    fn a_shard_of_another_format_is_refused_as_such() {
        let dir = std::env::temp_dir().join(format!("shard-format-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("shard-1-of-2.json");
        let file = ShardFile {
            format: SHARD_FORMAT,
            scenario: "demo".into(),
            seed: 1,
            runs: 2,
            shard: "1/2".into(),
            options: RunOptions::default(),
            results: vec![RunResult::new(1)],
        };
        file.write(&path).unwrap();
        assert_eq!(ShardFile::read(&path).unwrap(), file);
        let mut old: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        old["format"] = 1.into();
        old["results"][0].as_object_mut().unwrap().remove("health");
        std::fs::write(&path, old.to_string()).unwrap();
        let e = ShardFile::read(&path).unwrap_err().to_string();
        assert!(
            e.contains("shard-1-of-2.json") && e.contains("shard format 1"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
