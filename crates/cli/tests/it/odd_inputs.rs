//! Odd inputs and outputs found by a hostile review: outputs onto the maps a `.scen` file
//! names or through a link onto another input, devices and pipes as outputs, a thread count
//! past the limit from the environment, and parser messages that named Rust types or no
//! field. Each case failed before its fix.

use crate::common::*;
use std::path::Path;

/// A scratch directory of its own, emptied.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = tmp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `text` written to `dir/name`; its path as a string.
fn file(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_owned()
}

#[test]
fn a_csv_onto_a_map_a_scen_names_is_refused() {
    let dir = scratch("scen-map");
    let movingai = root().join("fixtures/maps/movingai");
    for f in ["random-32-32-10.map", "random-32-32-10-random-1.scen"] {
        std::fs::copy(movingai.join(f), dir.join(f)).unwrap();
    }
    let map = dir.join("random-32-32-10.map");
    let before = std::fs::read(&map).unwrap();
    let scen = dir.join("random-32-32-10-random-1.scen");
    for input in [&scen, &dir] {
        let err = refused(&[
            "bench-scen",
            input.to_str().unwrap(),
            "--limit",
            "1",
            "--csv",
            map.to_str().unwrap(),
        ]);
        assert!(
            err.contains("--csv") && err.contains("is the input"),
            "{err}"
        );
    }
    assert_eq!(
        std::fs::read(&map).unwrap(),
        before,
        "the map was overwritten"
    );
}

/// `graph --out-dir`: a file in DIR that links to another input is not written through.
#[cfg(unix)]
#[test]
fn a_graph_out_dir_link_onto_another_input_is_refused() {
    let dir = scratch("out-dir-link");
    let movingai = root().join("fixtures/maps/movingai");
    std::fs::copy(movingai.join("room-32-32-4.map"), dir.join("a.map")).unwrap();
    std::fs::copy(movingai.join("random-32-32-10.map"), dir.join("b.map")).unwrap();
    std::fs::create_dir_all(dir.join("out")).unwrap();
    std::os::unix::fs::symlink("../a.map", dir.join("out/b.msgpack")).unwrap();
    let before = std::fs::read(dir.join("a.map")).unwrap();
    let (a, b, out) = (dir.join("a.map"), dir.join("b.map"), dir.join("out"));
    let err = refused(&[
        "graph",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert!(
        err.contains("--out-dir") && err.contains("is the input"),
        "{err}"
    );
    assert!(!err.contains("--out "), "{err}");
    assert_eq!(std::fs::read(dir.join("a.map")).unwrap(), before);
    assert!(
        !dir.join("out/a.msgpack").exists(),
        "refused before any graph"
    );
}

/// `/dev/null` twice, and a named pipe: written to, never replaced by a file.
#[cfg(unix)]
#[test]
fn devices_and_pipes_are_written_to_as_they_are() {
    use std::os::unix::fs::FileTypeExt;
    let out = homospline()
        .args(["plan", "--json", "/dev/null", "--svg", "/dev/null"])
        .output()
        .unwrap();
    assert_ok(&out);
    let null = std::fs::metadata("/dev/null").unwrap().file_type();
    assert!(null.is_char_device(), "/dev/null was replaced");
    let dir = scratch("fifo");
    let fifo = dir.join("plan.fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let out = homospline()
        .args(["plan", "--json", fifo.to_str().unwrap()])
        .output()
        .unwrap();
    assert_ok(&out);
    let json: serde_json::Value = serde_json::from_slice(&reader.join().unwrap()).unwrap();
    assert!(json["classes"].is_array());
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(kind.is_fifo(), "the pipe was replaced by a file");
}

#[test]
fn an_output_that_is_a_directory_is_refused_before_the_work() {
    let dir = scratch("out-is-dir");
    assert_refused(
        &["plan", "--json", dir.to_str().unwrap()],
        "is a directory; name a file",
    );
}

#[test]
fn rayon_num_threads_past_the_limit_is_refused() {
    let out = homospline()
        .args(["plan"])
        .env("RAYON_NUM_THREADS", "5000")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("RAYON_NUM_THREADS=5000: at most 256"), "{err}");
    let out = homospline()
        .args(["plan"])
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .unwrap();
    assert_ok(&out);
}

/// Parser messages in words, under the key where the fault is, with what was found.
#[test]
fn parser_messages_name_the_key_and_what_was_found() {
    let dir = scratch("messages");
    let scene = std::fs::read_to_string(root().join("fixtures/scenes/convex.yaml")).unwrap();
    for (name, text, needle) in [
        (
            "two.yaml",
            format!("{scene}---\nname: x\n"),
            ": a second YAML document starts here (after `---`): the file holds one",
        ),
        (
            "version.yaml",
            format!("version: 1.0\n{scene}"),
            ":1:10: version: expected a whole number >= 0 (without quotes), got '1.0'",
        ),
        (
            "word.yaml",
            scene.replace("min: [0, 0]", "min: [zero, 0]"),
            ": bounds.min: expected a number (such as 2, -1.5 or 3e-2, without quotes), not the string 'zero'",
        ),
        (
            "flow.json",
            r#"{"name":"j","bounds":{"min":[0,0],"max":[NaN,60]},"start":[5,30],"goal":[55,30],"obstacles":[]}"#.to_owned(),
            ":1:42: bounds.max: expected a number (such as 2, -1.5 or 3e-2, without quotes), not 'NaN': it must be finite",
        ),
        (
            "escape.yaml",
            scene.replace("name: convex", "name: \"a\\e[31mred\""),
            "name: 'a\\u{1b}[31mred' holds the control character '\\u{1b}': names are printed",
        ),
    ] {
        let p = file(&dir, name, &text);
        let err = assert_check_refused(&p);
        assert!(err.contains(needle), "{name}: {err}");
        assert!(!err.contains("invalid") && !err.contains("from_str"), "{err}");
    }
    // An obstacle without a name is called after its index: the message says so.
    let p = file(
        &dir,
        "unnamed.yaml",
        &scene
            .replace("  - name: b\n", "  - name: obstacle-2\n")
            .replace("  - name: c\n", "  -\n"),
    );
    let err = assert_check_refused(&p);
    assert!(
        err.contains("duplicate obstacle name 'obstacle-2' (also obstacles[1]); obstacles[2] has no name and is called after its index"),
        "{err}"
    );
    // A saved graph that is no graph, and a ROS map YAML's fields.
    let err = refused(&[
        "plan",
        "fixtures/scenes/convex.yaml",
        "--graph",
        "fixtures/scenes/convex.yaml",
    ]);
    assert!(
        err.contains("not a graph saved by `homospline graph --out`") && !err.contains("struct"),
        "{err}"
    );
    let ros = root().join("fixtures/maps/ros/turtlebot3_world");
    std::fs::copy(ros.join("map.pgm"), dir.join("map.pgm")).unwrap();
    let yaml = std::fs::read_to_string(ros.join("map.yaml")).unwrap();
    for (edit, needle) in [
        (
            ("negate: 0", "negate: true"),
            "negate: expected a whole number, got 'true'",
        ),
        (("resolution: 0.050000", "resolution: 1e-300"), "got 1e-300"),
    ] {
        assert!(yaml.lines().any(|l| l == edit.0), "{yaml}");
        let p = file(&dir, "map.yaml", &yaml.replace(edit.0, edit.1));
        let err = refused(&["plan", &p, "--start", "0,0", "--goal", "1,1"]);
        assert!(err.contains(needle) && err.len() < 300, "{err}");
    }
    let origin = yaml.lines().find(|l| l.starts_with("origin:")).unwrap();
    let p = file(&dir, "map.yaml", &yaml.replace(origin, "origin: [0, 0]"));
    let err = refused(&["plan", &p, "--start", "0,0", "--goal", "1,1"]);
    assert!(err.contains(":3: origin: invalid length 2"), "{err}");
}

/// `check FILE`, refused: its stderr.
fn assert_check_refused(path: &str) -> String {
    refused(&["check", path])
}

#[test]
fn a_yaml_alias_used_too_often_is_named_in_words() {
    let dir = scratch("aliases");
    let mut text = String::from(
        "name: a\nbounds: {min: [0, 0], max: [60, 60]}\nstart: [5, 30]\ngoal: [55, 30]\nobstacles:\n  - name: a\n    circles:\n      - &p [20, 28, 1]\n",
    );
    for _ in 0..100 {
        text.push_str("      - *p\n");
    }
    let p = file(&dir, "aliases.yaml", &text);
    let err = assert_check_refused(&p);
    assert!(
        err.contains(
            "limit on aliases per anchor (once there are 100 aliases, at most 10 per anchor"
        ),
        "{err}"
    );
}

#[test]
fn a_map_with_a_byte_order_mark_or_an_upper_case_name_is_read() {
    let dir = scratch("bom");
    let text =
        std::fs::read_to_string(root().join("fixtures/maps/movingai/room-32-32-4.map")).unwrap();
    let p = file(&dir, "room.map", &format!("\u{feff}{text}"));
    let out = homospline()
        .args(["plan", &p, "--start", "1.5,1.5", "--goal", "30.5,30.5"])
        .output()
        .unwrap();
    assert!(
        out.status.code() != Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let ros = root().join("fixtures/maps/ros/turtlebot3_world");
    std::fs::copy(ros.join("map.pgm"), dir.join("map.pgm")).unwrap();
    std::fs::copy(ros.join("map.yaml"), dir.join("MAP.YAML")).unwrap();
    let p = dir.join("MAP.YAML");
    let out = homospline()
        .args([
            "plan",
            p.to_str().unwrap(),
            "--start",
            "-2,-0.5",
            "--goal",
            "1.5,0.5",
        ])
        .output()
        .unwrap();
    assert_ok(&out);
}

/// A PNG whose header claims 20000 x 20000 cells: refused by its size before its pixels
/// are decoded (it was decoded first, a gigabyte, or failed as a broken image).
#[test]
fn a_ros_image_too_large_is_refused_from_its_header() {
    let dir = scratch("big-png");
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = b"IHDR".to_vec();
    ihdr.extend(20000u32.to_be_bytes());
    ihdr.extend(20000u32.to_be_bytes());
    ihdr.extend([8, 0, 0, 0, 0]);
    png.extend(13u32.to_be_bytes());
    png.extend(&ihdr);
    png.extend(crc32(&ihdr).to_be_bytes());
    // An empty first data chunk: the header is read whole; the pixels are not there.
    png.extend(0u32.to_be_bytes());
    png.extend(b"IDAT");
    png.extend(crc32(b"IDAT").to_be_bytes());
    std::fs::write(dir.join("big.png"), png).unwrap();
    let p = file(
        &dir,
        "big.yaml",
        "image: big.png\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    );
    assert_refused(
        &["plan", &p, "--start", "1,1", "--goal", "2,2"],
        "is 20000 x 20000 cells (400000000 cells); at most 16777216 cells",
    );
}

/// The CRC-32 of PNG chunks (ISO 3309), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// The note on obstacles smaller than a cell is not printed for a grid that is refused
/// (it printed a cell size of 300 digits before the refusal).
#[test]
fn a_refused_grid_prints_no_note_before_its_error() {
    let err = refused(&[
        "plan",
        "fixtures/scenes/convex.yaml",
        "--resolution",
        "1e-300",
    ]);
    assert!(!err.contains("note:") && err.len() < 300, "{err}");
}

/// A temporary file a killed run left behind (the same process id, as in a container) does
/// not stand in the way of the next run's output.
#[cfg(unix)]
#[test]
fn a_temporary_file_left_behind_does_not_block_the_output() {
    let dir = scratch("left-behind");
    let script = format!(
        "touch .new.json.$$.tmp .new.json.$$.probe && exec \"{}\" plan --json new.json",
        env!("CARGO_BIN_EXE_homospline")
    );
    let out = std::process::Command::new("sh")
        .args(["-c", &script])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_ok(&out);
    assert!(read_json(&dir.join("new.json"))["classes"].is_array());
}

/// `--json /dev/stdout` with stdout appended to a file: written through stdout, after the
/// table (the file had been replaced, the table and what the file held lost).
#[cfg(unix)]
#[test]
fn an_output_onto_stdout_redirected_to_a_file_is_appended_to_it() {
    let dir = scratch("stdout-file");
    let log = dir.join("log");
    std::fs::write(&log, "OLD\n").unwrap();
    let file = std::fs::OpenOptions::new().append(true).open(&log).unwrap();
    let out = homospline()
        .args(["plan", "--json", "/dev/stdout"])
        .stdout(file)
        .output()
        .unwrap();
    assert_ok(&out);
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(text.starts_with("OLD\nscene "), "{text}");
    let json = &text[text.find("\n{").unwrap()..];
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    assert!(v["classes"].is_array());
}

#[test]
fn an_unknown_first_key_of_a_flow_map_names_its_parent_and_json_strings_lose_their_quotes() {
    let dir = scratch("flow-keys");
    let scene = std::fs::read_to_string(root().join("fixtures/scenes/convex.yaml")).unwrap();
    let p = file(&dir, "mn.yaml", &scene.replace("min: [0, 0]", "mn: [0, 0]"));
    let err = assert_check_refused(&p);
    assert!(err.contains(":3:10: bounds: unknown field `mn`"), "{err}");
    let p = file(
        &dir,
        "q.json",
        r#"{"name":"j","bounds":{"min":[0,0],"max":[60,60]},"start":[5,"q"],"goal":[55,30],"obstacles":[]}"#,
    );
    let err = assert_check_refused(&p);
    assert!(
        err.contains(
            "start: expected a number (such as 2, -1.5 or 3e-2, without quotes), not the string 'q'"
        ),
        "{err}"
    );
}
