//! The test tiers of docs/testing.md hold every test: kdray's tests are the
//! two binaries `tests/gpu/` and `tests/external/` (a new top-level test
//! file would be a binary outside both tiers), and every `.rs` file in a
//! test binary's folder is one of its modules (a file no `mod` names is
//! never compiled, so its tests would never run).

use super::*;

/// The test binaries Cargo finds in a package's `tests/`: its `*.rs` files
/// and its folders with a `main.rs`, by name.
fn test_binaries(tests: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(tests).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() && path.join("main.rs").is_file() {
            out.push(name);
        } else if let Some(stem) = name.strip_suffix(".rs") {
            out.push(stem.to_string());
        }
    }
    out.sort();
    out
}

#[test]
fn kdray_has_exactly_the_gpu_and_external_test_binaries() {
    assert_eq!(
        test_binaries(&repo_path("tests")),
        ["external", "gpu"],
        "kdray's tests are two binaries, tests/gpu/ (the GPU tier) and tests/external/ (the \
         external tier): add a new test file as a module of one of them (docs/testing.md, \"Tiers\")"
    );
}

#[test]
fn every_file_of_a_test_binarys_folder_is_one_of_its_modules() {
    let mut folders = Vec::new();
    for tests in [repo_path("tests"), repo_path("crates/kdray-core/tests")] {
        for name in test_binaries(&tests) {
            let dir = tests.join(&name);
            if dir.is_dir() {
                folders.push(dir);
            }
        }
    }
    assert!(folders.len() >= 4, "found only {folders:?}");
    let mut orphans = Vec::new();
    for dir in folders {
        let main = std::fs::read_to_string(dir.join("main.rs")).unwrap();
        for entry in std::fs::read_dir(&dir).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            let Some(stem) = name.strip_suffix(".rs") else {
                continue;
            };
            if stem != "main" && !main.contains(&format!("mod {stem};")) {
                orphans.push(dir.join(&name).display().to_string());
            }
        }
    }
    assert!(
        orphans.is_empty(),
        "files no `mod` names, never compiled:\n{}",
        orphans.join("\n")
    );
}
