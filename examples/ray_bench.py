"""A MovingAI benchmark sweep as Ray tasks, through the homospline Python package.

Each task plans one interleaved shard of every scenario picked from the given .scen files
(or directories of them); the driver merges the shards' rows into the summary that
`homospline bench-scen` gives for the whole sweep in one process (times aside).

    python examples/ray_bench.py fixtures/maps/movingai/maze-32-32-2-random-1.scen \\
        fixtures/maps/movingai/room-32-32-4-random-1.scen --sample 6 --shards 2 --csv merged.csv

On one machine it starts a local Ray (`--num-cpus`); on a cluster, start Ray there (for
example `ray start --head` on the first Slurm node and `ray start --address=...` on the
others) and pass `--address auto`.
"""

import argparse
import sys

import homospline
import ray


@ray.remote
def plan_shard(files, sample, k, n, classes):
    """One shard's rows, as CSV text."""
    return homospline.bench_scen(files, sample=sample, shard=(k, n), classes=classes)


def merged_csv(csvs):
    """The shards' rows under one header, sorted by file and scenario."""
    header = csvs[0].splitlines()[0]
    rows = [line for text in csvs for line in text.splitlines()[1:] if line.strip()]
    rows.sort(key=lambda r: (r.split(",")[0], int(r.split(",")[1])))
    return "\n".join([header] + rows) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+", help=".scen files or directories of them")
    ap.add_argument("--sample", type=int, default=None, help="scenarios per file, over every bucket")
    ap.add_argument("--shards", type=int, default=2, help="Ray tasks")
    ap.add_argument("--classes", type=int, default=5)
    ap.add_argument("--num-cpus", type=int, default=2, help="for a local Ray")
    ap.add_argument("--address", default=None, help="an existing Ray cluster ('auto')")
    ap.add_argument("--csv", default=None, help="write the merged rows here")
    args = ap.parse_args(argv)
    if args.address:
        ray.init(address=args.address)
    else:
        ray.init(num_cpus=args.num_cpus, include_dashboard=False)
    try:
        tasks = [
            plan_shard.remote(args.files, args.sample, k, args.shards, args.classes)
            for k in range(1, args.shards + 1)
        ]
        csvs = ray.get(tasks)
    finally:
        ray.shutdown()
    print(f"{sum(len(c.splitlines()) - 1 for c in csvs)} scenarios from {args.shards} Ray tasks")
    print(homospline.bench_summary(csvs), end="")
    if args.csv:
        with open(args.csv, "w") as f:
            f.write(merged_csv(csvs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
