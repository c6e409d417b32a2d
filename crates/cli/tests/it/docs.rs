//! The documentation keeps up with the command line: every option that a command's `--help`
//! lists is in the user guide (docs/guide.md), the README stays a short manual, and no file
//! of the repository reads as a lab notebook.

use crate::common::*;

/// The long options of `homospline ARGS --help`.
fn long_options(args: &[&str]) -> Vec<String> {
    let out = homospline().args(args).arg("--help").output().unwrap();
    assert_ok(&out);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut v: Vec<String> = text
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
        .filter(|w| w.starts_with("--") && w.len() > 2 && w != &"--help" && w != &"--version")
        .map(str::to_owned)
        .collect();
    v.sort();
    v.dedup();
    v
}

#[test]
fn the_guide_documents_every_option_of_every_command() {
    let guide = std::fs::read_to_string(root().join("docs/guide.md")).unwrap();
    let commands = [
        "plan",
        "bench-scen",
        "graph",
        "bench-merge",
        "simulate",
        "check",
        "serve",
    ];
    let mut missing = Vec::new();
    for c in commands {
        let options = long_options(&[c]);
        if c == "plan" {
            assert!(options.len() > 20, "plan --help: {options:?}");
        }
        for o in options {
            if !guide.contains(&format!("`{o}")) {
                missing.push(format!("{c} {o}"));
            }
        }
    }
    assert!(missing.is_empty(), "not in docs/guide.md: {missing:?}");
}

/// Every field of a class in the plan JSON has its row in docs/formats.md, and the two
/// clearances say which polyline each measures: `certified_clearance` could exceed
/// `min_clearance` at tight turns with nothing saying why.
#[test]
fn formats_documents_every_class_field_and_which_polyline_each_clearance_measures() {
    let formats = std::fs::read_to_string(root().join("docs/formats.md")).unwrap();
    let json = tmp("formats-plan.json");
    let out = homospline()
        .args(["plan", "fixtures/scenes/convex.yaml", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert_ok(&out);
    let plan = read_json(&json);
    let class = plan["classes"][0].as_object().unwrap();
    // A field's own row, else a row naming several (`optimum_length`, ...).
    let row = |key: &str| {
        let lines = || formats.lines();
        lines()
            .find(|l| l.starts_with(&format!("| `{key}` |")))
            .or_else(|| lines().find(|l| l.starts_with("| `") && l.contains(&format!("`{key}`"))))
            .map(str::to_owned)
    };
    let missing: Vec<&String> = class.keys().filter(|k| row(k).is_none()).collect();
    assert!(
        missing.is_empty(),
        "class fields not in docs/formats.md: {missing:?}"
    );
    let min = row("min_clearance").unwrap();
    let cert = row("certified_clearance").unwrap();
    assert!(min.contains("the clearance of `path`"), "{min}");
    assert!(
        cert.contains("the curve's own minimum clearance")
            && cert.contains("`path` is its samples"),
        "{cert}"
    );
}

#[test]
fn the_readme_is_short_and_starts_with_the_two_commands() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 250, "README.md has {lines} lines");
    let head: String = readme.lines().take(20).collect::<Vec<_>>().join("\n");
    assert!(head.contains("cargo test --workspace --locked"), "{head}");
    assert!(head.contains("plan"), "{head}");
}

#[test]
fn no_file_reads_as_a_lab_notebook() {
    // The word is built here so that this file does not hold it.
    let word = ["ses", "sion"].concat();
    let mut found = Vec::new();
    let mut stack = vec![root().to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            // Build output and hidden directories (a local virtual environment, caches) are
            // not the repository's; symbolic links are not followed.
            if name == "target"
                || (name.starts_with('.') && path.is_dir() && name != ".ci" && name != ".cargo")
                || path.is_symlink()
            {
                continue;
            }
            if path.is_dir() {
                stack.push(path);
            } else if let Ok(text) = std::fs::read_to_string(&path)
                && text.to_lowercase().contains(&word)
            {
                found.push(path.display().to_string());
            }
        }
    }
    assert!(found.is_empty(), "files holding the word: {found:?}");
}
