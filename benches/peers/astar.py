"""Our map plans against a peer in the same run: 8-connected A* (pyastar2d, C++) on a
nav2-style inflation costmap, on the scenarios `homospline bench-scen` planned.

Usage:
    homospline bench-scen MAP.scen... --sample 20 --csv ours.csv
    python3 benches/peers/astar.py ours.csv [--inflation 3] [--repeat 3]

Needs `pip install pyastar2d numpy`. For each scenario of the CSV (its map beside its
.scen file, MovingAI coordinates), the peer's costmap is built once per map (excluded from
its times, as our prepared map is from ours): occupied cells are impassable, free cells cost
1 plus a decaying inflation cost within `--inflation` cells of an obstacle (nav2's
exponential decay, scaled to at most 50), and A* runs from the start cell to the goal cell
with diagonal moves, best of `--repeat` timings. Printed per map and over all scenarios:
the median in-process time per plan, ours (the CSV's `time_ms`, our whole plan: graph
query, 5 classes, optimisation, certificates) and the peer's, their ratio, and the median
path length over the octile optimum (the peer's path is the polyline through its cell
centres; A* on an inflated costmap trades length for clearance, and cuts corners at cell
level) and each path's least clearance (ours certified; the peer's sampled along its
polyline every tenth of a step).
"""
import argparse
import csv
import math
import os
import statistics
import sys
import time

import numpy as np
import pyastar2d


def read_map(path):
    lines = open(path).read().splitlines()
    h = int(lines[1].split()[1])
    w = int(lines[2].split()[1])
    rows = lines[4 : 4 + h]
    return np.array([[c not in ".G" for c in r[:w]] for r in rows], dtype=bool)


def costmap(occ, inflation):
    """1 on free cells, plus nav2's decay within `inflation` cells; inf on occupied."""
    h, w = occ.shape
    dist = np.full(occ.shape, np.inf)
    r = int(math.ceil(inflation))
    padded = np.pad(occ, r, constant_values=True)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            d = math.hypot(dx, dy)
            if d > inflation:
                continue
            shifted = padded[r + dy : r + dy + h, r + dx : r + dx + w]
            dist = np.where(shifted, np.minimum(dist, d), dist)
    cost = np.ones(occ.shape, dtype=np.float32)
    near = np.isfinite(dist) & (dist > 0)
    cost[near] += (50.0 * np.exp(-3.0 * (dist[near] - 1.0) / max(inflation, 1.0))).astype(
        np.float32
    )
    cost[occ] = np.inf
    return cost, dist


def point_clearance(occ, x, y, reach=4):
    """Distance from (x, y) (cell units, x across) to the nearest occupied square or the edge."""
    h, w = occ.shape
    best = min(x, y, w - x, h - y)
    i0, j0 = int(x), int(y)
    for j in range(max(j0 - reach, 0), min(j0 + reach + 1, h)):
        for i in range(max(i0 - reach, 0), min(i0 + reach + 1, w)):
            if occ[j, i]:
                dx = max(i - x, 0.0, x - i - 1)
                dy = max(j - y, 0.0, y - j - 1)
                best = min(best, math.hypot(dx, dy))
    return best


def path_clearance(occ, path):
    """The least clearance along the polyline through the path's cell centres, sampled every
    tenth of a step (within 0.05 cells of the least)."""
    pts = path[:, ::-1].astype(float) + 0.5
    best = math.inf
    for a, b in zip(pts[:-1], pts[1:]):
        for k in range(11):
            p = a + (b - a) * (k / 10)
            best = min(best, point_clearance(occ, p[0], p[1]))
    return best if math.isfinite(best) else point_clearance(occ, *pts[0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--inflation", type=float, default=3.0)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    maps = {}
    per_map = {}
    for r in rows:
        if r["success"] != "true":
            continue
        scen = r["file"]
        name = open(scen).read().splitlines()[1].split("\t")[1]
        map_path = os.path.join(os.path.dirname(scen), os.path.basename(name))
        if map_path not in maps:
            occ = read_map(map_path)
            maps[map_path] = (occ,) + costmap(occ, a.inflation)
        occ, cost, dist = maps[map_path]
        s = (int(float(r["start_y"])), int(float(r["start_x"])))
        g = (int(float(r["goal_y"])), int(float(r["goal_x"])))
        best = math.inf
        path = None
        for _ in range(a.repeat):
            t0 = time.perf_counter()
            path = pyastar2d.astar_path(cost, s, g, allow_diagonal=True)
            best = min(best, (time.perf_counter() - t0) * 1e3)
        if path is None:
            continue
        length = float(np.sum(np.hypot(*np.diff(path, axis=0).T))) if len(path) > 1 else 0.0
        clear = path_clearance(occ, path)
        m = per_map.setdefault(os.path.basename(map_path), [])
        m.append(
            (
                float(r["time_ms"]),
                best,
                float(r["ratio"]),
                length / float(r["optimal"]) if float(r["optimal"]) > 0 else 1.0,
                float(r["clearance"]),
                clear,
            )
        )
    print(
        f"{'map':<22} {'plans':>5} {'ours ms':>8} {'A* ms':>7} {'ratio':>6} "
        f"{'ours len':>8} {'A* len':>7} {'ours clr':>8} {'A* clr':>7}"
    )
    everything = []
    for name, m in sorted(per_map.items()):
        everything += m
        col = lambda i: statistics.median(x[i] for x in m)
        print(
            f"{name:<22} {len(m):>5} {col(0):>8.2f} {col(1):>7.2f} {col(0) / col(1):>6.1f} "
            f"{col(2):>8.3f} {col(3):>7.3f} {col(4):>8.3f} {col(5):>7.3f}"
        )
    if not everything:
        sys.exit("no planned scenario in the CSV")
    col = lambda i: statistics.median(x[i] for x in everything)
    print(
        f"{'all':<22} {len(everything):>5} {col(0):>8.2f} {col(1):>7.2f} "
        f"{col(0) / col(1):>6.1f} {col(2):>8.3f} {col(3):>7.3f} {col(4):>8.3f} {col(5):>7.3f}"
    )


if __name__ == "__main__":
    main()
