#!/usr/bin/env bash
# The job array of bench.sbatch on one machine: TASKS tasks side by side, each with the
# environment Slurm would give it, then the merge.
set -euo pipefail
TASKS=${TASKS:-2}
here=$(dirname "$0")
for k in $(seq 1 "$TASKS"); do
    SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=$TASKS \
        bash "$here/bench.sbatch" > "${OUT:-bench-out}-task-$k.log" &
done
wait
bash "$here/merge.sh"
