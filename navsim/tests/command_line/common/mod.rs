//! Helpers shared by the `navsim` binary tests: temporary directories and
//! running the binary. Each test file uses a subset.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

pub struct TempDir(PathBuf);

impl TempDir {
    pub fn new(tag: &str) -> TempDir {
        static N: AtomicUsize = AtomicUsize::new(0);
        let p = std::env::temp_dir().join(format!(
            "navsim-test-{}-{tag}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        TempDir(p)
    }
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A directory shared by the tests of one process (a log written once and
/// read by many tests), held in a `static`. A `static` is never dropped, so
/// it lives under the target directory, not the system's temporary one, and
/// its creation removes those that processes no longer running left behind
/// (found by `/proc`; where there is no `/proc`, `cargo clean` removes them).
pub struct SharedDir(PathBuf);

impl SharedDir {
    pub fn new(tag: &str) -> SharedDir {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR"));
        let prefix = format!("navsim-shared-{tag}-");
        if Path::new("/proc/self").exists() {
            for e in std::fs::read_dir(root).into_iter().flatten().flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                // Only `<prefix><pid>`: the prefix of tag `a` also starts
                // the directories of tag `a-b`.
                let Some(pid) = name
                    .strip_prefix(&prefix)
                    .filter(|pid| pid.bytes().all(|b| b.is_ascii_digit()))
                else {
                    continue;
                };
                if !Path::new("/proc").join(pid).exists() {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        let p = root.join(format!("{prefix}{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        SharedDir(p)
    }
    pub fn path(&self) -> &Path {
        &self.0
    }
}

/// `navsim replay DIR --model MODEL --json EXTRA..`, which must succeed:
/// its JSON.
pub fn replay_json(dir: &Path, model: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["replay", dir.to_str().unwrap(), "--model", model, "--json"];
    args.extend_from_slice(extra);
    let o = navsim(&args);
    assert!(o.status.success(), "{}: {}", dir.display(), stderr(&o));
    serde_json::from_str(stdout(&o).trim()).expect("replay JSON")
}

pub fn navsim(args: &[&str]) -> Output {
    navsim_env(args, &[])
}

pub fn navsim_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_navsim"));
    cmd.args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("navsim runs")
}

/// `navsim simulate SCENARIO --seed SEED --out DIR`, which must succeed.
pub fn simulate(scenario: &str, seed: u64, dir: &Path) {
    let o = navsim(&[
        "simulate",
        scenario,
        "--seed",
        &seed.to_string(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A shared directory left by a process that is no longer running is removed
/// when the next one is made; the one of this process stays.
#[test]
fn a_shared_directory_removes_those_of_finished_processes() {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"));
    // Above the largest process id Linux hands out (2^22).
    let left = root.join("navsim-shared-leftover-4294967294");
    std::fs::create_dir_all(left.join("log")).unwrap();
    // Another tag's directory that begins with this tag's prefix.
    let other = root.join("navsim-shared-leftover-x-4294967293");
    std::fs::create_dir_all(&other).unwrap();
    let first = SharedDir::new("leftover");
    assert!(!left.exists(), "the leftover of a finished process stays");
    assert!(other.exists(), "another tag's directory is removed");
    std::fs::remove_dir_all(&other).unwrap();
    let again = SharedDir::new("leftover");
    assert!(again.path().exists() && first.path() == again.path());
    std::fs::remove_dir_all(again.path()).unwrap();
}
