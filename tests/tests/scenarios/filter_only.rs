//! A filter-only build of `nav-runtime` (`default-features = false`, with or
//! without `std`) pulls neither the QP solver of the guidance domain nor the
//! CSV and TOML parsers of log I/O nor the random generators of the
//! simulation; the full default build does (so the check below can fail).
//! And the crates by role depend one way: a user's replay program pulls
//! neither the papers' estimators nor the importers, the papers' crate not
//! the importers.

use std::process::Command;

/// Normal (non-dev) dependencies of `package` built with `features`.
fn dependency_tree(package: &str, no_default: bool, features: &str) -> String {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root)
        .args(["tree", "-p", package, "-e", "normal", "--prefix", "none"]);
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
        let tree = dependency_tree("nav-runtime", no_default, features);
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

#[test]
fn crates_by_role_depend_one_way() {
    // (package, crates its normal dependencies must not include, one they do)
    let cases: [(&str, &[&str], &str); 3] = [
        // The ship of `examples/ship/`: a user's replay program.
        (
            "ship",
            &["models", "navsim", "nav-import", "mcap", "px4-ulog"],
            "nav-replay",
        ),
        (
            "models",
            &["navsim", "nav-import", "mcap", "px4-ulog"],
            "nav-replay",
        ),
        ("nav-replay", &["models", "navsim", "nav-import"], "nav-ins"),
    ];
    for (package, absent, present) in cases {
        let tree = dependency_tree(package, false, "");
        let names = crates(&tree);
        assert!(names.contains(&present), "{package}: {present} in\n{tree}");
        for name in absent {
            assert!(
                !names.contains(name),
                "{package} depends on {name}:\n{tree}"
            );
        }
    }
}
