//! The documents say what the repository holds: README.md and docs/*.md
//! checked against the code, so that a renamed file, module or test, or a
//! scene example the loader no longer reads, fails here rather than
//! misleading a reader; so are the paths the code's comments name. Also:
//! the README's test command is what CI runs, every test file belongs to
//! one of the tiers docs/testing.md describes, and docs/benchmarks.md types
//! no measured figure outside its generated tables.

#[path = "../common/mod.rs"]
mod common;

mod comment_paths;
mod figures;
mod names;
mod paths;
mod readme_command;
mod scene_blocks;
mod tiers;

use std::path::{Path, PathBuf};

use common::{repo_path, repo_root};

/// README.md and every docs/*.md: (path relative to the root, text).
fn documents() -> Vec<(String, String)> {
    let mut names = vec!["README.md".to_string()];
    let mut docs: Vec<String> = std::fs::read_dir(repo_path("docs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    docs.sort();
    names.extend(docs);
    names
        .into_iter()
        .map(|n| {
            let text = std::fs::read_to_string(repo_path(&n)).unwrap();
            (n, text)
        })
        .collect()
}

/// Every file under `dir` (recursively) whose name ends with one of
/// `extensions`, skipping build outputs and installed packages.
fn files_under(dir: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return out;
    };
    for entry in entries {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if !matches!(
                name.as_str(),
                "target" | "node_modules" | ".git" | "corpus" | "grown"
            ) {
                out.extend(files_under(&path, extensions));
            }
        } else if extensions.iter().any(|e| name.ends_with(e)) {
            out.push(path);
        }
    }
    out.sort();
    out
}

/// The spans of text between backticks in `text` (inline code), with the
/// line each starts on. Fenced blocks are skipped.
fn inline_code(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_fence = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        let mut parts = line.split('`');
        parts.next();
        while let (Some(code), Some(_)) = (parts.next(), parts.next()) {
            out.push((i + 1, code.to_string()));
        }
    }
    out
}
