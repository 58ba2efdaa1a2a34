//! The README's test command is one line, and CI (`.ci/run`) runs exactly
//! that line: a new user who types it gets what CI gets. It runs the four
//! tiers, and each tier's commands are the ones docs/testing.md gives.

use super::*;

fn repo_file(name: &str) -> String {
    let path = repo_path(name);
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

/// The cargo commands `scripts/test.sh --dry-run ARGS` says it would run.
fn dry_run(script: &Path, args: &[&str]) -> Vec<String> {
    let out = std::process::Command::new(script)
        .arg("--dry-run")
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", script.display()));
    assert!(
        out.status.success(),
        "{} --dry-run {args:?}: {}",
        script.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("cargo "))
        .map(str::to_string)
        .collect()
}

/// The command is an executable script in the repository (the README runs
/// it by path) that parses, runs the lint, core, GPU and external tiers in
/// that order, and runs each alone when named; docs/testing.md gives each
/// tier's cargo commands. The lint tier fails on any unformatted file and
/// on any clippy warning.
#[test]
fn the_test_command_is_a_script_that_runs_every_tier() {
    let readme = readme_block_after(&repo_file("README.md"), "## Run the tests");
    let script = readme[0].split_whitespace().next().unwrap().to_string();
    let path = repo_path(&script);
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
    let lint = dry_run(&path, &["lint"]);
    assert!(
        lint.iter()
            .any(|c| c.starts_with("cargo fmt") && c.contains("--check"))
            && lint.iter().any(|c| c.starts_with("cargo clippy")
                && c.contains("--workspace")
                && c.contains("--all-targets")
                && c.ends_with("-D warnings")),
        "{script} lint: {lint:?}"
    );
    let tiers = ["core", "gpu", "external"].map(|t| {
        let commands = dry_run(&path, &[t]);
        assert_eq!(commands.len(), 1, "{script} {t}: {commands:?}");
        commands[0].clone()
    });
    let every: Vec<String> = lint.iter().chain(&tiers).cloned().collect();
    assert_eq!(
        dry_run(&path, &[]),
        every,
        "{script} without a tier runs every tier in order"
    );
    assert_eq!(dry_run(&path, &["all"]), every);
    assert!(
        every
            .iter()
            .all(|c| c.contains(" --locked") || c.starts_with("cargo fmt")),
        "{every:?}"
    );
    assert!(
        tiers[0].contains("-p kdray-core")
            && tiers[1].contains("--test gpu")
            && tiers[2].contains("--test external"),
        "{tiers:?}"
    );
    let testing = repo_file("docs/testing.md");
    for command in &every {
        let documented = command.replace(" --locked", "");
        assert!(
            testing.contains(&documented),
            "docs/testing.md does not give the tier command `{documented}`"
        );
    }
}
