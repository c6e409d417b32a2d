//! Project automation: `cargo xtask regress [--bless]` checks every fixture against its golden.
//!
//! Fixtures and their goldens:
//! - `fixtures/scenes/NAME.yaml` -> `fixtures/golden/check/NAME.txt`: the summary that
//!   `homospline check` prints. Floats are printed rounded to 3 decimals; that rounding is the
//!   tolerance (1e-3 map units, far below any planning resolution, far above the last-bit
//!   noise of a different but equivalent summation order).
//! - `fixtures/invalid/NAME.*` -> `fixtures/invalid/NAME.expected`: the exact error line.
//!
//! A mismatch prints a line diff and exits 1; `--bless` rewrites the goldens (review the diff
//! with `git diff fixtures/` before committing).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use homospline_geom::Scene;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("regress") => {
            let bless = match &args[1..] {
                [] => false,
                [flag] if flag == "--bless" => true,
                other => {
                    eprintln!("usage: cargo xtask regress [--bless]  (unexpected {other:?})");
                    return ExitCode::from(2);
                }
            };
            regress(bless)
        }
        _ => {
            eprintln!("usage: cargo xtask regress [--bless]");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!(
                "\nregress: mismatches above. If the change is intended, review it and run\n    cargo xtask regress --bless\nthen inspect `git diff fixtures/` before committing."
            );
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("regress: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn files(dir: &Path, keep: impl Fn(&Path) -> bool) -> Result<Vec<PathBuf>> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && keep(p))
        .collect();
    v.sort();
    Ok(v)
}

/// Compares `actual` with the golden at `golden`; prints a diff; rewrites when blessing.
fn compare(name: &str, golden: &Path, actual: &str, bless: bool) -> Result<bool> {
    let expected = std::fs::read_to_string(golden).unwrap_or_default();
    if expected == actual {
        return Ok(true);
    }
    if bless {
        if let Some(dir) = golden.parent() {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(golden, actual).with_context(|| format!("writing {}", golden.display()))?;
        println!("blessed {name}");
        return Ok(true);
    }
    println!("MISMATCH {name} ({})", golden.display());
    let (e, a): (Vec<&str>, Vec<&str>) = (expected.lines().collect(), actual.lines().collect());
    for i in 0..e.len().max(a.len()) {
        match (e.get(i), a.get(i)) {
            (Some(x), Some(y)) if x == y => {}
            (x, y) => {
                if let Some(x) = x {
                    println!("  -{:>4} {x}", i + 1);
                }
                if let Some(y) = y {
                    println!("  +{:>4} {y}", i + 1);
                }
            }
        }
    }
    Ok(false)
}

fn regress(bless: bool) -> Result<bool> {
    let root = root();
    let mut ok = true;
    let mut count = 0;
    let scenes = files(&root.join("fixtures/scenes"), |p| {
        p.extension().is_some_and(|e| e == "yaml" || e == "json")
    })?;
    for path in &scenes {
        let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("scene");
        let bytes = std::fs::read(path)?;
        let scene = Scene::from_bytes(&bytes, &format!("fixtures/scenes/{stem}"))?;
        let golden = root
            .join("fixtures/golden/check")
            .join(format!("{stem}.txt"));
        ok &= compare(
            &format!("check {stem}"),
            &golden,
            &homospline_cli::summary(&scene),
            bless,
        )?;
        count += 1;
    }
    let invalid = files(&root.join("fixtures/invalid"), |p| {
        p.extension().is_none_or(|e| e != "expected")
    })?;
    for path in &invalid {
        let name = path.file_name().and_then(|s| s.to_str()).unwrap_or("?");
        let rel = format!("fixtures/invalid/{name}");
        let bytes = std::fs::read(path)?;
        let actual = match Scene::from_bytes(&bytes, &rel) {
            Ok(_) => bail!("{rel} was accepted: an invalid fixture must be rejected"),
            Err(e) => format!("{e}\n"),
        };
        ok &= compare(
            &format!("invalid {name}"),
            &path.with_extension("expected"),
            &actual,
            bless,
        )?;
        count += 1;
    }
    println!(
        "regress: {count} fixtures, {}",
        if ok { "all match" } else { "MISMATCHES" }
    );
    Ok(ok)
}
