//! Writing an imported log directory all at once.
//!
//! The files go to a hidden sibling of `--out` (`.NAME.import-PID`), which
//! takes the place of `--out` by a rename once every file is written and
//! synced: a full disk, a SIGINT or a SIGTERM while writing leaves `--out` as
//! it was (absent, or the earlier import), never half written. On SIGINT or
//! SIGTERM the staging directory is removed by a handler thread (removing
//! files is not allowed inside a signal handler) and the process exits with
//! status 130 or 143; the rename itself is done with that thread held off.
//!
//! `--out` may be absent, an empty directory, or an earlier import of ours
//! (its `meta.toml` starts with [`WRITTEN_BY`] and it holds nothing but log
//! files): it is then replaced whole, so no file of the earlier import (a
//! `mag.csv` the new log has no source for) survives next to the new ones.
//! Anything else is refused, so a user's own directory is never emptied.
//!
//! Errors name the user's `--out` path (and the file in it), never the
//! staging path.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, Once};

/// The first line of every `meta.toml` an importer writes: how an earlier
/// import is recognized.
pub const WRITTEN_BY: &str = "# Written by `navsim import";

/// Why a log directory was not written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StageError {
    /// A file or directory could not be written: `path` is where it was
    /// meant to be under `--out`.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path under `--out`.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// `--out` is something the import must not replace.
    #[error("{}: {reason}", path.display())]
    Refused {
        /// `--out`.
        path: PathBuf,
        /// Why.
        reason: String,
    },
}

/// What `--out` is now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Existing {
    /// Nothing there.
    Absent,
    /// An empty directory, or an earlier import: replaced whole.
    Replaceable,
}

/// Whether `name` is a file an importer may have written.
fn is_log_file(name: &str) -> bool {
    name.ends_with(".csv") || name == "meta.toml" || name == "noise.toml"
}

fn inspect(out: &Path) -> Result<Existing, StageError> {
    let refused = |reason: String| StageError::Refused {
        path: out.to_path_buf(),
        reason,
    };
    let io = |source| StageError::Io {
        path: out.to_path_buf(),
        source,
    };
    let meta = match std::fs::symlink_metadata(out) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Existing::Absent),
        Err(e) => return Err(io(e)),
    };
    if meta.file_type().is_symlink() {
        return Err(refused(
            "is a symbolic link; give the directory itself as --out".into(),
        ));
    }
    if !meta.is_dir() {
        return Err(refused("exists and is not a directory".into()));
    }
    let mut names = Vec::new();
    for entry in std::fs::read_dir(out).map_err(io)? {
        let entry = entry.map_err(io)?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry.file_type().map(|t| t.is_file()).unwrap_or(false);
        if !is_file || !is_log_file(&name) {
            return Err(refused(format!(
                "not empty and not an earlier import (it holds `{name}`); give a new or empty directory"
            )));
        }
        names.push(name);
    }
    if names.is_empty() {
        return Ok(Existing::Replaceable);
    }
    let ours = std::fs::read_to_string(out.join("meta.toml"))
        .map(|t| t.starts_with(WRITTEN_BY))
        .unwrap_or(false);
    if !ours {
        return Err(refused(
            "not empty and not an earlier import (no meta.toml written by `navsim import`); give a new or empty directory"
                .into(),
        ));
    }
    Ok(Existing::Replaceable)
}

/// Writes the files `files` (name, content) as the log directory `out`,
/// replacing an earlier import there whole.
///
/// # Errors
/// [`StageError::Refused`] when `out` is a file, a symbolic link or a
/// non-empty directory that is not an earlier import; [`StageError::Io`]
/// naming the file under `out` that could not be written. `out` is then as
/// it was.
pub fn write_log_dir(out: &Path, files: &[(&str, &[u8])]) -> Result<(), StageError> {
    let existing = inspect(out)?;
    let name = out
        .file_name()
        .ok_or_else(|| StageError::Refused {
            path: out.to_path_buf(),
            reason: "names no directory".into(),
        })?
        .to_string_lossy()
        .into_owned();
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let pid = std::process::id();
    let staging = parent.join(format!(".{name}.import-{pid}"));
    let aside = parent.join(format!(".{name}.replaced-{pid}"));
    let io_at = |path: PathBuf| move |source| StageError::Io { path, source };
    let ((), pending) = Pending::create(
        || {
            // A leftover of an earlier process with this id (killed by SIGKILL).
            let _ = std::fs::remove_dir_all(&staging);
            std::fs::create_dir_all(&staging).map_err(io_at(out.to_path_buf()))
        },
        |()| staging.clone(),
    )?;
    for (file, bytes) in files {
        if let Err(e) = write_synced(&staging.join(file), bytes) {
            let _ = std::fs::remove_dir_all(&staging);
            return Err(io_at(out.join(file))(e));
        }
    }
    let result = pending.finish(|| {
        if existing == Existing::Replaceable {
            std::fs::rename(out, &aside)?;
            if let Err(e) = std::fs::rename(&staging, out) {
                // Put the earlier import back.
                let _ = std::fs::rename(&aside, out);
                return Err(e);
            }
            let _ = std::fs::remove_dir_all(&aside);
            Ok(())
        } else {
            std::fs::rename(&staging, out)
        }
    });
    result.map_err(|e| {
        let _ = std::fs::remove_dir_all(&staging);
        io_at(out.to_path_buf())(e)
    })
}

/// Writes and syncs one file, so that a full disk is an error here and not
/// a short file later.
fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = std::fs::File::create(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static HANDLER: Once = Once::new();

/// A staging directory removed if the process is interrupted while this
/// value lives.
#[derive(Debug)]
struct Pending {
    path: PathBuf,
}

impl Pending {
    /// Creates the directory with `make` and registers it with the handler
    /// installed first and the registry held meanwhile: a signal finds the
    /// directory either not yet created or registered.
    fn create<T, E>(
        make: impl FnOnce() -> Result<T, E>,
        path: impl FnOnce(&T) -> PathBuf,
    ) -> Result<(T, Pending), E> {
        install();
        let mut list = PENDING.lock().unwrap_or_else(|e| e.into_inner());
        let value = make()?;
        let path = path(&value);
        list.push(path.clone());
        Ok((value, Pending { path }))
    }

    /// Runs `commit` (the renames) with the handler held off, then unregisters.
    fn finish<T>(self, commit: impl FnOnce() -> T) -> T {
        let result = {
            let _hold = PENDING.lock();
            commit()
        };
        drop(self);
        result
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if let Ok(mut list) = PENDING.lock() {
            list.retain(|p| p != &self.path);
        }
    }
}

fn install() {
    HANDLER.call_once(|| {
        use signal_hook::consts::{SIGINT, SIGTERM};
        let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
            return;
        };
        std::thread::spawn(move || {
            if let Some(signal) = signals.forever().next() {
                let list = PENDING.lock();
                if let Ok(list) = &list {
                    for dir in list.iter() {
                        let _ = std::fs::remove_dir_all(dir);
                    }
                }
                eprintln!("error: interrupted; the import wrote nothing");
                std::process::exit(128 + signal);
            }
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("nav-import-staging-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temp dir");
        d
    }

    const META: &str = "# Written by `navsim import ulog`.\n[initial]\n";

    /// What `--out` holds before, and whether the import replaces it.
    #[test]
    fn out_directory_cases() {
        type Setup = fn(&Path);
        let cases: [(&str, Setup, Option<&str>); 6] = [
            ("absent", |_| {}, None),
            (
                "empty directory",
                |o| std::fs::create_dir(o).expect("dir"),
                None,
            ),
            (
                "earlier import with a mag.csv the new one lacks",
                |o| {
                    std::fs::create_dir(o).expect("dir");
                    std::fs::write(o.join("meta.toml"), META).expect("meta");
                    std::fs::write(o.join("mag.csv"), "t,mx,my,mz\n").expect("mag");
                },
                None,
            ),
            (
                "a user's directory",
                |o| {
                    std::fs::create_dir(o).expect("dir");
                    std::fs::write(o.join("notes.txt"), "mine").expect("notes");
                },
                Some("not an earlier import (it holds `notes.txt`)"),
            ),
            (
                "a log directory written by hand",
                |o| {
                    std::fs::create_dir(o).expect("dir");
                    std::fs::write(o.join("meta.toml"), "[initial]\n").expect("meta");
                },
                Some("no meta.toml written by `navsim import`"),
            ),
            (
                "a file",
                |o| std::fs::write(o, "x").expect("file"),
                Some("exists and is not a directory"),
            ),
        ];
        let root = tmp("cases");
        for (i, (name, setup, refused)) in cases.iter().enumerate() {
            let out = root.join(format!("out{i}"));
            setup(&out);
            let r = write_log_dir(
                &out,
                &[("imu.csv", b"t,gx\n"), ("meta.toml", META.as_bytes())],
            );
            match (refused, r) {
                (None, Ok(())) => {
                    let mut names: Vec<String> = std::fs::read_dir(&out)
                        .expect("out")
                        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
                        .collect();
                    names.sort();
                    assert_eq!(names, ["imu.csv", "meta.toml"], "{name}");
                }
                (Some(part), Err(e)) => {
                    let text = e.to_string();
                    assert!(text.contains(part), "{name}: {text}");
                    assert!(
                        text.starts_with(&out.display().to_string()),
                        "{name}: {text}"
                    );
                }
                (_, r) => panic!("{name}: {r:?}"),
            }
            // No staging or set-aside directory is left next to --out.
            let left: Vec<String> = std::fs::read_dir(&root)
                .expect("root")
                .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
                .filter(|n| n.starts_with('.'))
                .collect();
            assert!(left.is_empty(), "{name}: {left:?}");
        }
        let _ = std::fs::remove_dir_all(&root);
    }

    /// A file that cannot be written (a name into a missing subdirectory
    /// stands for a full disk) is an error naming the path under `--out`,
    /// and `--out` is left as it was.
    #[test]
    fn a_failed_write_names_out_and_leaves_it_as_it_was() {
        let root = tmp("fail");
        let out = root.join("flight");
        write_log_dir(&out, &[("meta.toml", META.as_bytes())]).expect("first import");
        let e = write_log_dir(&out, &[("imu.csv", b"t\n"), ("missing/x.csv", b"t\n")])
            .expect_err("cannot write into a missing directory");
        let text = e.to_string();
        assert!(
            text.starts_with(&out.join("missing/x.csv").display().to_string()),
            "{text}"
        );
        assert!(!text.contains(".import-"), "{text}");
        // The earlier import is untouched: no imu.csv came in.
        assert!(out.join("meta.toml").is_file());
        assert!(!out.join("imu.csv").exists());
        let entries = std::fs::read_dir(&root).expect("root").count();
        assert_eq!(entries, 1, "a staging directory was left behind");
        let _ = std::fs::remove_dir_all(&root);
    }
}
