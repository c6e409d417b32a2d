//! Fuzz-style runs of the command itself: mutated scenes, worlds, maps and scenario files
//! handed to `check`, `plan`, `graph`, `simulate` and `bench-scen`. Every run must end
//! within its time bound with an exit code of 0 to 3 (never a panic's 101 or a signal) and,
//! when it refuses, a message. Cases: `HOMOSPLINE_CLI_FUZZ_CASES` (default 64; every case
//! runs the command six times).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use crate::common::{homospline, mutate, root, tmp, wait_bounded};
use proptest::prelude::*;

/// Most seconds one run may take: far above any fixture's plan in a debug build.
const RUN_BOUND: Duration = Duration::from_secs(60);

/// Runs `cmd` to its end or the bound; asserts the exit code and the message.
fn run_bounded(mut cmd: Command, what: &str) {
    let err_file = tmp("fuzz-cli-stderr.txt");
    let err = std::fs::File::create(&err_file).unwrap();
    let mut child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::from(err))
        .spawn()
        .unwrap();
    let status = wait_bounded(&mut child, RUN_BOUND.as_secs(), what);
    let stderr = std::fs::read_to_string(&err_file).unwrap_or_default();
    let code = status.code();
    assert!(
        code.is_some_and(|c| (0..=3).contains(&c)),
        "{what}: exit {code:?}\n{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    if code == Some(2) {
        assert!(
            stderr.starts_with("error: ") && stderr.len() > 10,
            "{what}: {stderr}"
        );
    }
}

fn fixture(path: &str) -> Vec<u8> {
    std::fs::read(root().join(path)).unwrap()
}

/// Writes `bytes` to `dir/name`; its path.
fn put(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.display().to_string()
}

fn cases() -> u32 {
    std::env::var("HOMOSPLINE_CLI_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(64)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn every_command_ends_in_time_with_exit_0_to_3(
        flips in prop::collection::vec((any::<usize>(), 1u8..=255), 0..4),
        cut in (any::<usize>(), any::<usize>()),
        number in any::<usize>(),
        which in 0usize..5,
    ) {
        let dir = tmp("fuzz-cli");
        std::fs::create_dir_all(&dir).unwrap();
        let scenes = ["concave-cup", "convex", "field", "narrow-pass", "two-homotopies"];
        let scene = mutate(&fixture(&format!("fixtures/scenes/{}.yaml", scenes[which])), &flips, cut, number);
        let s = put(&dir, "scene.yaml", &scene);
        let mut c = homospline();
        c.args(["check", &s]);
        run_bounded(c, &format!("check {}", String::from_utf8_lossy(&scene)));
        let mut c = homospline();
        c.args(["plan", &s, "--classes", "2"]);
        run_bounded(c, &format!("plan {}", String::from_utf8_lossy(&scene)));
        let mut c = homospline();
        c.args(["graph", &s]);
        run_bounded(c, &format!("graph {}", String::from_utf8_lossy(&scene)));

        // A world beside its (unchanged) scene, as the fixtures are laid out.
        let world = mutate(&fixture(&format!("fixtures/worlds/{}-blocked.yaml", scenes[which])), &flips, cut, number);
        let wdir = dir.join("worlds");
        std::fs::create_dir_all(&wdir).unwrap();
        std::fs::create_dir_all(dir.join("scenes")).unwrap();
        put(&dir.join("scenes"), &format!("{}.yaml", scenes[which]), &fixture(&format!("fixtures/scenes/{}.yaml", scenes[which])));
        let w = put(&wdir, "world.yaml", &world);
        let mut c = homospline();
        c.args(["simulate", &w, "--classes", "2"]);
        run_bounded(c, &format!("simulate {}", String::from_utf8_lossy(&world)));

        let maps = ["maze-32-32-2", "random-32-32-10", "room-32-32-4"];
        let name = maps[which % maps.len()];
        let map = mutate(&fixture(&format!("fixtures/maps/movingai/{name}.map")), &flips, cut, number);
        let m = put(&dir, &format!("{name}.map"), &map);
        let mut c = homospline();
        c.args(["plan", &m, "--start", "1.5,1.5", "--goal", "30.5,30.5", "--classes", "2"]);
        run_bounded(c, &format!("plan {name}.map mutated"));

        let scen = mutate(&fixture(&format!("fixtures/maps/movingai/{name}-random-1.scen")), &flips, cut, number);
        // The scenario file names the map beside it: the unchanged one.
        put(&dir, &format!("{name}.map"), &fixture(&format!("fixtures/maps/movingai/{name}.map")));
        let sc = put(&dir, "bench.scen", &scen);
        let mut c = homospline();
        c.args(["bench-scen", &sc, "--sample", "2", "--classes", "2"]);
        run_bounded(c, &format!("bench-scen {}", String::from_utf8_lossy(&scen)));
    }
}
