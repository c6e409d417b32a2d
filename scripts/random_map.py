"""A seeded random MovingAI map and a scenario file of pairs that keep a robot radius.

Usage: python3 scripts/random_map.py OUT_DIR [--size 256] [--density 0.10] [--radius 1]
       [--pairs 40] [--seed 10]

Writes OUT_DIR/random<size>-<density%>.map and its .scen: one-cell obstacles drawn
independently (MovingAI's random maps), start and goal cell centres that keep more than the
radius from every occupied cell and the edge, sorted by straight-line distance. The
scenario file's optimum column is 1.1 times that distance (not an octile optimum: the
scenarios test whether a disc gets a route, not lengths). Used for decision 0022's
diagonal-passage figures (`cargo xtask map-clearance --robot-radius 1 OUT_DIR/*.scen`).
"""
import argparse
import math
import os
import random

ap = argparse.ArgumentParser()
ap.add_argument("out")
ap.add_argument("--size", type=int, default=256)
ap.add_argument("--density", type=float, default=0.10)
ap.add_argument("--radius", type=float, default=1.0)
ap.add_argument("--pairs", type=int, default=40)
ap.add_argument("--seed", type=int, default=10)
a = ap.parse_args()
random.seed(a.seed)
n = a.size
occ = [[random.random() < a.density for _ in range(n)] for _ in range(n)]
name = f"random{n}-{round(a.density * 100)}"


def clearance(x, y):
    best = min(x, y, n - x, n - y)
    reach = int(a.radius) + 3
    for j in range(int(y) - reach, int(y) + reach + 1):
        for i in range(int(x) - reach, int(x) + reach + 1):
            if 0 <= i < n and 0 <= j < n and occ[j][i]:
                dx = max(i - x, 0, x - i - 1)
                dy = max(j - y, 0, y - j - 1)
                best = min(best, math.hypot(dx, dy))
    return best


points = []
while len(points) < 2 * a.pairs:
    i, j = random.randrange(n), random.randrange(n)
    if not occ[j][i] and clearance(i + 0.5, j + 0.5) > a.radius:
        points.append((i, j))
pairs = sorted(
    ((points[2 * k], points[2 * k + 1]) for k in range(a.pairs)),
    key=lambda p: math.dist(p[0], p[1]),
)
os.makedirs(a.out, exist_ok=True)
rows = ["".join("@" if occ[j][i] else "." for i in range(n)) for j in range(n)]
with open(os.path.join(a.out, name + ".map"), "w") as f:
    f.write(f"type octile\nheight {n}\nwidth {n}\nmap\n" + "\n".join(rows) + "\n")
lines = ["version 1"]
for k, (s, g) in enumerate(pairs):
    d = math.dist(s, g)
    lines.append(f"{k // 10}\t{name}.map\t{n}\t{n}\t{s[0]}\t{s[1]}\t{g[0]}\t{g[1]}\t{1.1 * d:.8f}")
with open(os.path.join(a.out, name + ".map.scen"), "w") as f:
    f.write("\n".join(lines) + "\n")
print(os.path.join(a.out, name + ".map.scen"))
