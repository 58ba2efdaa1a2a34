//! Every source path a comment names exists: the comments of the Rust,
//! WGSL, JavaScript, shell and Python files under src/, crates/, shaders/,
//! web/, scripts/ and tests/, read as the documents are
//! ([`super::paths`]), with web/ and docs/ paths too. Only comments count:
//! a string may name a file a test writes or expects to be missing, and a
//! system path (`/usr/...`, `/tmp/...`) is not under the root anyway.
//! Placeholders match any name: a word in capitals (`tests/gpu/NAME.rs`)
//! and a brace group (`heatmap-{bunny,spheres}.png`). Under docs/ only the
//! documents (`.md`) count: the rest there (results, images) is what the
//! scripts write.

use super::paths::{exists, named_paths_under, ROOTS};
use super::*;

/// Where a comment may name a path: the documents' roots, the page and the
/// documents themselves.
const COMMENT_ROOTS: [&str; 7] = [
    ROOTS[0], ROOTS[1], ROOTS[2], ROOTS[3], ROOTS[4], "web/", "docs/",
];

/// The folders scanned, and the files in them that have comments.
const SCANNED: [&str; 6] = ["src", "crates", "shaders", "web", "scripts", "tests"];
const EXTENSIONS: [&str; 6] = [".rs", ".wgsl", ".js", ".mjs", ".sh", ".py"];

/// The text of `source`'s comments with their lines: `//` and `/* */` in
/// Rust, WGSL and JavaScript, `#` (at a word's start) in shell and Python.
/// Text inside a string literal is not a comment.
fn comments(file_name: &str, source: &str) -> Vec<(usize, String)> {
    let hash = file_name.ends_with(".sh") || file_name.ends_with(".py");
    let quotes: &[char] = match file_name.rsplit('.').next() {
        Some("wgsl") => &[],
        Some("rs") => &['"'],
        _ => &['"', '\'', '`'],
    };
    let chars: Vec<char> = source.chars().collect();
    let mut out: Vec<(usize, String)> = Vec::new();
    let mut line = 1;
    let mut string: Option<char> = None;
    let mut block = false;
    let mut i = 0;
    // Appends a comment's character to the text of its line.
    let push = |out: &mut Vec<(usize, String)>, line: usize, c: char| match out.last_mut() {
        Some((l, text)) if *l == line => text.push(c),
        _ => out.push((line, c.to_string())),
    };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '\n' {
            line += 1;
            if hash {
                string = None;
            }
            i += 1;
            continue;
        }
        if block {
            if c == '*' && next == Some('/') {
                block = false;
                i += 2;
            } else {
                push(&mut out, line, c);
                i += 1;
            }
            continue;
        }
        if let Some(q) = string {
            if c == '\\' {
                // An escaped newline continues the string on the next line.
                if next == Some('\n') {
                    line += 1;
                }
                i += 2;
                continue;
            }
            if c == q {
                string = None;
            }
            i += 1;
            continue;
        }
        let line_comment = match hash {
            true => c == '#' && (i == 0 || chars[i - 1].is_whitespace()),
            false => c == '/' && next == Some('/'),
        };
        if line_comment {
            i += if hash { 1 } else { 2 };
            while i < chars.len() && chars[i] != '\n' {
                push(&mut out, line, chars[i]);
                i += 1;
            }
        } else if !hash && c == '/' && next == Some('*') {
            block = true;
            i += 2;
        } else if c == '\'' && next == Some('"') && chars.get(i + 2) == Some(&'\'') {
            i += 3; // Rust's '"'
        } else if quotes.contains(&c) || (hash && (c == '"' || c == '\'')) {
            string = Some(c);
            i += 1;
        } else {
            i += 1;
        }
    }
    out
}

/// `path` with its placeholders made `*`: brace groups and words in
/// capitals.
fn placeholders_as_globs(path: &str) -> String {
    let mut out = String::new();
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        let capitals = word.chars().filter(|c| c.is_ascii_uppercase()).count();
        let lower = word.chars().any(|c| c.is_ascii_lowercase());
        if capitals >= 2 && !lower {
            out.push('*');
        } else {
            out.push_str(word);
        }
        word.clear();
    };
    for c in path.chars() {
        if c.is_ascii_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}

/// The paths the comment `text` names, placeholders as globs.
fn comment_paths(text: &str) -> Vec<String> {
    let mut braced = String::new();
    let mut depth = 0;
    for c in text.chars() {
        match c {
            '{' => {
                depth += 1;
                if depth == 1 {
                    braced.push('*');
                }
            }
            '}' if depth > 0 => depth -= 1,
            _ if depth > 0 => {}
            _ => braced.push(c),
        }
    }
    named_paths_under(&braced, &COMMENT_ROOTS)
        .into_iter()
        .map(|(_, path)| placeholders_as_globs(&path))
        .filter(|path| !path.starts_with("docs/") || path.ends_with(".md"))
        .collect()
}

/// Every path the comments of the scanned files name that does not exist,
/// as `file:line: path`, and how many were checked.
fn missing_comment_paths() -> (Vec<String>, usize) {
    let root = repo_root();
    let mut missing = Vec::new();
    let mut checked = 0;
    for dir in SCANNED {
        for file in files_under(&root.join(dir), &EXTENSIONS) {
            let name = file.strip_prefix(&root).unwrap().display().to_string();
            let Ok(source) = std::fs::read_to_string(&file) else {
                continue;
            };
            for (line, text) in comments(&name, &source) {
                for path in comment_paths(&text) {
                    checked += 1;
                    if !exists(&path) {
                        missing.push(format!("{name}:{line}: {path}"));
                    }
                }
            }
        }
    }
    (missing, checked)
}

#[test]
fn every_source_path_a_comment_names_exists() {
    let (missing, checked) = missing_comment_paths();
    assert!(
        checked > 100,
        "only {checked} paths found in comments: is the scan broken?"
    );
    assert!(
        missing.is_empty(),
        "paths named in comments that do not exist:\n{}",
        missing.join("\n")
    );
}

#[test]
fn only_comments_are_read_and_placeholders_match_any_name() {
    let rust = "let s = \"// src/in_a_string.rs\"; // see src/render.rs\n\
                let q = '\"'; /* and shaders/types.wgsl\n   over tests/gpu/ */ x\n";
    assert_eq!(
        comments("a.rs", rust),
        [
            (1, " see src/render.rs".to_string()),
            (2, " and shaders/types.wgsl".to_string()),
            (3, "   over tests/gpu/ ".to_string()),
        ]
    );
    let shell = "echo \"# src/no.rs\" ${#x} # scripts/test.sh\n";
    assert_eq!(
        comments("a.sh", shell),
        [(1, " scripts/test.sh".to_string())]
    );
    assert_eq!(
        comment_paths("scripts/{a,b}.sh and tests/gpu/NAME.rs"),
        ["scripts/*.sh", "tests/gpu/*.rs"]
    );
    assert!(exists("scripts/*.sh") && exists("tests/gpu/*.rs"));
    assert_eq!(
        comment_paths("writes docs/results/x.json, see docs/design.md"),
        ["docs/design.md"]
    );
    assert_eq!(
        comment_paths("src/gpu/bindings.rs, /usr/src/x"),
        ["src/gpu/bindings.rs"]
    );
    assert!(!exists("src/gpu/bindings.rs"));
}
