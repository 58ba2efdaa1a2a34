//! Every Rust name the documents cite in inline code exists: module paths
//! (`kdtree::build::tests`, `gpu::RayQueries`, `kdray_core::fuzz_support`) resolve
//! through the two crates' source trees to a file, an inline module or an
//! item; `Type::name` names a function, constant or variant of a type the
//! code defines; and a snake_case name of three words or more (a test's
//! name, mostly) is a `fn` of the code or a word of its code outside
//! comments.

use std::collections::HashSet;

use super::*;

/// The two crates' source roots: kdray's `src/` and kdray-core's.
fn source_roots() -> [PathBuf; 2] {
    [repo_path("src"), repo_path("crates/kdray-core/src")]
}

/// Every code file of the repository without its comment lines (of these
/// tests' own files, only the names of their functions).
struct Code {
    /// Per file: its path and its lines that are not comments.
    files: Vec<(PathBuf, String)>,
    words: HashSet<String>,
    fns: HashSet<String>,
}

impl Code {
    fn read() -> Code {
        let mut files = Vec::new();
        let mut own_fns: Vec<String> = Vec::new();
        for dir in [
            "src",
            "crates",
            "tests",
            "examples",
            "fuzz/fuzz_targets",
            "shaders",
            "web",
            "scripts",
        ] {
            for path in files_under(
                &repo_path(dir),
                &[".rs", ".wgsl", ".mjs", ".js", ".sh", ".py"],
            ) {
                // These tests name what must not exist: only their own
                // functions count.
                if path.starts_with(repo_path("crates/kdray-core/tests/docs_agree")) {
                    let text = std::fs::read_to_string(&path).unwrap();
                    own_fns.extend(
                        text.split("fn ")
                            .skip(1)
                            .filter_map(|rest| {
                                rest.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                                    .next()
                            })
                            .map(str::to_string),
                    );
                    continue;
                }
                let text = std::fs::read_to_string(&path).unwrap();
                let code: String = text
                    .lines()
                    .filter(|l| {
                        !l.trim_start().starts_with("//") && !l.trim_start().starts_with('#')
                    })
                    .map(|l| format!("{l}\n"))
                    .collect();
                files.push((path, code));
            }
        }
        let mut words = HashSet::new();
        let mut fns: HashSet<String> = own_fns.into_iter().collect();
        for (_, code) in &files {
            let tokens: Vec<&str> = code
                .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty())
                .collect();
            for pair in tokens.windows(2) {
                if pair[0] == "fn" {
                    fns.insert(pair[1].to_string());
                }
            }
            words.extend(tokens.iter().map(|w| w.to_string()));
        }
        Code { files, words, fns }
    }

    /// Whether the module file `file` defines `name` as an item, or
    /// re-exports it (`pub use`, one name or a braced list).
    fn defines(&self, file: &Path, name: &str) -> bool {
        const KINDS: [&str; 8] = [
            "fn", "struct", "enum", "trait", "const", "static", "type", "mod",
        ];
        let Some((_, code)) = self.files.iter().find(|(p, _)| p == file) else {
            return false;
        };
        let words = |text: &str| -> Vec<String> {
            text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .filter(|w| !w.is_empty())
                .map(str::to_string)
                .collect()
        };
        let all = words(code);
        if all
            .windows(2)
            .any(|w| KINDS.contains(&w[0].as_str()) && w[1] == name)
        {
            return true;
        }
        code.split("pub use ").skip(1).any(|rest| {
            let statement = rest.split(';').next().unwrap_or("");
            words(statement).iter().any(|w| w == name)
        })
    }

    /// Whether a type of this name is defined anywhere.
    fn defines_type(&self, name: &str) -> bool {
        self.files.iter().any(|(_, code)| {
            ["struct", "enum", "trait", "type"].iter().any(|k| {
                code.contains(&format!("{k} {name} "))
                    || code.contains(&format!("{k} {name}<"))
                    || code.contains(&format!("{k} {name};"))
                    || code.contains(&format!("{k} {name}("))
            })
        })
    }
}

/// `a::b::c` with any `()` or `<...>` dropped, or None when `code` is not a
/// Rust path.
fn rust_path(code: &str) -> Option<Vec<String>> {
    let code = code.trim_end_matches("()");
    let code = code.split('<').next().unwrap();
    if !code.contains("::") || code.contains(' ') {
        return None;
    }
    let segments: Vec<String> = code.split("::").map(str::to_string).collect();
    let ok = segments
        .iter()
        .all(|s| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
    ok.then_some(segments)
}

/// Why `segments` does not resolve, or Ok. A path whose first segment is
/// neither one of the crates' modules nor one of their types is someone
/// else's (`f32::total_cmp`, `wgpu::Backend`): Ok.
fn resolve(code: &Code, segments: &[String]) -> Result<(), String> {
    // `kdray::` names kdray's modules and the core's it re-exports;
    // `kdray_core::` the core's alone; a bare path either.
    let [kdray, core] = source_roots();
    let (roots, segments) = match segments[0].as_str() {
        "kdray" => (vec![kdray], &segments[1..]),
        "kdray_core" => (vec![core], &segments[1..]),
        _ => (vec![kdray, core], segments),
    };
    let Some(first) = segments.first() else {
        return Ok(());
    };
    if roots.len() == 1
        && roots[0] == repo_path("src")
        && !repo_path(&format!("src/{first}.rs")).is_file()
        && !repo_path(&format!("src/{first}/mod.rs")).is_file()
    {
        return if code.defines(&repo_path("src/lib.rs"), first) {
            resolve(code, &[&["kdray_core".to_string()], segments].concat())
        } else {
            Err(format!(
                "kdray has no module `{first}` (nor re-exports one)"
            ))
        };
    }
    if first.starts_with(|c: char| c.is_ascii_uppercase()) {
        if !code.defines_type(first) {
            return Ok(());
        }
        let name = &segments[1];
        return if code.fns.contains(name) || code.words.contains(name) {
            Ok(())
        } else {
            Err(format!("{first} has no `{name}`"))
        };
    }
    // The module's file and folder in one of the two crates.
    let start = roots.into_iter().find_map(|root| {
        let dir = root.join(first);
        let file = root.join(format!("{first}.rs"));
        if file.is_file() {
            Some((file, dir))
        } else if dir.join("mod.rs").is_file() {
            Some((dir.join("mod.rs"), dir))
        } else {
            None
        }
    });
    let Some((mut file, mut dir)) = start else {
        return Ok(());
    };
    let mut inline = false;
    for (i, segment) in segments.iter().enumerate().skip(1) {
        let as_file = dir.join(format!("{segment}.rs"));
        let as_dir = dir.join(segment);
        let text = std::fs::read_to_string(&file).unwrap();
        if !inline && as_file.is_file() {
            (file, dir) = (as_file, as_dir);
        } else if !inline && as_dir.join("mod.rs").is_file() {
            (file, dir) = (as_dir.join("mod.rs"), as_dir);
        } else if text.contains(&format!("mod {segment} {{")) {
            inline = true;
        } else {
            // An item of this module (or re-exported by it), and then maybe
            // one of its own (a method, a variant).
            if !code.defines(&file, segment) {
                return Err(format!("no `{segment}` in {}", file.display()));
            }
            if let Some(member) = segments.get(i + 1) {
                if !code.fns.contains(member) && !code.words.contains(member) {
                    return Err(format!("`{segment}` has no `{member}`"));
                }
            }
            return Ok(());
        }
    }
    Ok(())
}

/// A snake_case name of three words or more.
fn is_long_snake_name(code: &str) -> bool {
    let code = code.trim_end_matches("()");
    code.split('_').count() >= 3
        && code.starts_with(|c: char| c.is_ascii_lowercase())
        && code
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        && !code.contains("__")
        && !code.ends_with('_')
}

#[test]
fn every_rust_path_the_documents_cite_exists() {
    let code = Code::read();
    let mut wrong = Vec::new();
    let mut checked = 0;
    for (doc, text) in documents() {
        for (line, span) in inline_code(&text) {
            if let Some(segments) = rust_path(&span) {
                checked += 1;
                if let Err(why) = resolve(&code, &segments) {
                    wrong.push(format!("{doc}:{line}: `{span}`: {why}"));
                }
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} Rust paths found: is the scan broken?"
    );
    assert!(
        wrong.is_empty(),
        "Rust paths in the documents that do not exist:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn every_test_and_function_name_the_documents_cite_exists() {
    let code = Code::read();
    let mut missing = Vec::new();
    let mut checked = 0;
    for (doc, text) in documents() {
        for (line, span) in inline_code(&text) {
            if is_long_snake_name(&span) {
                checked += 1;
                let name = span.trim_end_matches("()");
                if !code.fns.contains(name) && !code.words.contains(name) {
                    missing.push(format!("{doc}:{line}: `{span}`"));
                }
            }
        }
    }
    assert!(
        checked > 30,
        "only {checked} names found: is the scan broken?"
    );
    assert!(
        missing.is_empty(),
        "names in the documents that no code defines or uses:\n{}",
        missing.join("\n")
    );
}

#[test]
fn a_renamed_module_or_test_is_caught() {
    let code = Code::read();
    let path = |s: &str| rust_path(s).unwrap();
    assert_eq!(resolve(&code, &path("kdtree::sah::shortcut_tests")), Ok(()));
    assert_eq!(
        resolve(
            &code,
            &path("kdtree::build_params::tests::intersection_cost_follows_the_scene_kinds")
        ),
        Ok(())
    );
    assert_eq!(resolve(&code, &path("kdray::output::PngStream")), Ok(()));
    assert_eq!(resolve(&code, &path("kdray::kdtree::Traversal")), Ok(()));
    assert_eq!(
        resolve(&code, &path("kdray_core::fuzz_support::scene")),
        Ok(())
    );
    assert!(
        resolve(&code, &path("kdray::fuzz_support")).is_err(),
        "kdray does not re-export it"
    );
    assert_eq!(
        resolve(&code, &path("kdray_core::scene::SceneFormat")),
        Ok(())
    );
    assert!(resolve(&code, &path("scene::no_such_module::tests")).is_err());
    assert!(resolve(&code, &path("kdtree::build::tests::no_such_test_anywhere")).is_err());
    // A test that exists, cited in the wrong module.
    assert!(resolve(
        &code,
        &path("kdtree::build::tests::intersection_cost_follows_the_scene_kinds")
    )
    .is_err());
    assert!(
        resolve(&code, &path("scene::tests")).is_err(),
        "scene/mod.rs has no tests module"
    );
    assert!(resolve(&code, &path("KdTree::no_such_method_anywhere")).is_err());
    assert!(
        is_long_snake_name("threads_do_not_change_the_tree") && !is_long_snake_name("max_depth")
    );
    assert!(code.fns.contains("threads_do_not_change_the_tree"));
    assert!(!code.words.contains("threads_do_not_change_the_forest"));
}
