//! `homospline bench-scen` and `bench-merge` on bad and edge input, end to end: a `.scen`
//! given twice, an empty shard, CSV fields checked on merge, `.scen` and `.map` headers, and
//! the count of scenarios picked.

use std::path::{Path, PathBuf};
use std::process::Output;

use crate::common::*;

const ROOM_SCEN: &str = "fixtures/maps/movingai/room-32-32-4-random-1.scen";
const MAZE_SCEN: &str = "fixtures/maps/movingai/maze-32-32-2-random-1.scen";

/// Scenarios in the fixture files (their lines but the `version` line).
const ROOM_SCENARIOS: usize = 341;
const MAZE_SCENARIOS: usize = 333;

/// Runs `homospline args` without a Slurm job array in the environment.
fn run(args: &[&str]) -> Output {
    homospline()
        .args(args)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .output()
        .unwrap()
}

fn stdout_of(out: &Output) -> String {
    assert_ok(out);
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// A fresh scratch directory of this test process.
fn scratch(name: &str) -> PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn text(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// No figure printed as NaN, infinite or negative zero: no word `NaN`, `inf` or `infinity`
/// (any case, wherever it stands: before a comma, a space, the end of a line or of the
/// text), and no `-0.00`.
fn assert_no_odd_figures(text: &str) {
    for word in text.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
        for bad in ["nan", "inf", "infinity"] {
            assert!(!word.eq_ignore_ascii_case(bad), "{word} in {text}");
        }
    }
    assert!(!text.contains("-0.00"), "-0.00 in {text}");
}

#[test]
fn odd_figures_are_caught_wherever_they_stand() {
    let caught = |text: &str| std::panic::catch_unwind(|| assert_no_odd_figures(text)).is_err();
    for text in [
        "max inf\nnext line",
        "max inf",
        "median NaN\n",
        "ratio (inf)",
        "min -inf, max 2",
        "max inf ms",
        "mean -0.00 ms",
        "nan",
    ] {
        assert!(caught(text), "{text:?} passed");
    }
    for text in ["information, infeasible, Infinite", "success 1/1 (100.0 %)"] {
        assert!(!caught(text), "{text:?} caught");
    }
}

#[test]
fn a_scen_file_given_twice_is_refused_naming_it() {
    let err = refused(&["bench-scen", ROOM_SCEN, ROOM_SCEN, "--limit", "1"]);
    assert!(
        err.contains(&format!(
            "{ROOM_SCEN}: the same .scen file is given twice: its scenarios would be planned twice"
        )),
        "{err}"
    );
    // Through another spelling of its path: the same file.
    let other = format!("./{ROOM_SCEN}");
    assert_refused(
        &["bench-scen", ROOM_SCEN, &other, "--limit", "1"],
        &format!("{other}: the same .scen file is given twice (as {ROOM_SCEN})"),
    );
    // Inside a directory given too.
    let dir = scratch("twice");
    let scen = dir.join("room.scen");
    std::fs::copy(root().join(ROOM_SCEN), &scen).unwrap();
    std::fs::copy(
        root().join("fixtures/maps/movingai/room-32-32-4.map"),
        dir.join("room-32-32-4.map"),
    )
    .unwrap();
    assert_refused(
        &["bench-scen", text(&dir), text(&scen), "--limit", "1"],
        "room.scen: the same .scen file is given twice",
    );
    // Two different files are fine, and so is a merge of their CSV.
    let csv = tmp("two-files.csv");
    let out = run(&[
        "bench-scen",
        ROOM_SCEN,
        text(&scen),
        "--limit",
        "1",
        "--classes",
        "1",
        "--csv",
        text(&csv),
    ]);
    assert!(stdout_of(&out).contains("success      2/2"));
    let merged = stdout_of(&run(&["bench-merge", text(&csv)]));
    assert!(merged.contains("2 scenarios from 1 CSV files"), "{merged}");
}

#[test]
fn an_empty_shard_says_so_and_its_csv_merges() {
    let (empty, full) = (tmp("empty-shard.csv"), tmp("full-shard.csv"));
    let shard = |k: &str, csv: &Path| {
        run(&[
            "bench-scen",
            ROOM_SCEN,
            "--limit",
            "1",
            "--classes",
            "1",
            "--shard",
            k,
            "--csv",
            text(csv),
        ])
    };
    let out = stdout_of(&shard("2/2", &empty));
    assert!(
        out.contains(&format!(
            "0 of 1 scenarios picked from {ROOM_SCENARIOS} (the first of each file: the shortest paths only), shard 2/2"
        )),
        "{out}"
    );
    assert!(
        out.contains("no scenarios in this shard or these CSVs"),
        "{out}"
    );
    assert!(!out.contains("success"), "{out}");
    assert_no_odd_figures(&out);
    // The CSV is the header alone.
    let csv = std::fs::read_to_string(&empty).unwrap();
    assert_eq!(csv.lines().count(), 1, "{csv}");
    assert!(csv.starts_with("file,index,line,"), "{csv}");
    // Merged alone: no scenarios, said so.
    let merged = stdout_of(&run(&["bench-merge", text(&empty)]));
    assert!(merged.contains("0 scenarios from 1 CSV files"), "{merged}");
    assert!(
        merged.contains("no scenarios in this shard or these CSVs"),
        "{merged}"
    );
    assert_no_odd_figures(&merged);
    // Merged with the other shard: that shard's summary.
    stdout_of(&shard("1/2", &full));
    let merged = stdout_of(&run(&["bench-merge", text(&empty), text(&full)]));
    assert!(merged.contains("1 scenarios from 2 CSV files"), "{merged}");
    assert!(merged.contains("success      1/1"), "{merged}");
    assert_no_odd_figures(&merged);
}

/// A CSV as `bench-scen` writes it: a plan, a timeout, no plan, an error.
const GOOD_ROWS: [&str; 4] = [
    "s.scen,0,2,5,21.5,14.5,9.5,0.5,16,20,1.25,0.5,0,true,20.000,ok",
    "s.scen,1,3,9,29.5,30.5,5.5,25.5,40,50,1.25,NaN,0,false,90.500,timeout",
    "s.scen,2,4,9,1.5,1.5,3.5,1.5,2,NaN,NaN,NaN,3,false,5.000,no collision-free class among 3",
    "s.scen,3,5,9,1.5,1.5,99.5,1.5,2,NaN,NaN,NaN,0,false,0.100,error: goal [99.5; 1.5] is outside the map",
];

/// Writes a CSV of the good rows with row `i` (0-based) replaced by `bad`; returns its path.
fn csv_with(name: &str, i: usize, bad: &str) -> PathBuf {
    let mut rows = GOOD_ROWS.map(String::from);
    rows[i] = bad.to_owned();
    let p = tmp(name);
    std::fs::write(
        &p,
        format!(
            "{}\n{}\n",
            homospline_maps::sweep::CSV_HEADER,
            rows.join("\n")
        ),
    )
    .unwrap();
    p
}

#[test]
fn bench_merge_checks_every_field() {
    // The good rows merge.
    let good = csv_with("good.csv", 0, GOOD_ROWS[0]);
    let out = stdout_of(&run(&["bench-merge", text(&good)]));
    assert!(
        out.contains("success      1/4 (25.0 %), timeouts 1"),
        "{out}"
    );
    assert!(out.contains("median 1.2500"), "{out}");
    let cases = [
        (
            1,
            "s.scen,1,3,9,29.5,30.5,5.5,25.5,40,50,1.25,NaN,0,false,NaN,timeout",
            "time_ms: 'NaN' is not a finite non-negative number",
        ),
        (
            0,
            "s.scen,0,2,5,21.5,14.5,9.5,0.5,16,20,1.25,0.5,0,maybe,20.000,ok",
            "success: 'maybe' is not a boolean (true or false)",
        ),
        (
            1,
            "s.scen,1,3,9,29.5,30.5,5.5,25.5,40,50,1.25,NaN,0,true,90.500,timeout",
            "success: 'true' given, but the outcome is 'timeout'",
        ),
        (
            0,
            "s.scen,0,2,5,21.5,14.5,9.5,0.5,16,20,0.9,0.5,0,true,20.000,ok",
            "ratio: '0.9' is not length / optimal = 1.25",
        ),
        (
            2,
            "s.scen,2,4,9,1.5,1.5,3.5,1.5,2,NaN,1.0,NaN,3,false,5.000,no collision-free class among 3",
            "ratio: '1.0' given, but there is no length / optimal",
        ),
        (
            2,
            "s.scen,2,4,9,1.5,1.5,3.5,1.5,2,NaN,NaN,NaN,2,false,5.000,no collision-free class among 3",
            "classes: '2' given, but the outcome says 3",
        ),
        (
            0,
            "s.scen,0,2,5,21.5,14.5,9.5,0.5,-16,20,1.25,0.5,0,true,20.000,ok",
            "optimal: '-16' is not a finite non-negative number",
        ),
        (
            0,
            "s.scen,0,2,5,inf,14.5,9.5,0.5,16,20,1.25,0.5,0,true,20.000,ok",
            "start_x: 'inf' is not a finite non-negative number",
        ),
        (
            3,
            "s.scen,3,5,9,1.5,1.5,99.5,1.5,2,7,NaN,NaN,0,false,0.100,error: no",
            "length: '7' given, but there is no path",
        ),
        (
            0,
            "s.scen,1,3,5,21.5,14.5,9.5,0.5,16,20,1.25,0.5,0,true,20.000,ok",
            "scenario 1 of s.scen is also at line 2 of the same CSV",
        ),
    ];
    for (k, (i, bad, needle)) in cases.into_iter().enumerate() {
        let name = format!("bad-{k}.csv");
        let p = csv_with(&name, i, bad);
        let err = refused(&["bench-merge", text(&p)]);
        // file:line: column: problem (the duplicate at the later of its two lines).
        let line = if needle.starts_with("scenario") {
            3
        } else {
            i + 2
        };
        assert!(
            err.contains(&format!("{name}:{line}: {needle}")),
            "{bad}: {err}"
        );
    }
}

/// A directory holding room-32-32-4.map and a `.scen` of `text` beside it; returns the
/// `.scen`'s path.
fn scen_beside_room(dir: &str, name: &str, text: &str) -> PathBuf {
    let dir = scratch(dir);
    std::fs::copy(
        root().join("fixtures/maps/movingai/room-32-32-4.map"),
        dir.join("room-32-32-4.map"),
    )
    .unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const ROOM_LINE: &str = "5\troom-32-32-4.map\t32\t32\t21\t14\t9\t0\t23.65685425";

#[test]
fn scen_headers_must_match_the_map_and_the_version() {
    // A line declaring another map size, even past --limit (every shard refuses alike).
    let other_size = ROOM_LINE.replace("\t32\t32\t", "\t64\t64\t");
    let p = scen_beside_room(
        "size",
        "size.scen",
        &format!("version 1\n{ROOM_LINE}\n{other_size}\n"),
    );
    let err = refused(&["bench-scen", text(&p), "--limit", "1"]);
    assert!(
        err.contains(
            "size.scen:3: map size: the line declares a 64 x 64 map (width x height), but its map"
        ) && err.contains(
            "room-32-32-4.map is 32 x 32: scaled maps are not supported (MovingAI would scale the map to 64 x 64)"
        ),
        "{err}"
    );
    // Width and height are not swapped silently either.
    let p = scen_beside_room(
        "swapped",
        "swapped.scen",
        &format!(
            "version 1\n{}\n",
            ROOM_LINE.replace("\t32\t32\t", "\t32\t33\t")
        ),
    );
    assert_refused(
        &["bench-scen", text(&p)],
        "swapped.scen:2: map size: the line declares a 32 x 33 map",
    );
    // Unknown versions.
    for v in ["version 2", "version 1.1", "version"] {
        let p = scen_beside_room("version", "v.scen", &format!("{v}\n{ROOM_LINE}\n"));
        assert_refused(
            &["bench-scen", text(&p)],
            &format!("v.scen:1: '{v}': unknown version"),
        );
    }
    // The versions MovingAI writes (the fixtures: `version 1`).
    for v in ["version 1", "version 1.0"] {
        let p = scen_beside_room("version-ok", "v.scen", &format!("{v}\n{ROOM_LINE}\n"));
        let out = stdout_of(&run(&["bench-scen", text(&p), "--classes", "1"]));
        assert!(out.contains("1 of 1 scenarios picked"), "{out}");
    }
}

#[test]
fn scen_files_with_blank_lines_a_byte_order_mark_or_joined_read() {
    let other = ROOM_LINE.replace("\t23.65685425", "\t23.6568");
    for (name, scen, n) in [
        ("blank.scen", format!("\n\nversion 1\n{ROOM_LINE}\n"), 1),
        ("bom.scen", format!("\u{feff}version 1\n{ROOM_LINE}\n"), 1),
        (
            "joined.scen",
            format!("version 1\n{ROOM_LINE}\nversion 1\n{other}\n"),
            2,
        ),
        // `version 1` and `version 1.0` are the one version.
        (
            "mixed.scen",
            format!("version 1\n{ROOM_LINE}\nversion 1.0\n{other}\n"),
            2,
        ),
    ] {
        let p = scen_beside_room("readable", name, &scen);
        let out = stdout_of(&run(&["bench-scen", text(&p), "--classes", "1"]));
        assert!(
            out.contains(&format!(
                "{n} of {n} scenarios picked, on room-32-32-4 (32 x 32)"
            )),
            "{name}: {out}"
        );
    }
    // A version other than 1 in a joined file: refused at its line.
    let p = scen_beside_room(
        "joined-versions",
        "other.scen",
        &format!("version 1\n{ROOM_LINE}\nversion 2\n{other}\n"),
    );
    assert_refused(
        &["bench-scen", text(&p)],
        "other.scen:3: 'version 2': unknown version",
    );
}

#[test]
fn map_header_errors_name_file_and_line() {
    let dir = scratch("headers");
    let rows = format!("{}\n", ".".repeat(4)).repeat(2);
    for (name, header, needle) in [
        (
            "hex.map",
            "type hex\nheight 2\nwidth 4\nmap\n",
            "hex.map:1: type 'hex' is not a MovingAI map type",
        ),
        (
            "untyped.map",
            "height 2\nwidth 4\nmap\n",
            "untyped.map:3: missing `type` line in the header",
        ),
        (
            "narrow.map",
            "type octile\nheight 2\nmap\n",
            "narrow.map:3: missing `width` line in the header",
        ),
        (
            "twice.map",
            "type octile\nheight 2\nwidth 4\nheight 2\nmap\n",
            "twice.map:4: a second `height` line (the first is line 2)",
        ),
    ] {
        let p = dir.join(name);
        std::fs::write(&p, format!("{header}{rows}")).unwrap();
        assert_refused(
            &["plan", text(&p), "--start", "0.5,0.5", "--goal", "3.5,1.5"],
            needle,
        );
    }
}

#[test]
fn the_count_picked_is_out_of_what_the_run_picked_from() {
    let picked = |args: &[&str]| -> String {
        let mut all = vec!["bench-scen"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--classes", "1"]);
        let out = stdout_of(&run(&all));
        out.lines().next().unwrap().to_owned()
    };
    // ROWS of PICKED (the sweep, before sharding) from TOTAL (every scenario of the files).
    // --sample: of every scenario of the file.
    let line = picked(&[ROOM_SCEN, "--sample", "3"]);
    assert!(
        line.contains(&format!(
            "3 of 3 scenarios picked from {ROOM_SCENARIOS} (sampled evenly over every bucket), on"
        )),
        "{line}"
    );
    // Several files: of all their scenarios.
    let line = picked(&[ROOM_SCEN, MAZE_SCEN, "--sample", "1"]);
    assert!(
        line.contains(&format!(
            "2 of 2 scenarios picked from {} (sampled evenly over every bucket), on",
            ROOM_SCENARIOS + MAZE_SCENARIOS
        )),
        "{line}"
    );
    // A shard: its share of the sweep, the sweep, and all the files hold.
    let line = picked(&[ROOM_SCEN, "--sample", "3", "--shard", "1/2"]);
    assert!(
        line.contains(&format!(
            "2 of 3 scenarios picked from {ROOM_SCENARIOS} (sampled evenly over every bucket), shard 1/2, on"
        )),
        "{line}"
    );
    // --limit N: the first N of each file, which the message says, out of all of them.
    let line = picked(&[ROOM_SCEN, MAZE_SCEN, "--limit", "1", "--shard", "2/2"]);
    assert!(
        line.contains(&format!(
            "1 of 2 scenarios picked from {} (the first of each file: the shortest paths only), shard 2/2, on",
            ROOM_SCENARIOS + MAZE_SCENARIOS
        )),
        "{line}"
    );
    // No option: every scenario is picked, a shard plans its share of them.
    let p = scen_beside_room(
        "all",
        "all.scen",
        &format!("version 1\n{ROOM_LINE}\n{ROOM_LINE}\n{ROOM_LINE}\n"),
    );
    let line = picked(&[text(&p), "--shard", "1/2"]);
    assert!(
        line.contains("2 of 3 scenarios picked, shard 1/2, on room-32-32-4 (32 x 32)"),
        "{line}"
    );
}

/// A CSV the older writer wrote (length, ratio and clearance with 4 decimals), and the
/// writer's own `inf` for a ratio whose quotient overflows, merge.
#[test]
fn bench_merge_reads_rounded_and_infinite_ratios() {
    let rounded = "s.scen,0,2,5,21.5,14.5,9.5,0.5,1.41421356,1.4181,1.0028,0.2500,0,true,20.000,ok";
    let p = csv_with("rounded.csv", 0, rounded);
    let out = stdout_of(&run(&["bench-merge", text(&p)]));
    assert!(out.contains("success      1/4"), "{out}");
    assert_no_odd_figures(&out);
    let tiny = format!("0.{}1", "0".repeat(309));
    let infinite = format!("s.scen,0,2,5,21.5,14.5,9.5,0.5,{tiny},1e10,inf,0.5,0,true,20.000,ok");
    let p = csv_with("infinite.csv", 0, &infinite);
    let out = stdout_of(&run(&["bench-merge", text(&p)]));
    assert!(out.contains("success      1/4"), "{out}");
    assert_no_odd_figures(&out);
    // A ratio more than rounding explains is still refused.
    let p = csv_with("off.csv", 0, &rounded.replace(",1.0028,", ",1.0031,"));
    assert_refused(
        &["bench-merge", text(&p)],
        "off.csv:2: ratio: '1.0031' is not length / optimal = 1.00274",
    );
}

/// `--time-limit` stops a plan at the limit (its interrupt raised): such a row is a
/// timeout without a length. It only labelled plans that ended late, so a plan that ran on
/// (past 100 s at radius 0.49 once) held the run; and the rows read back and merge.
#[test]
fn the_time_limit_stops_a_plan_at_the_limit() {
    let csv = scratch("time-limit").join("rows.csv");
    let out = run(&[
        "bench-scen",
        "fixtures/maps/full-scale/maze512-8-0.map.scen",
        "--sample",
        "2",
        "--time-limit",
        "1",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_ok(&out);
    let written = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = written.lines().skip(1).collect();
    assert_eq!(rows.len(), 2);
    // The longer scenario (a path of 2,400 cells) cannot plan in 1 ms: stopped, no length.
    let last: Vec<&str> = rows[1].split(',').collect();
    assert_eq!(last[last.len() - 1], "timeout", "{}", rows[1]);
    assert_eq!(last[9], "NaN", "{}", rows[1]);
    let merged = run(&["bench-merge", text(&csv)]);
    assert!(
        stdout_of(&merged).contains("timeout"),
        "{}",
        stdout_of(&merged)
    );
}

#[test]
fn a_map_without_room_for_the_robot_is_each_scenario_s_error_row() {
    // No point of room-32-32-4 keeps a radius of 2 (its doors are one cell wide): the sweep
    // aborted (exit 2, no CSV). Each of its scenarios is now a row saying so, as the guide
    // promises per-scenario errors and exit 0.
    let csv = tmp("no-room.csv");
    let out = homospline()
        .args([
            "bench-scen",
            "fixtures/maps/movingai/room-32-32-4-random-1.scen",
            "--sample",
            "3",
            "--robot-radius",
            "2",
            "--csv",
        ])
        .arg(&csv)
        .output()
        .unwrap();
    assert_ok(&out);
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 3, "{text}");
    for r in rows {
        assert!(
            r.ends_with("false,0.000,error: fixtures/maps/movingai/room-32-32-4.map: no route: no point of the map keeps the robot radius 2"),
            "{r}"
        );
    }
}
