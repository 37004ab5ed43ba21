//! A filter-only build of `nav-runtime` (`default-features = false`, with or
//! without `std`) pulls neither the QP solver of the guidance domain nor the
//! CSV and TOML parsers of log I/O nor the random generators of the
//! simulation; the full default build does (so the check below can fail).

use std::process::Command;

/// Normal (non-dev) dependencies of `nav-runtime` built with `features`.
fn dependency_tree(no_default: bool, features: &str) -> String {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root).args([
        "tree",
        "-p",
        "nav-runtime",
        "-e",
        "normal",
        "--prefix",
        "none",
    ]);
    if no_default {
        cmd.arg("--no-default-features");
    }
    if !features.is_empty() {
        cmd.args(["--features", features]);
    }
    let out = cmd.output().expect("run cargo tree");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Crate names (first word of each line) of a tree.
fn crates(tree: &str) -> Vec<&str> {
    tree.lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect()
}

#[test]
fn filter_only_build_pulls_no_solver_parser_or_generator() {
    const HEAVY: [&str; 6] = ["clarabel", "csv", "toml", "serde", "rand", "rand_chacha"];
    // (no default features, features, heavy crates expected)
    let cases: [(bool, &str, bool); 4] = [
        (true, "", false),
        (true, "std", false),
        (true, "std,inertial", false),
        (false, "", true),
    ];
    for (no_default, features, heavy_expected) in cases {
        let tree = dependency_tree(no_default, features);
        let names = crates(&tree);
        assert!(names.contains(&"nalgebra"), "{features}: {tree}");
        for heavy in HEAVY {
            assert_eq!(
                names.contains(&heavy),
                heavy_expected,
                "no_default={no_default} features={features:?}: {heavy} in\n{tree}"
            );
        }
    }
}
