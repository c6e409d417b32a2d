//! The scenario bench harness every front end shares: one row per MovingAI scenario planned
//! on its prepared map, rows to and from CSV, interleaved shards, and the summary. A sharded
//! run's rows, merged, give the same summary as one run (up to the times).

use std::fmt::Write;

use homospline_geom::Point;
use homospline_optim::{PlanConfig, PlanError};

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
    /// Past the time limit: planned collision-free but late (its length), or stopped at the
    /// limit (`NaN`: the plan's interrupt was raised, [`PlanConfig::interrupt`]).
    Timeout {
        /// Length, `NaN` when the plan was stopped.
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

/// The longest plan time a CSV row may hold, ms: 31 years.
pub const MAX_TIME_MS: f64 = 1e12;

/// The CSV header of [`Row::to_csv`].
pub const CSV_HEADER: &str = "file,index,line,bucket,start_x,start_y,goal_x,goal_y,optimal,length,ratio,clearance,classes,success,time_ms,outcome";

/// The columns of [`CSV_HEADER`], in order.
const COLUMNS: [&str; 16] = [
    "file",
    "index",
    "line",
    "bucket",
    "start_x",
    "start_y",
    "goal_x",
    "goal_y",
    "optimal",
    "length",
    "ratio",
    "clearance",
    "classes",
    "success",
    "time_ms",
    "outcome",
];

/// `text` as one CSV field: commas become `;`, control characters (line breaks) spaces.
fn csv_text_field(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            ',' => ';',
            c if c.is_control() => ' ',
            c => c,
        })
        .collect()
}

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

    /// One CSV line (no newline); in texts commas become `;` and line breaks (any control
    /// character) spaces, so that a file name cannot split the row.
    pub fn to_csv(&self) -> String {
        let (clearance, classes) = match self.outcome {
            Outcome::Planned { clearance, .. } => (clearance, 0),
            Outcome::NoPlan { classes } => (f64::NAN, classes),
            _ => (f64::NAN, 0),
        };
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{classes},{},{:.3},{}",
            csv_text_field(&self.file),
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
            csv_text_field(&self.what())
        )
    }

    /// Reads a line written by [`Row::to_csv`]; `source` and `line` name it in errors, as
    /// `source:line: column: problem`. Every field is checked as the writer writes it:
    /// counts, finite non-negative numbers, `NaN` where there is no value, `true` or `false`;
    /// and the columns that follow from others must agree with them (`ratio` is
    /// `length / optimal`, `success` is `true` for `ok` only, `classes` is the count in the
    /// outcome of a scenario with no collision-free class and 0 otherwise). The `ratio` is
    /// compared within the rounding of 4 decimals (see `ratio_agrees`): `inf` and `NaN`
    /// only where length / optimal is infinite or has no value.
    pub fn from_csv(text: &str, source: &str, line: usize) -> Result<Self, MapError> {
        let f = Fields::split(text, source, line)?;
        let (file, index, at_line, bucket) = f.scenario()?;
        let start = Point::new(f.amount(4)?, f.amount(5)?);
        let goal = Point::new(f.amount(6)?, f.amount(7)?);
        let optimal = f.amount(8)?;
        let outcome = f.outcome()?;
        let row = Self {
            file: file.to_owned(),
            index,
            line: at_line,
            bucket,
            start,
            goal,
            optimal,
            outcome,
            time_ms: f.time(14)?,
        };
        // The columns computed from others.
        f.check_ratio(&row)?;
        f.check_success(&row)?;
        Ok(row)
    }
}

/// The fields of one CSV line of [`Row::to_csv`], as written and trimmed, with the source
/// and line that name it in errors.
struct Fields<'a> {
    raw: Vec<&'a str>,
    f: Vec<&'a str>,
    source: &'a str,
    line: usize,
}

impl<'a> Fields<'a> {
    /// The fields of `text`, which must be one per column.
    fn split(text: &'a str, source: &'a str, line: usize) -> Result<Self, MapError> {
        let raw: Vec<&str> = text.split(',').collect();
        let fields = Self {
            f: raw.iter().map(|x| x.trim()).collect(),
            raw,
            source,
            line,
        };
        if fields.raw.len() != COLUMNS.len() {
            return Err(fields.at(format!(
                "expected {} fields ({CSV_HEADER}), got {}",
                COLUMNS.len(),
                fields.raw.len()
            )));
        }
        Ok(fields)
    }

    /// `problem` at this line.
    fn at(&self, problem: String) -> MapError {
        MapError::Format {
            source_name: self.source.to_owned(),
            line: Some(self.line),
            problem,
        }
    }

    /// `problem` in column `i`.
    fn err(&self, i: usize, problem: String) -> MapError {
        self.at(format!("{}: {problem}", COLUMNS[i]))
    }

    /// Column `i` as a number.
    fn number(&self, i: usize) -> Result<f64, MapError> {
        let f = &self.f;
        f[i].parse::<f64>()
            .map_err(|_| self.err(i, format!("'{}' is not a number", f[i])))
    }

    /// Column `i` as a finite number >= 0.
    fn amount(&self, i: usize) -> Result<f64, MapError> {
        let v = self.number(i)?;
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(
                i,
                format!("'{}' is not a finite non-negative number", self.f[i]),
            ))
        }
    }

    /// Column `i` is a plan's time in ms: an amount no run reaches past [`MAX_TIME_MS`] (a
    /// time of 1e308 was taken, and the summary printed its mean in 309 digits).
    fn time(&self, i: usize) -> Result<f64, MapError> {
        let v = self.amount(i)?;
        if v <= MAX_TIME_MS {
            Ok(v)
        } else {
            Err(self.err(
                i,
                format!(
                    "'{}' ms is beyond any run (at most 1e12 ms, 31 years)",
                    self.f[i]
                ),
            ))
        }
    }

    /// Column `i` holds no value: `NaN`, as the writer writes it.
    fn nothing(&self, i: usize, why: &str) -> Result<(), MapError> {
        if self.number(i)?.is_nan() {
            Ok(())
        } else {
            Err(self.err(
                i,
                format!("'{}' given, but {why} (the writer writes NaN)", self.f[i]),
            ))
        }
    }

    /// Column `i` as a count.
    fn count(&self, i: usize) -> Result<usize, MapError> {
        let f = &self.f;
        f[i].parse::<usize>()
            .map_err(|_| self.err(i, format!("'{}' is not a count", f[i])))
    }

    /// The scenario's file (as written), index, line and bucket.
    fn scenario(&self) -> Result<(&'a str, usize, usize, u32), MapError> {
        let f = &self.f;
        let file = self.raw[0];
        if f[0].is_empty() {
            return Err(self.err(0, "empty: a scenario file is needed".into()));
        }
        let index = self.count(1)?;
        let at_line = self.count(2)?;
        if at_line <= index {
            return Err(self.err(
                2,
                format!(
                    "{at_line} cannot hold scenario {index} (1-based lines, one scenario a line: the line is more than the index)"
                ),
            ));
        }
        let bucket = f[3]
            .parse::<u32>()
            .map_err(|_| self.err(3, format!("'{}' is not a bucket number", f[3])))?;
        Ok((file, index, at_line, bucket))
    }

    /// The `classes` column is 0, as for every outcome but [`Outcome::NoPlan`].
    fn zero_classes(&self) -> Result<(), MapError> {
        let what = self.f[15];
        match self.count(12)? {
            0 => Ok(()),
            n => Err(self.err(
                12,
                format!(
                    "{n} given, but the outcome is '{what}' (the writer writes 0 unless no class is collision-free)"
                ),
            )),
        }
    }

    /// The outcome, from its text with the length, clearance and classes columns it
    /// implies.
    fn outcome(&self) -> Result<Outcome, MapError> {
        let f = &self.f;
        let what = f[15];
        let no_path = "there is no path";
        let outcome = if what == "ok" {
            let length = self.amount(9)?;
            let clearance = self.number(11)?;
            if clearance.is_nan() || clearance <= 0.0 {
                return Err(self.err(
                    11,
                    format!(
                        "'{}' is not a positive clearance (an `ok` plan is collision-free)",
                        f[11]
                    ),
                ));
            }
            self.zero_classes()?;
            Outcome::Planned { length, clearance }
        } else if what == "timeout" {
            // NaN: stopped at the limit, no path.
            let length = if self.number(9)?.is_nan() {
                f64::NAN
            } else {
                self.amount(9)?
            };
            self.nothing(11, "the clearance is written for `ok` only")?;
            self.zero_classes()?;
            Outcome::Timeout { length }
        } else if let Some(n) = what.strip_prefix("no collision-free class among ") {
            let classes = n
                .parse::<usize>()
                .map_err(|_| self.err(15, format!("'{what}': '{n}' is not a count of classes")))?;
            self.nothing(9, no_path)?;
            self.nothing(11, no_path)?;
            if self.count(12)? != classes {
                return Err(self.err(
                    12,
                    format!("'{}' given, but the outcome says {classes}", f[12]),
                ));
            }
            Outcome::NoPlan { classes }
        } else if let Some(e) = what.strip_prefix("error: ") {
            self.nothing(9, no_path)?;
            self.nothing(11, no_path)?;
            self.zero_classes()?;
            Outcome::Error(e.to_owned())
        } else {
            return Err(self.err(
                15,
                format!(
                    "'{what}' is not one this program writes (ok, timeout, no collision-free class among N, error: ...)"
                ),
            ));
        };
        Ok(outcome)
    }

    /// The `ratio` column agrees with `row`'s length / optimal ([`ratio_agrees`]); `NaN`
    /// where that has no value.
    fn check_ratio(&self, row: &Row) -> Result<(), MapError> {
        let f = &self.f;
        let (given, ratio) = (self.number(10)?, row.ratio());
        if ratio.is_nan() {
            if !given.is_nan() {
                return Err(self.err(
                    10,
                    format!(
                        "'{}' given, but there is no length / optimal (no path, or optimal 0: the writer writes NaN)",
                        f[10]
                    ),
                ));
            }
        } else if !ratio_agrees(given, ratio, row.optimal) {
            return Err(self.err(10, format!("'{}' is not length / optimal = {ratio}", f[10])));
        }
        Ok(())
    }

    /// The `success` column is a boolean, `true` for `ok` only.
    fn check_success(&self, row: &Row) -> Result<(), MapError> {
        let f = &self.f;
        let success = match f[13] {
            "true" => true,
            "false" => false,
            other => {
                return Err(self.err(13, format!("'{other}' is not a boolean (true or false)")));
            }
        };
        if success != row.success() {
            return Err(self.err(
                13,
                format!(
                    "'{}' given, but the outcome is '{}' (success is true for `ok` only)",
                    f[13], f[15]
                ),
            ));
        }
        Ok(())
    }
}

/// Whether the `ratio` column `given` agrees with `ratio`, the row's length over its
/// optimum `optimal`: infinite both (the writer writes `inf` when the quotient overflows),
/// or within what rounding each of the length, the optimum and the ratio to 4 decimals
/// explains (an older writer wrote `{:.4}`; spreadsheets round too), plus 1e-9 relative.
fn ratio_agrees(given: f64, ratio: f64, optimal: f64) -> bool {
    if ratio.is_infinite() || given.is_infinite() {
        return given == ratio;
    }
    // Half a unit in the 4th decimal of the ratio, and that of the length and the optimum
    // carried through length / optimal.
    const HALF: f64 = 5e-5;
    let tolerance = HALF + HALF * (1.0 + ratio.abs()) / optimal + 1e-9 * ratio.abs();
    (given - ratio).abs() <= tolerance
}

/// Plans scenario `index` of `file` on its prepared map; a plan still running at
/// `time_limit` ms is stopped there (its interrupt raised by a watchdog thread: it ends
/// within a growth round) and counts as a timeout, as does a plan that ended past the limit.
pub fn run(
    prepared: &PreparedMap,
    file: &str,
    index: usize,
    s: &Scenario,
    cfg: &PlanConfig,
    time_limit: Option<f64>,
) -> Row {
    let t = std::time::Instant::now();
    let (outcome, ms) = match time_limit {
        None => {
            let outcome = prepared.plan(s.start, s.goal, cfg);
            (outcome, t.elapsed().as_secs_f64() * 1e3)
        }
        Some(limit) => {
            let cfg = PlanConfig {
                interrupt: Default::default(),
                ..cfg.clone()
            };
            // A limit past what a `Duration` holds is no limit (and no panic).
            let after = std::time::Duration::try_from_secs_f64(limit.max(0.0) / 1e3)
                .unwrap_or(std::time::Duration::MAX);
            let deadline = cfg.interrupt.raise_after(after);
            let outcome = prepared.plan(s.start, s.goal, &cfg);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            drop(deadline);
            (outcome, ms)
        }
    };
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
        Err(MapError::Plan(PlanError::Interrupted)) => Outcome::Timeout { length: f64::NAN },
        Err(e) => Outcome::Error(e.to_string()),
    };
    row(file, index, s, outcome, ms)
}

/// The row of scenario `index` of `file` that was not planned because its map cannot be
/// (`why`: no point of it keeps the robot's radius): an error row, in 0 ms.
pub fn unplanned(file: &str, index: usize, s: &Scenario, why: &str) -> Row {
    row(file, index, s, Outcome::Error(why.to_owned()), 0.0)
}

/// The row of scenario `index` of `file`: `outcome` in `ms`.
fn row(file: &str, index: usize, s: &Scenario, outcome: Outcome, ms: f64) -> Row {
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

/// What [`summary`] says of no rows.
pub const NO_SCENARIOS: &str = "no scenarios in this shard or these CSVs: nothing to summarise (a shard gets none when there are more shards than scenarios picked; its CSV is the header alone)";

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
///
/// No rows (a shard of more shards than scenarios, or CSVs with a header only) give one
/// line saying so. No figure is printed as NaN or infinite: a figure with nothing to
/// measure is `-`.
pub fn summary(rows: &[Row]) -> String {
    if rows.is_empty() {
        return format!("{NO_SCENARIOS}\n");
    }
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
    if ratios.is_empty() {
        let _ = writeln!(
            s,
            "length / octile optimum  - (no successful plan of a scenario with an optimum above 0)"
        );
    } else {
        let _ = writeln!(
            s,
            "length / octile optimum  median {:.4}, min {:.4}, max {:.4} (a smooth any-angle path can be shorter than the octile one)",
            median(&ratios),
            ratios.iter().copied().fold(f64::INFINITY, f64::min),
            ratios.iter().copied().fold(0.0, f64::max)
        );
    }
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
            let q = median(&q);
            let _ = writeln!(
                s,
                "{:>3}-{:<4}  {:>5}-{:<8} {:>5}  {:>7}  {:>9.1}  {:>12}",
                b0,
                b1,
                4 * b0,
                4 * (b1 + 1),
                in_band.len(),
                in_band.iter().filter(|r| r.success()).count(),
                median(&t),
                if q.is_finite() {
                    format!("{q:.4}")
                } else {
                    "-".into()
                }
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
mod tests;
