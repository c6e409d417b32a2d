//! Helpers shared by the end-to-end tests of `homospline`.
#![allow(dead_code)] // each test file uses its own subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `plan` on a MovingAI map fixture, from a start to a goal that are free cells' centres.
pub const MAP_PLAN: [&str; 6] = [
    "plan",
    "fixtures/maps/movingai/random-32-32-10.map",
    "--start",
    "1.5,27.5",
    "--goal",
    "30.5,2.5",
];

/// The `homospline` binary, run from the repository root (fixture paths are relative).
pub fn homospline() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_homospline"));
    c.current_dir(root());
    c
}

/// The repository root.
pub fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// A scratch file for this test process, in a folder of the calling test file's own (the
/// test files share one process: two may use one name).
///
/// The folders live in Cargo's `target/tmp`, one per test process; the first call removes
/// those left by test processes that have ended, so repeated runs do not pile up.
#[track_caller]
pub fn tmp(name: &str) -> PathBuf {
    let caller = Path::new(std::panic::Location::caller().file());
    let module = caller
        .file_stem()
        .map_or_else(|| "common".to_owned(), |s| s.to_string_lossy().into_owned());
    let dir = scratch_root().join(module);
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// This process's scratch folder, `target/tmp/cli-test-<pid>`; made once, after sweeping
/// the folders of processes that no longer run (read from `/proc`; elsewhere nothing is
/// swept).
fn scratch_root() -> &'static Path {
    static ROOT: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    ROOT.get_or_init(|| {
        let base = Path::new(env!("CARGO_TARGET_TMPDIR"));
        if Path::new("/proc/self").exists() {
            for entry in std::fs::read_dir(base).into_iter().flatten().flatten() {
                let name = entry.file_name();
                let pid = name.to_str().and_then(|n| n.strip_prefix("cli-test-"));
                if pid.is_some_and(|p| !Path::new("/proc").join(p).exists()) {
                    let _ = std::fs::remove_dir_all(entry.path());
                }
            }
        }
        let root = base.join(format!("cli-test-{}", std::process::id()));
        std::fs::create_dir_all(&root).unwrap();
        root
    })
}

/// Waits for `child` at most `secs` seconds: its exit status, or a panic naming `what`
/// after it is killed (a hang is a failure, not a stuck test run).
pub fn wait_bounded(
    child: &mut std::process::Child,
    secs: u64,
    what: &str,
) -> std::process::ExitStatus {
    let t = std::time::Instant::now();
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return s;
        }
        if t.elapsed().as_secs() >= secs {
            let _ = child.kill();
            panic!("{what} ran past {secs} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// Asserts exit code 0, showing stderr otherwise.
pub fn assert_ok(out: &Output) {
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `homospline args` and asserts a refusal of bad input: exit 2, nothing on stdout, no
/// panic; returns stderr, which names the file or option and the problem.
pub fn refused(args: &[&str]) -> String {
    let out = homospline().args(args).output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(out.stdout.is_empty(), "{args:?}: nothing on stdout");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    err
}

/// [`refused`], with stderr holding `needle`.
pub fn assert_refused(args: &[&str], needle: &str) {
    let err = refused(args);
    assert!(err.contains(needle), "{args:?}: {err}");
}

/// A JSON file, parsed.
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Asserts that the SVG file at `path` parses and has a `<g>` layer with each of these ids.
pub fn assert_svg_layers(path: &Path, expected: &[&str]) {
    let layers = svg_layers(&std::fs::read_to_string(path).unwrap());
    for layer in expected {
        assert!(
            layers.iter().any(|l| l == layer),
            "layer {layer} in {layers:?}"
        );
    }
}

/// Parses the whole document and returns the ids of its `<g>` layers.
pub fn svg_layers(text: &str) -> Vec<String> {
    let mut reader = quick_xml::Reader::from_str(text);
    let mut ids = Vec::new();
    let mut depth = 0i64;
    loop {
        match reader.read_event().expect("well-formed SVG") {
            quick_xml::events::Event::Start(e) => {
                depth += 1;
                if e.name().as_ref() == b"g" {
                    for a in e.attributes() {
                        let a = a.unwrap();
                        if a.key.as_ref() == b"id" {
                            ids.push(String::from_utf8(a.value.to_vec()).unwrap());
                        }
                    }
                }
            }
            quick_xml::events::Event::End(_) => depth -= 1,
            quick_xml::events::Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(depth, 0, "balanced tags");
    ids
}

/// `base` mutated: bytes flipped, a slice cut out, a number replaced by an extreme one.
pub fn mutate(base: &[u8], flips: &[(usize, u8)], cut: (usize, usize), number: usize) -> Vec<u8> {
    let mut v = base.to_vec();
    if v.is_empty() {
        return v;
    }
    for &(i, b) in flips {
        let k = i % v.len();
        v[k] ^= b;
    }
    let (a, n) = (cut.0 % v.len(), cut.1 % 64);
    let z = (a + n).min(v.len());
    v.drain(a..z);
    let extremes: [&[u8]; 6] = [b"1e308", b"-0", b"NaN", b"99999999999", b"-7", b"0.0000001"];
    if let Some(p) = v.iter().position(|c| c.is_ascii_digit()) {
        let at = (p + number) % v.len();
        let e = extremes[number % extremes.len()];
        v.splice(at..(at + 1).min(v.len()), e.iter().copied());
    }
    v
}
