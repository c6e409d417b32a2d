//! The scenario bench harness every front end shares: one row per MovingAI scenario planned
//! on its prepared map, rows to and from CSV, interleaved shards, and the summary. A sharded
//! run's rows, merged, give the same summary as one run (up to the times).

use std::fmt::Write;

use homospline_geom::Point;
use homospline_optim::PlanConfig;

use crate::movingai::Scenario;
use crate::{MapError, PreparedMap};

/// What planning one scenario gave.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// A collision-free plan: length and clearance of the chosen class.
    Planned {
        /// Length.
        length: f64,
        /// Minimum clearance.
        clearance: f64,
    },
    /// Planned collision-free, but past the time limit.
    Timeout {
        /// Length.
        length: f64,
    },
    /// Classes were optimised; none is collision-free.
    NoPlan {
        /// How many.
        classes: usize,
    },
    /// The planner refused the query.
    Error(String),
}

/// One scenario's result.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The `.scen` file as given.
    pub file: String,
    /// Index of the scenario in its file (0-based).
    pub index: usize,
    /// Line of the file (1-based).
    pub line: usize,
    /// Bucket.
    pub bucket: u32,
    /// Start.
    pub start: Point,
    /// Goal.
    pub goal: Point,
    /// Octile optimum of the file.
    pub optimal: f64,
    /// What came out.
    pub outcome: Outcome,
    /// Planning time, milliseconds (the only field that varies between runs).
    pub time_ms: f64,
}

/// The CSV header of [`Row::to_csv`].
pub const CSV_HEADER: &str = "file,index,line,bucket,start_x,start_y,goal_x,goal_y,optimal,length,ratio,clearance,classes,success,time_ms,outcome";

impl Row {
    /// A collision-free plan within the time limit.
    pub fn success(&self) -> bool {
        matches!(self.outcome, Outcome::Planned { .. })
    }

    /// Length of the chosen path (NaN without one).
    pub fn length(&self) -> f64 {
        match self.outcome {
            Outcome::Planned { length, .. } | Outcome::Timeout { length } => length,
            _ => f64::NAN,
        }
    }

    /// Length over the octile optimum (NaN without a path or an optimum).
    pub fn ratio(&self) -> f64 {
        if self.optimal > 0.0 {
            self.length() / self.optimal
        } else {
            f64::NAN
        }
    }

    fn what(&self) -> String {
        match &self.outcome {
            Outcome::Planned { .. } => "ok".into(),
            Outcome::Timeout { .. } => "timeout".into(),
            Outcome::NoPlan { classes } => format!("no collision-free class among {classes}"),
            Outcome::Error(e) => format!("error: {e}"),
        }
    }

    /// One CSV line (no newline); commas in texts become `;`.
    pub fn to_csv(&self) -> String {
        let (clearance, classes) = match self.outcome {
            Outcome::Planned { clearance, .. } => (clearance, 0),
            Outcome::NoPlan { classes } => (f64::NAN, classes),
            _ => (f64::NAN, 0),
        };
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{classes},{},{:.3},{}",
            self.file.replace(',', ";"),
            self.index,
            self.line,
            self.bucket,
            self.start.x,
            self.start.y,
            self.goal.x,
            self.goal.y,
            self.optimal,
            self.length(),
            self.ratio(),
            clearance,
            self.success(),
            self.time_ms,
            self.what().replace(',', ";")
        )
    }

    /// Reads a line written by [`Row::to_csv`]; `source` and `line` name it in errors.
    pub fn from_csv(text: &str, source: &str, line: usize) -> Result<Self, MapError> {
        let err = |problem: String| MapError::Format {
            source_name: source.to_owned(),
            line: Some(line),
            problem,
        };
        let f: Vec<&str> = text.split(',').collect();
        if f.len() != 16 {
            return Err(err(format!(
                "expected 16 fields ({CSV_HEADER}), got {}",
                f.len()
            )));
        }
        let num = |i: usize, what: &str| -> Result<f64, MapError> {
            f[i].trim()
                .parse::<f64>()
                .map_err(|_| err(format!("{what}: '{}' is not a number", f[i])))
        };
        let int = |i: usize, what: &str| -> Result<usize, MapError> {
            f[i].trim()
                .parse::<usize>()
                .map_err(|_| err(format!("{what}: '{}' is not a count", f[i])))
        };
        let what = f[15].trim();
        let outcome = if what == "ok" {
            Outcome::Planned {
                length: num(9, "length")?,
                clearance: num(11, "clearance")?,
            }
        } else if what == "timeout" {
            Outcome::Timeout {
                length: num(9, "length")?,
            }
        } else if what.starts_with("no collision-free class") {
            Outcome::NoPlan {
                classes: int(12, "classes")?,
            }
        } else if let Some(e) = what.strip_prefix("error: ") {
            Outcome::Error(e.to_owned())
        } else {
            return Err(err(format!(
                "outcome: '{what}' is not one this program writes"
            )));
        };
        Ok(Self {
            file: f[0].to_owned(),
            index: int(1, "index")?,
            line: int(2, "line")?,
            bucket: f[3]
                .trim()
                .parse::<u32>()
                .map_err(|_| err(format!("bucket: '{}' is not a bucket number", f[3])))?,
            start: Point::new(num(4, "start_x")?, num(5, "start_y")?),
            goal: Point::new(num(6, "goal_x")?, num(7, "goal_y")?),
            optimal: num(8, "optimal")?,
            outcome,
            time_ms: num(14, "time_ms")?,
        })
    }
}

/// Plans scenario `index` of `file` on its prepared map; a plan that took longer than
/// `time_limit` ms counts as a timeout (it is not interrupted).
pub fn run(
    prepared: &PreparedMap,
    file: &str,
    index: usize,
    s: &Scenario,
    cfg: &PlanConfig,
    time_limit: Option<f64>,
) -> Row {
    let t = std::time::Instant::now();
    let outcome = prepared.plan(s.start, s.goal, cfg);
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let outcome = match outcome {
        Ok(p) => match p.best {
            Some(b) => {
                let c = &p.classes[b - 1];
                if time_limit.is_some_and(|lim| ms > lim) {
                    Outcome::Timeout { length: c.length }
                } else {
                    Outcome::Planned {
                        length: c.length,
                        clearance: c.min_clearance,
                    }
                }
            }
            None => Outcome::NoPlan {
                classes: p.classes.len(),
            },
        },
        Err(e) => Outcome::Error(e.to_string()),
    };
    Row {
        file: file.to_owned(),
        index,
        line: s.line,
        bucket: s.bucket,
        start: s.start,
        goal: s.goal,
        optimal: s.optimal_length,
        outcome,
        time_ms: ms,
    }
}

/// `n` indices spread evenly over `0..total`, the first and the last included (a `.scen` is
/// sorted by length: this samples every bucket).
pub fn sample_indices(total: usize, n: usize) -> Vec<usize> {
    if n >= total {
        return (0..total).collect();
    }
    if n == 1 {
        return vec![total - 1];
    }
    let mut v: Vec<usize> = (0..n)
        .map(|k| ((k as f64) * (total - 1) as f64 / (n - 1) as f64).round() as usize)
        .collect();
    v.dedup();
    v
}

/// Slice `k` (1-based) of `n` interleaved slices: the positions `i` with `i % n == k - 1`.
/// Interleaving spreads every length over every shard, so shards take about equal time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which slice, `1..=n`.
    pub k: usize,
    /// How many.
    pub n: usize,
}

impl Shard {
    /// The whole.
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// Parses `K/N` with `1 <= K <= N`.
    pub fn parse(text: &str) -> Result<Self, String> {
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| format!("'{text}': expected K/N"))?;
        let (k, n) = (
            k.trim()
                .parse::<usize>()
                .map_err(|_| format!("'{text}': K is not a number"))?,
            n.trim()
                .parse::<usize>()
                .map_err(|_| format!("'{text}': N is not a number"))?,
        );
        if n == 0 || k == 0 || k > n {
            return Err(format!("'{text}': need 1 <= K <= N"));
        }
        Ok(Self { k, n })
    }

    /// From a Slurm job array's environment (`SLURM_ARRAY_TASK_ID`, `SLURM_ARRAY_TASK_MIN`,
    /// `SLURM_ARRAY_TASK_COUNT`, as given by `get`): task `id` is slice `id - min + 1` of
    /// `count`. `None` outside a job array.
    pub fn from_slurm(get: impl Fn(&str) -> Option<String>) -> Option<Result<Self, String>> {
        let id = get("SLURM_ARRAY_TASK_ID")?;
        let count = get("SLURM_ARRAY_TASK_COUNT")?;
        let min = get("SLURM_ARRAY_TASK_MIN").unwrap_or_else(|| "0".into());
        let parse = |what: &str, v: &str| {
            v.trim()
                .parse::<usize>()
                .map_err(|_| format!("{what}={v} is not a number"))
        };
        Some((|| {
            let (id, count, min) = (
                parse("SLURM_ARRAY_TASK_ID", &id)?,
                parse("SLURM_ARRAY_TASK_COUNT", &count)?,
                parse("SLURM_ARRAY_TASK_MIN", &min)?,
            );
            if id < min || id - min >= count {
                return Err(format!(
                    "SLURM_ARRAY_TASK_ID={id} is not within {min}..{} (SLURM_ARRAY_TASK_MIN, SLURM_ARRAY_TASK_COUNT)",
                    min + count
                ));
            }
            Ok(Self {
                k: id - min + 1,
                n: count,
            })
        })())
    }

    /// Whether position `i` of the whole list belongs to this slice.
    pub fn takes(&self, i: usize) -> bool {
        i % self.n == self.k - 1
    }
}

fn median(v: &[f64]) -> f64 {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

/// The summary of some rows (any order: they are sorted by file and index): success rate,
/// timeouts, times, length over the optimum, bands of buckets, and every scenario not
/// planned with its cause.
pub fn summary(rows: &[Row]) -> String {
    let mut rows: Vec<&Row> = rows.iter().collect();
    rows.sort_by(|a, b| a.file.cmp(&b.file).then(a.index.cmp(&b.index)));
    let n = rows.len();
    let ok = rows.iter().filter(|r| r.success()).count();
    let timeouts = rows
        .iter()
        .filter(|r| matches!(r.outcome, Outcome::Timeout { .. }))
        .count();
    let times: Vec<f64> = rows.iter().map(|r| r.time_ms).collect();
    let ratios: Vec<f64> = rows
        .iter()
        .filter(|r| r.success())
        .map(|r| r.ratio())
        .filter(|r| r.is_finite())
        .collect();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "success      {ok}/{n} ({:.1} %), timeouts {timeouts}",
        100.0 * ok as f64 / n.max(1) as f64
    );
    let _ = writeln!(
        s,
        "time / plan  mean {:.2} ms, median {:.2} ms, max {:.2} ms",
        times.iter().sum::<f64>() / n.max(1) as f64,
        median(&times),
        times.iter().copied().fold(0.0, f64::max)
    );
    let _ = writeln!(
        s,
        "length / octile optimum  median {:.4}, min {:.4}, max {:.4} (a smooth any-angle path can be shorter than the octile one)",
        median(&ratios),
        ratios.iter().copied().fold(f64::INFINITY, f64::min),
        ratios.iter().copied().fold(0.0, f64::max)
    );
    // Per bucket, in at most ten bands of buckets.
    // In u64: buckets span all of u32.
    let (lo, hi) = rows.iter().fold((u64::MAX, 0u64), |(l, h), r| {
        (l.min(u64::from(r.bucket)), h.max(u64::from(r.bucket)))
    });
    if lo <= hi {
        let bands = (hi - lo + 1).min(10);
        let width = (hi - lo + 1).div_ceil(bands);
        let _ = writeln!(
            s,
            "buckets   optimal length  plans  success  median ms  median ratio"
        );
        for b in 0..bands {
            let (b0, b1) = (lo + b * width, (lo + (b + 1) * width - 1).min(hi));
            let in_band: Vec<&&Row> = rows
                .iter()
                .filter(|r| (b0..=b1).contains(&u64::from(r.bucket)))
                .collect();
            if in_band.is_empty() {
                continue;
            }
            let t: Vec<f64> = in_band.iter().map(|r| r.time_ms).collect();
            let q: Vec<f64> = in_band
                .iter()
                .map(|r| if r.success() { r.ratio() } else { f64::NAN })
                .collect();
            let _ = writeln!(
                s,
                "{:>3}-{:<4}  {:>5}-{:<8} {:>5}  {:>7}  {:>9.1}  {:>12.4}",
                b0,
                b1,
                4 * b0,
                4 * (b1 + 1),
                in_band.len(),
                in_band.iter().filter(|r| r.success()).count(),
                median(&t),
                median(&q)
            );
        }
    }
    let failures: Vec<&&Row> = rows.iter().filter(|r| !r.success()).collect();
    if !failures.is_empty() {
        let _ = writeln!(s, "not planned:");
        for r in failures {
            let what = match &r.outcome {
                Outcome::Timeout { .. } => format!("timeout ({:.0} ms)", r.time_ms),
                _ => r.what(),
            };
            let _ = writeln!(
                s,
                "  {} line {} (bucket {}, optimal {:.1}): {what}",
                r.file, r.line, r.bucket, r.optimal
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
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
            let r = Row {
                file: "m.map.scen".into(),
                index: 7,
                line: 9,
                bucket: 2,
                start: Point::new(1.5, 2.5),
                goal: Point::new(3.5, 4.5),
                optimal: 10.0,
                outcome,
                time_ms: 1.25,
            };
            assert_eq!(Row::from_csv(&r.to_csv(), "x.csv", 2).unwrap(), r);
        }
        assert!(
            Row::from_csv("a,b", "x.csv", 3)
                .unwrap_err()
                .to_string()
                .contains("x.csv:3")
        );
    }
}
