//! The generated code and the filter core build without `std`: builds the
//! `nostd-check` crate (a `#![no_std]` library declaring a model and running the
//! EKF) on its own, so `nav-runtime` is compiled with `default-features = false`.
//! A `cargo check`: whether a crate compiles without `std` is settled by name
//! resolution and type checking, and a library links nothing, so code
//! generation would add time (about 15 s of the test's 40) and no check.

#[test]
fn generated_code_and_ekf_build_without_std() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = root.join("target").join("nostd-check");
    let out = std::process::Command::new(cargo)
        .current_dir(&root)
        .args(["check", "-p", "nostd-check", "--target-dir"])
        .arg(&target)
        .output()
        .expect("run cargo");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The build really was without std: nav-runtime's std-only modules are absent.
    let tree =
        std::process::Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
            .current_dir(&root)
            .args([
                "tree",
                "-p",
                "nostd-check",
                "-e",
                "features",
                "-i",
                "nav-runtime",
            ])
            .output()
            .expect("run cargo tree");
    let text = String::from_utf8_lossy(&tree.stdout);
    assert!(
        !text.contains("\"std\""),
        "nav-runtime built with std:\n{text}"
    );
}
