#!/usr/bin/env bash
# Merges the shards written by bench.sbatch (or local.sh) into one summary and one CSV.
set -euo pipefail
OUT=${OUT:-bench-out}
HOMOSPLINE=${HOMOSPLINE:-homospline}
"$HOMOSPLINE" bench-merge "$OUT"/shard-*.csv --out "$OUT/all.csv"
