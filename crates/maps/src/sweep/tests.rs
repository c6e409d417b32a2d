//! Unit tests of the bench rows, their CSV form and the summary.

use super::*;

#[test]
fn shards_partition_and_parse() {
    let parts: Vec<Vec<usize>> = (1..=3)
        .map(|k| (0..10).filter(|&i| Shard { k, n: 3 }.takes(i)).collect())
        .collect();
    assert_eq!(parts, vec![vec![0, 3, 6, 9], vec![1, 4, 7], vec![2, 5, 8]]);
    assert_eq!(Shard::parse("2/5"), Ok(Shard { k: 2, n: 5 }));
    assert!(Shard::parse("0/5").is_err() && Shard::parse("6/5").is_err());
    assert!(Shard::parse("x").is_err());
    let env = |id: &'static str, count: &'static str, min: &'static str| {
        move |k: &str| match k {
            "SLURM_ARRAY_TASK_ID" => Some(id.to_owned()),
            "SLURM_ARRAY_TASK_COUNT" => Some(count.to_owned()),
            "SLURM_ARRAY_TASK_MIN" => Some(min.to_owned()),
            _ => None,
        }
    };
    assert_eq!(
        Shard::from_slurm(env("0", "4", "0")),
        Some(Ok(Shard { k: 1, n: 4 }))
    );
    assert_eq!(
        Shard::from_slurm(env("4", "4", "1")),
        Some(Ok(Shard { k: 4, n: 4 }))
    );
    assert!(matches!(
        Shard::from_slurm(env("9", "4", "1")),
        Some(Err(_))
    ));
    assert_eq!(Shard::from_slurm(|_| None), None);
}

#[test]
fn rows_survive_csv() {
    for outcome in [
        Outcome::Planned {
            length: 12.5,
            clearance: 0.25,
        },
        Outcome::Timeout { length: 3.0 },
        Outcome::NoPlan { classes: 5 },
        Outcome::Error("start is in an occupied cell".into()),
    ] {
        let r = row(outcome);
        assert_eq!(Row::from_csv(&r.to_csv(), "x.csv", 2).unwrap(), r);
    }
    assert!(
        Row::from_csv("a,b", "x.csv", 3)
            .unwrap_err()
            .to_string()
            .contains("x.csv:3")
    );
}

#[test]
fn a_file_name_with_a_line_break_keeps_its_row_whole() {
    let mut r = row(Outcome::Error("cannot read,\nthe map".into()));
    r.file = "a\nb,c\r.scen".into();
    let line = r.to_csv();
    assert!(!line.contains(['\n', '\r']), "{line:?}");
    let back = Row::from_csv(&line, "x.csv", 2).unwrap();
    assert_eq!(back.file, "a b;c .scen");
    assert_eq!(back.outcome, Outcome::Error("cannot read; the map".into()));
}

fn row(outcome: Outcome) -> Row {
    Row {
        file: "m.map.scen".into(),
        index: 7,
        line: 9,
        bucket: 2,
        start: Point::new(1.5, 2.5),
        goal: Point::new(3.5, 4.5),
        optimal: 10.0,
        outcome,
        time_ms: 1.25,
    }
}

/// `line` with column `column` set to `value`.
fn with(line: &str, column: &str, value: &str) -> String {
    let i = COLUMNS.iter().position(|c| *c == column).unwrap();
    let mut f: Vec<&str> = line.split(',').collect();
    f[i] = value;
    f.join(",")
}

#[test]
fn every_csv_field_is_checked_as_the_writer_writes_it() {
    assert_eq!(COLUMNS.join(","), CSV_HEADER);
    let ok = row(Outcome::Planned {
        length: 12.5,
        clearance: 0.25,
    })
    .to_csv();
    let timeout = row(Outcome::Timeout { length: 3.0 }).to_csv();
    let none = row(Outcome::NoPlan { classes: 5 }).to_csv();
    let error = row(Outcome::Error("start is outside".into())).to_csv();
    let cases = [
        (&ok, "file", " ", "file: empty"),
        (&ok, "index", "-1", "index: '-1' is not a count"),
        (&ok, "line", "0", "line: 0 cannot hold scenario 7"),
        (&ok, "line", "7", "line: 7 cannot hold scenario 7"),
        (&ok, "bucket", "x", "bucket: 'x' is not a bucket number"),
        (
            &ok,
            "time_ms",
            "1e308",
            "time_ms: '1e308' ms is beyond any run",
        ),
        (
            &ok,
            "start_x",
            "inf",
            "start_x: 'inf' is not a finite non-negative",
        ),
        (
            &ok,
            "goal_y",
            "NaN",
            "goal_y: 'NaN' is not a finite non-negative",
        ),
        (
            &ok,
            "optimal",
            "-1",
            "optimal: '-1' is not a finite non-negative",
        ),
        (
            &ok,
            "length",
            "NaN",
            "length: 'NaN' is not a finite non-negative",
        ),
        (
            &ok,
            "clearance",
            "NaN",
            "clearance: 'NaN' is not a positive clearance",
        ),
        (
            &ok,
            "clearance",
            "-0.5",
            "clearance: '-0.5' is not a positive clearance",
        ),
        (
            &ok,
            "classes",
            "3",
            "classes: 3 given, but the outcome is 'ok'",
        ),
        (
            &ok,
            "ratio",
            "1.5",
            "ratio: '1.5' is not length / optimal = 1.25",
        ),
        (
            &ok,
            "ratio",
            "NaN",
            "ratio: 'NaN' is not length / optimal = 1.25",
        ),
        (&ok, "success", "maybe", "success: 'maybe' is not a boolean"),
        (
            &ok,
            "success",
            "false",
            "success: 'false' given, but the outcome is 'ok'",
        ),
        (
            &ok,
            "time_ms",
            "NaN",
            "time_ms: 'NaN' is not a finite non-negative",
        ),
        (
            &ok,
            "time_ms",
            "-2",
            "time_ms: '-2' is not a finite non-negative",
        ),
        (
            &ok,
            "outcome",
            "fine",
            "outcome: 'fine' is not one this program writes",
        ),
        (
            &timeout,
            "success",
            "true",
            "success: 'true' given, but the outcome is 'timeout'",
        ),
        (
            &timeout,
            "clearance",
            "0.5",
            "clearance: '0.5' given, but the clearance",
        ),
        (
            &none,
            "classes",
            "4",
            "classes: '4' given, but the outcome says 5",
        ),
        (
            &none,
            "length",
            "3",
            "length: '3' given, but there is no path",
        ),
        (
            &none,
            "ratio",
            "0.3",
            "ratio: '0.3' given, but there is no length / optimal",
        ),
        (
            &none,
            "outcome",
            "no collision-free class among many",
            "outcome: 'no collision-free class among many': 'many' is not a count",
        ),
        (
            &error,
            "clearance",
            "1",
            "clearance: '1' given, but there is no path",
        ),
        (
            &error,
            "success",
            "True",
            "success: 'True' is not a boolean",
        ),
    ];
    for (line, column, value, needle) in cases {
        let bad = with(line, column, value);
        let e = Row::from_csv(&bad, "x.csv", 3).unwrap_err().to_string();
        assert!(e.starts_with(&format!("x.csv:3: {needle}")), "{bad}: {e}");
    }
    // An optimum of 0 has no ratio: NaN, and only NaN.
    let mut zero = row(Outcome::Planned {
        length: 1.0,
        clearance: 0.5,
    });
    zero.optimal = 0.0;
    let line = zero.to_csv();
    assert_eq!(Row::from_csv(&line, "x.csv", 3).unwrap(), zero);
    assert!(Row::from_csv(&with(&line, "ratio", "1"), "x.csv", 3).is_err());
}

#[test]
fn ratios_rounded_to_4_decimals_or_infinite_are_read() {
    let mut checked = 0;
    for optimal in [1.0, 2.414_213_56, 3.0, 23.656_854_25, 517.5] {
        for k in 0..400 {
            let length = optimal * (1.0 + 0.001_37 * f64::from(k)) + 1.3e-5 * f64::from(k);
            let r = Row {
                optimal,
                ..row(Outcome::Planned {
                    length,
                    clearance: 0.25,
                })
            };
            let line = r.to_csv();
            // As the older writer wrote it: length, ratio and clearance with {:.4}.
            let older = with(
                &with(
                    &with(&line, "length", &format!("{length:.4}")),
                    "ratio",
                    &format!("{:.4}", r.ratio()),
                ),
                "clearance",
                "0.2500",
            );
            // As a spreadsheet may: the optimum rounded too.
            let sheet = with(&older, "optimal", &format!("{optimal:.4}"));
            for text in [older, sheet] {
                let read =
                    Row::from_csv(&text, "x.csv", 3).unwrap_or_else(|e| panic!("{text}: {e}"));
                assert!((read.ratio() - r.ratio()).abs() < 1e-3, "{text}");
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 4000);
    // More than rounding explains is still refused.
    let line = row(Outcome::Planned {
        length: 12.5,
        clearance: 0.25,
    })
    .to_csv();
    for bad in ["1.2502", "1.2498", "inf", "-inf"] {
        let e = Row::from_csv(&with(&line, "ratio", bad), "x.csv", 3)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(&format!(
                "x.csv:3: ratio: '{bad}' is not length / optimal = 1.25"
            )),
            "{e}"
        );
    }
    assert!(Row::from_csv(&with(&line, "ratio", "1.2500"), "x.csv", 3).is_ok());
    // An infinite quotient, as the writer writes it (`inf`), reads back.
    let huge = Row {
        optimal: 1e-310,
        ..row(Outcome::Planned {
            length: 1e10,
            clearance: 0.25,
        })
    };
    assert!(huge.ratio().is_infinite());
    let line = huge.to_csv();
    assert_eq!(line.split(',').nth(10), Some("inf"), "{line}");
    assert_eq!(Row::from_csv(&line, "x.csv", 3).unwrap(), huge);
    // ... and only `inf`.
    let e = Row::from_csv(&with(&line, "ratio", "1e300"), "x.csv", 3)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("x.csv:3: ratio: '1e300' is not length / optimal = inf"),
        "{e}"
    );
}

#[test]
fn summaries_print_no_nan_or_infinity() {
    let empty = summary(&[]);
    assert_eq!(empty, format!("{NO_SCENARIOS}\n"));
    let failed = summary(&[
        row(Outcome::NoPlan { classes: 2 }),
        row(Outcome::Timeout { length: 3.0 }),
    ]);
    for text in [&empty, &failed] {
        for bad in ["NaN", "inf"] {
            assert!(!text.contains(bad), "{text}");
        }
    }
    assert!(failed.contains("length / octile optimum  -"), "{failed}");
    assert!(failed.contains("success      0/2"), "{failed}");
}
