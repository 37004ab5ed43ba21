//! The opt-in `fma` build of the covariance kernels (`nav-runtime` feature
//! `fma`, docs/performance.md): runs the filter core's unit tests in that
//! build (propagation and Joseph kernels against dense products, AVX path
//! bit-identical to the portable one, EKF behaviour), in a target directory
//! of its own. The default build's results are pinned by every other test.

#[test]
fn the_fma_build_passes_the_filter_core_tests() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = root.join("target").join("fma-check");
    let out = std::process::Command::new(cargo)
        .current_dir(&root)
        .args([
            "test",
            "-p",
            "nav-runtime",
            "--lib",
            "--no-default-features",
            "--features",
            "simulation,fma",
            "--target-dir",
        ])
        .arg(&target)
        .output()
        .expect("run cargo");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("test result: ok"), "{stdout}");
}
