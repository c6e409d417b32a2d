//! `cargo xtask bench-against REV`: the plan bench of another revision and of this checkout,
//! run in turns, so that a shared machine's slow and quiet periods fall on both alike.
//!
//! A time target set on one machine cannot be read off another by the milliseconds alone:
//! the same binary on a shared machine reads a quite different time from one run to the
//! next (measured: docs/performance.md, "Measurements behind the defaults"). What the code
//! did is the ratio to a reference run beside it (docs/performance.md reads the 5 ms plan
//! target against revision b4711fd this way). REV is checked out in a worktree
//! under `target/bench-against/` (registered with git, and kept for the next run) with its own
//! target directory. The checkout's side is its working tree, uncommitted changes included;
//! criterion's saved baselines of both are overwritten as by any bench run.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};

/// Criterion's estimates in `text`: each bench's name and the middle of its `time:` interval,
/// in milliseconds, in the order printed. The name stands before `time:` on the same line, or
/// alone on the line before when it is too long to share it.
pub fn criterion_times(text: &str) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let mut last_name: Option<&str> = None;
    for line in text.lines() {
        let trimmed = line.trim();
        if trimmed.is_empty() {
            continue;
        }
        let Some(at) = line.find("time:") else {
            last_name = trimmed.split_whitespace().next();
            continue;
        };
        let head = line[..at].trim();
        let name = if head.is_empty() {
            last_name
        } else {
            Some(head)
        };
        let interval = line[at + "time:".len()..]
            .trim()
            .trim_start_matches('[')
            .trim_end_matches(']');
        let words: Vec<&str> = interval.split_whitespace().collect();
        // "[low unit mid unit high unit]": the middle value and its unit.
        if let (Some(name), [_, _, mid, unit, ..]) = (name, words.as_slice())
            && let (Ok(v), Some(scale)) = (mid.parse::<f64>(), to_ms(unit))
        {
            out.push((name.to_owned(), v * scale));
        }
        last_name = None;
    }
    out
}

/// Milliseconds per `unit` as criterion prints it.
fn to_ms(unit: &str) -> Option<f64> {
    match unit {
        "s" => Some(1e3),
        "ms" => Some(1.0),
        "µs" | "us" => Some(1e-3),
        "ns" => Some(1e-6),
        "ps" => Some(1e-9),
        _ => None,
    }
}

/// Runs the plan bench (criterion filter `filter`) in `dir`, with `target` as its target
/// directory when given, and returns its estimates.
fn plan_bench(dir: &Path, target: Option<&Path>, filter: &str) -> Result<Vec<(String, f64)>> {
    // The cargo that runs xtask, else the one on the path.
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(dir).args([
        "bench",
        "-q",
        "-p",
        "homospline-benches",
        "--bench",
        "plan",
        "--",
        filter,
    ]);
    if let Some(t) = target {
        cmd.env("CARGO_TARGET_DIR", t);
    }
    let out = cmd
        .output()
        .with_context(|| format!("running the plan bench in {}", dir.display()))?;
    if !out.status.success() {
        bail!(
            "the plan bench failed in {}:\n{}",
            dir.display(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let times = criterion_times(&String::from_utf8_lossy(&out.stdout));
    if times.is_empty() {
        bail!(
            "the plan bench in {} matched no bench for filter {filter:?}",
            dir.display()
        );
    }
    Ok(times)
}

/// `bench-against REV [--runs N] [FILTER]`: `runs` rounds of REV's plan bench then this
/// checkout's, each bench's milliseconds and their ratio per round, then each bench's range.
pub fn run(root: &Path, rev: &str, runs: usize, filter: &str) -> Result<()> {
    let git = |args: &[&str]| -> Result<String> {
        let out = Command::new("git")
            .current_dir(root)
            .args(args)
            .output()
            .context("running git")?;
        if !out.status.success() {
            bail!(
                "git {}: {}",
                args.join(" "),
                String::from_utf8_lossy(&out.stderr).trim()
            );
        }
        Ok(String::from_utf8_lossy(&out.stdout).trim().to_owned())
    };
    let commit = git(&["rev-parse", "--verify", &format!("{rev}^{{commit}}")])
        .with_context(|| format!("{rev}: not a revision of this repository"))?;
    let short = &commit[..commit.len().min(12)];
    let base = root.join("target").join("bench-against");
    let tree = base.join(short);
    if !tree.join("Cargo.toml").is_file() {
        if tree.exists() {
            bail!(
                "{} exists but is not a checkout of {short}: remove it and run again",
                tree.display()
            );
        }
        std::fs::create_dir_all(&base).with_context(|| format!("creating {}", base.display()))?;
        // A worktree whose directory went with `cargo clean` is still registered.
        git(&["worktree", "prune"])?;
        let path = tree.to_str().context("a worktree path that is not UTF-8")?;
        git(&["worktree", "add", "--detach", path, &commit])?;
    }
    let target = base.join(format!("{short}-target"));
    println!("plan bench, filter {filter:?}: {short} ({rev}) against this checkout, {runs} rounds");
    println!(
        "{:<36} {:>10} {:>10} {:>7}",
        "bench", "REV ms", "this ms", "ratio"
    );
    let mut all: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for round in 1..=runs {
        let old = plan_bench(&tree, Some(&target), filter)?;
        let new = plan_bench(root, None, filter)?;
        println!("round {round}");
        for (name, t_new) in &new {
            let Some((_, t_old)) = old.iter().find(|(n, _)| n == name) else {
                println!("{name:<36} {:>10} {t_new:>10.3} {:>7}", "-", "-");
                continue;
            };
            println!(
                "{name:<36} {t_old:>10.3} {t_new:>10.3} {:>7.3}",
                t_new / t_old
            );
            match all.iter_mut().find(|(n, _)| n == name) {
                Some((_, v)) => v.push((*t_old, *t_new)),
                None => all.push((name.clone(), vec![(*t_old, *t_new)])),
            }
        }
    }
    println!("over the rounds (min to max)");
    let range = |xs: Vec<f64>| {
        let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        format!("{lo:.3} to {hi:.3}")
    };
    for (name, v) in all {
        println!(
            "{name:<36} REV {}  this {}  ratio {}",
            range(v.iter().map(|p| p.0).collect()),
            range(v.iter().map(|p| p.1).collect()),
            range(v.iter().map(|p| p.1 / p.0).collect())
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn criterion_lines_give_each_bench_its_middle_estimate_in_ms() {
        let text = "\
plan/concave-cup/nelder-mead
                        time:   [2.1562 ms 2.1985 ms 2.2383 ms]
                        change: [-1.0% +0.5% +2.0%] (p = 0.40 > 0.05)
plan/convex/nelder-mead time:   [2.6892 ms 2.7420 ms 2.8422 ms]
Found 1 outliers among 10 measurements (10.00%)
cost/eval               time:   [5.1 µs 5.9 µs 6.4 µs]
plan/slow               time:   [1.2 s 1.5 s 1.9 s]
";
        let got = criterion_times(text);
        let want = [
            ("plan/concave-cup/nelder-mead", 2.1985),
            ("plan/convex/nelder-mead", 2.7420),
            ("cost/eval", 5.9e-3),
            ("plan/slow", 1500.0),
        ];
        assert_eq!(got.len(), want.len(), "{got:?}");
        for ((n, v), (wn, wv)) in got.iter().zip(want) {
            assert_eq!(n, wn);
            assert!((v - wv).abs() < 1e-12, "{n}: {v} against {wv}");
        }
    }

    #[test]
    fn a_time_line_without_a_name_or_a_known_unit_is_skipped() {
        assert!(criterion_times("                time:   [1 ms 2 ms 3 ms]").is_empty());
        assert!(criterion_times("a/b time: [1 parsecs 2 parsecs 3 parsecs]").is_empty());
    }
}
