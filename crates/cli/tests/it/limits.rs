//! The process's limits: a map or scene too large for the address space the process may use
//! (`ulimit -v`) is refused with exit 3 and what it needs, not aborted by the allocator; a
//! signal (SIGINT, SIGTERM, SIGHUP) during a write leaves no temporary file behind.
#![cfg(unix)]

use crate::common::*;
use std::os::unix::process::ExitStatusExt;
use std::process::Stdio;

/// A MovingAI map of `n x n` cells, a fifth of them occupied (seeded), the 3 x 3 blocks
/// round (10, 10) and (n - 10, n - 10) free.
fn random_map_file(n: usize) -> std::path::PathBuf {
    let path = tmp(&format!("random{n}.map"));
    let mut text = format!("type octile\nheight {n}\nwidth {n}\nmap\n");
    let mut state: u64 = 7;
    for y in 0..n {
        for x in 0..n {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let near_end = |c: usize| x.abs_diff(c) <= 1 && y.abs_diff(c) <= 1;
            let occupied = (state >> 33).is_multiple_of(5) && !near_end(10) && !near_end(n - 10);
            text.push(if occupied { '@' } else { '.' });
        }
        text.push('\n');
    }
    std::fs::write(&path, text).unwrap();
    path
}

/// `homospline args` under `ulimit -v kb`.
fn under_ulimit(kb: u64, args: &[&str]) -> std::process::Output {
    let mut script = format!("ulimit -v {kb} && exec \"$0\"");
    for k in 1..=args.len() {
        script.push_str(&format!(" \"${{{k}}}\""));
    }
    std::process::Command::new("sh")
        .current_dir(root())
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_homospline"))
        .args(args)
        .output()
        .unwrap()
}

/// A 2048^2 map under `ulimit -v 400000` died of SIGABRT ("memory allocation of N bytes
/// failed", exit 134) half way through preparing it.
#[test]
fn a_map_too_large_for_the_address_space_is_refused_with_what_it_needs() {
    let map = random_map_file(2048);
    let map = map.to_str().unwrap();
    for cmd in [
        vec![
            "plan",
            map,
            "--start",
            "10.5,10.5",
            "--goal",
            "2038.5,2038.5",
        ],
        vec!["graph", map, "--out", "/dev/null"],
    ] {
        let out = under_ulimit(400_000, &cmd);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{cmd:?}: {err}");
        assert!(
            err.contains("(2048 x 2048 cells) needs up to about 713 MB of memory")
                && err.contains("this process may use 409 MB")
                && err.contains("ulimit -v"),
            "{cmd:?}: {err}"
        );
        assert!(
            !err.contains("panicked") && !err.contains("memory allocation"),
            "{err}"
        );
    }
}

/// A scene at a resolution of 57 cells a unit died of SIGABRT under `ulimit -v` 300 to
/// 700 MB.
#[test]
fn a_scene_grid_too_large_for_the_address_space_is_refused_with_what_it_needs() {
    let out = under_ulimit(
        500_000,
        &["plan", "fixtures/scenes/field.yaml", "--resolution", "57"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains("scene field at --resolution 57 needs up to about")
            && err.contains("this process may use 512 MB"),
        "{err}"
    );
}

/// The outputs were always whole, but a signal during a write left the full-size
/// `.NAME.PID.tmp` beside them.
#[test]
fn a_signal_during_a_write_leaves_no_temporary_file() {
    for (name, number) in [("INT", 2), ("TERM", 15), ("HUP", 1)] {
        let dir = tmp(&format!("signal-{name}"));
        std::fs::create_dir_all(&dir).unwrap();
        let json = dir.join("plan.json");
        std::fs::write(&json, "old").unwrap();
        let mut child = homospline()
            .args(["plan", "fixtures/scenes/convex.yaml", "--json"])
            .arg(&json)
            .env("HOMOSPLINE_HOLD_WRITE_MS", "10000")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let temporary = dir.join(format!(".plan.json.{}.tmp", child.id()));
        let start = std::time::Instant::now();
        while !temporary.exists() {
            assert!(
                start.elapsed().as_secs() < 60,
                "SIG{name}: no temporary file in 60 s"
            );
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let killed = std::process::Command::new("kill")
            .args(["-s", name, &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let status = child.wait().unwrap();
        assert!(
            start.elapsed().as_secs() < 9,
            "SIG{name}: the process did not stop at the signal"
        );
        assert_eq!(status.signal(), Some(number), "SIG{name}: {status:?}");
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["plan.json"], "SIG{name}");
        assert_eq!(std::fs::read_to_string(&json).unwrap(), "old", "SIG{name}");
    }
}

/// A start 0.05 from an obstacle needs a finer grid (2 million cells at 20 cells a unit);
/// under `ulimit -v 300000` that grid is more than the process may use. It is refused
/// with the resolution it needs (exit 2), and that resolution with what it needs (exit 3),
/// never aborted by the allocator; without the limit it plans.
#[test]
fn a_finer_grid_keeps_to_the_memory_the_process_may_use() {
    let near = ["plan", "fixtures/scenes/field.yaml", "--start", "30.95,30"];
    let out = under_ulimit(300_000, &near);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("the start [30.95, 30] is 0.05 from obstacle 'o2'")
            && err.contains("--resolution 20.1 plans it"),
        "{err}"
    );
    let out = under_ulimit(300_000, &[&near[..], &["--resolution", "20.1"]].concat());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains("ulimit -v") && !err.contains("memory allocation"),
        "{err}"
    );
    let out = homospline().args(near).output().unwrap();
    assert_ok(&out);
}
