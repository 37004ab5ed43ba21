//! Clean-up on interruption: staging directories of `--out` that are being
//! written are removed when the process receives SIGINT or SIGTERM, so an
//! interrupted run leaves neither a partial output nor a `.partial-*`
//! directory behind.
//!
//! [`Pending::create`] makes and registers a directory and installs the signal handler
//! once (a thread waiting for the signal: removing files is not allowed in a
//! signal handler itself); dropping the [`Pending`] unregisters it. On a
//! signal every registered directory is removed and the process exits with
//! status 130 (SIGINT) or 143 (SIGTERM).

use std::path::PathBuf;
use std::sync::{Mutex, Once};

static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
static HANDLER: Once = Once::new();

/// A directory removed if the process is interrupted while this value lives.
#[derive(Debug)]
pub struct Pending {
    path: PathBuf,
}

impl Pending {
    /// Creates a staging directory with `make` and registers it (its path
    /// from `path`) with the handler installed first and the registry held
    /// meanwhile: a signal at any moment finds the directory either not yet
    /// created or registered, never created and unregistered.
    ///
    /// # Errors
    /// The error of `make` (nothing is registered).
    pub fn create<T, E>(
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
}

impl Pending {
    /// Runs `commit` (moving the directory into place) with interruption
    /// held off, so a signal cannot remove a half-moved directory; then
    /// unregisters it.
    pub fn finish<T>(self, commit: impl FnOnce() -> T) -> T {
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
                // Hold the lock until exit: no directory is committed meanwhile.
                let list = PENDING.lock();
                if let Ok(list) = &list {
                    for dir in list.iter() {
                        remove_while_written(dir);
                    }
                }
                eprintln!("error: interrupted; partial outputs removed");
                std::process::exit(128 + signal);
            }
        });
    });
}

/// Removes `dir`, which the main thread may still be writing into: moved
/// aside first (new files can then no longer be created in it by its path),
/// then removed; tried again while something remains.
fn remove_while_written(dir: &std::path::Path) {
    let mut aside = dir.as_os_str().to_owned();
    aside.push(".removing");
    let aside = std::path::PathBuf::from(aside);
    let target = if std::fs::rename(dir, &aside).is_ok() {
        aside
    } else {
        dir.to_path_buf()
    };
    for _ in 0..100 {
        if std::fs::remove_dir_all(&target).is_ok() || !target.exists() {
            return;
        }
    }
}
