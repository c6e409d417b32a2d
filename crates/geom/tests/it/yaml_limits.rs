//! The YAML reader's limits: a scene far past the parser's default node budget reads, and
//! a file past the project's budget is refused with a message that names the limit in
//! words (it once printed Rust's debug text, "budget breached: Nodes { nodes: 250001 }").

use homospline_geom::Scene;
use homospline_geom::scene::{from_yaml_within, yaml_problem};

/// A scene of `n` one-circle obstacles on a grid, as block YAML.
fn scene_text(n: usize) -> String {
    let mut s = String::from(
        "name: many\nbounds: {min: [0, 0], max: [1000, 1000]}\nstart: [1, 1]\ngoal: [999, 999]\nobstacles:\n",
    );
    for k in 0..n {
        let (x, y) = (10.0 + (k % 300) as f64 * 3.2, 10.0 + (k / 300) as f64 * 3.2);
        s.push_str(&format!("  - name: o{k}\n    circles: [[{x}, {y}, 0.5]]\n"));
    }
    s
}

#[test]
fn a_scene_past_the_parsers_default_budget_reads() {
    // 60,000 obstacles: about 540,000 nodes (9 each, keys included), over the parser's
    // default of 250,000.
    let scene = Scene::from_str(&scene_text(60_000), "many.yaml").unwrap();
    assert_eq!(scene.obstacles.len(), 60_000);
}

#[test]
fn a_file_past_the_budget_is_refused_in_words() {
    let text = scene_text(100);
    let e = from_yaml_within::<serde::de::IgnoredAny>(&text, 50).unwrap_err();
    let msg = yaml_problem(&e, "malformed");
    assert!(
        msg.starts_with("exceeds the YAML reader's limit on nodes"),
        "{msg}"
    );
    assert!(!msg.contains('{'), "no debug text: {msg}");
}

/// A key given twice is named in words, without the parser's advice about its own options.
#[test]
fn a_duplicate_key_is_named_without_the_parsers_advice() {
    let text = "bounds: {min: [0, 0], max: [60, 60]}\nstart: [5, 30]\nstart: [6, 30]\ngoal: [55, 30]\nobstacles: []\n";
    let e = Scene::from_str(text, "dup.yaml").unwrap_err().to_string();
    assert!(e.contains("the key 'start' is given twice"), "{e}");
    assert!(!e.contains("Options"), "{e}");
}
