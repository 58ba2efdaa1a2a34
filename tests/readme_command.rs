//! The README's test command is one line, and CI (`.ci/run`) runs exactly
//! that line: a new user who types it gets what CI gets.

use std::path::Path;

fn repo_file(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// The lines of the first ```sh block after `heading` in the README.
fn readme_block_after(readme: &str, heading: &str) -> Vec<String> {
    let section = readme
        .split_once(heading)
        .unwrap_or_else(|| panic!("README has no {heading:?}"))
        .1;
    let block = section
        .split_once("```sh\n")
        .unwrap_or_else(|| panic!("no ```sh block after {heading:?}"))
        .1;
    let block = block.split_once("```").expect("unclosed ```sh block").0;
    block
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .map(str::to_string)
        .collect()
}

/// The command lines of `.ci/run` after its "# The README's test command:"
/// comment (comments and blank lines skipped).
fn ci_commands_after_marker(ci: &str) -> Vec<String> {
    let marker = "# The README's test command:";
    let rest = ci
        .split_once(marker)
        .unwrap_or_else(|| panic!(".ci/run has no {marker:?} line"))
        .1;
    rest.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_string)
        .collect()
}

#[test]
fn ci_runs_exactly_the_readme_test_command() {
    let readme = readme_block_after(&repo_file("README.md"), "## Run the tests");
    assert_eq!(
        readme.len(),
        1,
        "the README's test command should be one line: {readme:?}"
    );
    let ci = ci_commands_after_marker(&repo_file(".ci/run"));
    assert_eq!(
        ci, readme,
        ".ci/run must end with exactly the README's test command"
    );
}

/// The command is a script in the repository that ends by running the whole
/// suite, is executable (the README runs it by path), and parses.
#[test]
fn the_test_command_is_an_executable_script_that_runs_cargo_test() {
    let readme = readme_block_after(&repo_file("README.md"), "## Run the tests");
    let script = readme[0].split_whitespace().next().unwrap().to_string();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(&script);
    let text = repo_file(&script);
    let last = text
        .lines()
        .map(str::trim)
        .rfind(|l| !l.is_empty() && !l.starts_with('#'))
        .unwrap();
    assert_eq!(last, r#"exec cargo test --locked "$@""#, "{script}");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert!(mode & 0o111 != 0, "{script} is not executable ({mode:o})");
    }
    let syntax = std::process::Command::new("bash")
        .arg("-n")
        .arg(&path)
        .output()
        .expect("cannot run bash");
    assert!(
        syntax.status.success(),
        "bash -n {script}: {}",
        String::from_utf8_lossy(&syntax.stderr)
    );
}
