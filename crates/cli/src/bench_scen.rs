//! `homospline bench-scen` and `bench-merge`: MovingAI scenario sweeps, sharded over a
//! cluster and merged.

use std::path::{Path, PathBuf};

use homospline_front::bench::{BenchJob, csv_text, input_files, rows_of_named, run_files};
use homospline_maps::sweep::{self, Shard};

use crate::args::BenchArgs;
use crate::input::parse_weights;
use crate::out::{bad, check_outputs, write};

/// This run's slice: `--shard K/N`, else a Slurm job array's, else the whole.
pub fn shard_of(opt: Option<&str>) -> anyhow::Result<Shard> {
    match opt {
        Some(t) => Shard::parse(t).map_err(|e| bad(format!("--shard {e}"))),
        None => match Shard::from_slurm(|k| std::env::var(k).ok()) {
            Some(r) => r.map_err(|e| bad(format!("Slurm job array: {e}"))),
            None => Ok(Shard::ALL),
        },
    }
}

/// `bench-scen`: plans this run's shard of the scenarios and prints the summary.
pub fn bench_scen(a: BenchArgs) -> anyhow::Result<u8> {
    let shard = shard_of(a.shard.as_deref())?;
    let job = BenchJob {
        files: a.scen.clone(),
        sample: a.sample,
        limit: a.limit,
        shard,
        classes: a.classes,
        time_limit: a.time_limit,
        weights: parse_weights(&a.weights)?,
        robot_radius: a.robot_radius.unwrap_or(0.0),
    };
    // The `.scen` files and the maps they name: the CSV overwrites none of them.
    let inputs = input_files(&job).map_err(bad)?;
    check_outputs(
        &inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>(),
        &[("--csv", "CSV", a.csv.as_deref())],
    )?;
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} scenarios {elapsed_precise} eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let (rows, info) = run_files(&job, |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .map_err(|e| bad(e.to_string()))?;
    bar.finish_and_clear();
    say!(
        "{}: {} of {} scenarios picked{}{}{}, on {}; maps prepared once in {:.1} ms",
        info.files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
        rows.len(),
        info.picked,
        if a.limit.is_some() || a.sample.is_some() {
            format!(" from {}", info.total)
        } else {
            String::new()
        },
        match (a.limit, a.sample) {
            (Some(_), _) => " (the first of each file: the shortest paths only)",
            (_, Some(_)) => " (sampled evenly over every bucket)",
            _ => "",
        },
        if shard.n > 1 {
            format!(", shard {}/{}", shard.k, shard.n)
        } else {
            String::new()
        },
        info.maps.join(", "),
        info.prepare_ms
    );
    say_raw!("{}", sweep::summary(&rows));
    if let Some(p) = &a.csv {
        write(p, "CSV", csv_text(&rows).as_bytes())?;
    }
    Ok(0)
}

/// `bench-merge`: the shards' CSVs as one run's summary and rows.
pub fn bench_merge(csvs: &[PathBuf], out: Option<&Path>) -> anyhow::Result<u8> {
    let inputs: Vec<&Path> = csvs.iter().map(PathBuf::as_path).collect();
    check_outputs(&inputs, &[("--out", "CSV", out)])?;
    let mut texts = Vec::new();
    for p in csvs {
        let name = p.display().to_string();
        let text = homospline_front::read_regular_string(p)
            .map_err(|e| bad(format!("{name}: cannot read: {e}")))?;
        texts.push((name, text));
    }
    let rows = rows_of_named(&texts).map_err(bad)?;
    say!("{} scenarios from {} CSV files", rows.len(), csvs.len());
    say_raw!("{}", sweep::summary(&rows));
    if let Some(p) = out {
        write(p, "CSV", csv_text(&rows).as_bytes())?;
    }
    Ok(0)
}
