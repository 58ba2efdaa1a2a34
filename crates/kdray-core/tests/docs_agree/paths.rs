//! Every source path the documents name exists: `src/...`, `crates/...`,
//! `shaders/...`, `scripts/...` and `tests/...`, in prose, inline code and
//! fenced blocks alike. A `*` in a path matches any run of characters within
//! one file name.

use super::*;

pub(super) const ROOTS: [&str; 5] = ["src/", "crates/", "shaders/", "scripts/", "tests/"];

/// The paths under [`ROOTS`] that `text` names, with their lines.
fn named_paths(text: &str) -> Vec<(usize, String)> {
    named_paths_under(text, &ROOTS)
}

/// The paths under `roots` that `text` names, with their lines.
pub(super) fn named_paths_under(text: &str, roots: &[&str]) -> Vec<(usize, String)> {
    let is_path_char = |c: char| c.is_ascii_alphanumeric() || "_-./*".contains(c);
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let bytes = line.as_bytes();
        for root in roots {
            for (at, _) in line.match_indices(root) {
                // The start of a path, not the middle of one (`../src/`,
                // `target/tests/`) nor a longer word (`tests/` in `mytests/`).
                if at > 0 && is_path_char(bytes[at - 1] as char) {
                    continue;
                }
                let path: String = line[at..]
                    .chars()
                    .take_while(|&c| is_path_char(c))
                    .collect();
                let path = path.trim_end_matches(['.', ',']);
                out.push((i + 1, path.to_string()));
            }
        }
    }
    out
}

/// Whether `pattern` (a path, perhaps with `*` in its file names) names
/// something under the root.
pub(super) fn exists(pattern: &str) -> bool {
    let mut candidates = vec![repo_root()];
    for part in pattern.trim_end_matches('/').split('/') {
        let mut next = Vec::new();
        for dir in candidates {
            if !part.contains('*') {
                let p = dir.join(part);
                if p.exists() {
                    next.push(p);
                }
                continue;
            }
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue;
            };
            for entry in entries {
                let path = entry.unwrap().path();
                let name = path.file_name().unwrap().to_string_lossy().into_owned();
                if glob_matches(part, &name) {
                    next.push(path);
                }
            }
        }
        candidates = next;
    }
    !candidates.is_empty()
}

/// `*` matches any run of characters; everything else itself.
fn glob_matches(pattern: &str, name: &str) -> bool {
    match pattern.split_once('*') {
        None => pattern == name,
        Some((head, tail)) => {
            name.starts_with(head)
                && (0..=name.len() - head.len()).any(|i| {
                    name.is_char_boundary(head.len() + i)
                        && glob_matches(tail, &name[head.len() + i..])
                })
        }
    }
}

#[test]
fn every_source_path_the_documents_name_exists() {
    let mut missing = Vec::new();
    let mut checked = 0;
    for (doc, text) in documents() {
        for (line, path) in named_paths(&text) {
            checked += 1;
            if !exists(&path) {
                missing.push(format!("{doc}:{line}: {path}"));
            }
        }
    }
    assert!(
        checked > 100,
        "only {checked} paths found: is the scan broken?"
    );
    assert!(
        missing.is_empty(),
        "paths named in the documents that do not exist:\n{}",
        missing.join("\n")
    );
}

#[test]
fn the_path_scan_finds_paths_and_refuses_missing_ones() {
    let text = "see `src/render.rs`, tests/cli.rs, and ../src/x.rs or target/tests/y.\n\
                shaders/*.wgsl and crates/kdray-core/src/nope.rs.";
    let mut paths: Vec<String> = named_paths(text).into_iter().map(|(_, p)| p).collect();
    paths.sort();
    assert_eq!(
        paths,
        [
            "crates/kdray-core/src/nope.rs",
            "shaders/*.wgsl",
            "src/render.rs",
            "tests/cli.rs"
        ]
    );
    assert!(exists("src/render.rs") && exists("shaders/*.wgsl") && exists("tests/"));
    assert!(!exists("crates/kdray-core/src/nope.rs") && !exists("shaders/*.nope"));
}
