"""A seeded scene of random discs in a square: the clutter and `--optimum` figures of
docs/performance.md and the CHANGELOG.

Usage: python3 scripts/random_discs.py N [--seed 1] [--size 100] [--rmin 0.2] [--rmax 0.6]
       > scene.yaml

Centres are uniform in the square, radii uniform in [rmin, rmax]; discs within 3 units of
the start (1, 1) or the goal (size - 1, size - 1) are drawn again.
"""

import argparse
import random


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", type=int)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--size", type=float, default=100.0)
    ap.add_argument("--rmin", type=float, default=0.2)
    ap.add_argument("--rmax", type=float, default=0.6)
    a = ap.parse_args()
    rng = random.Random(a.seed)
    w = a.size
    s, t = (1.0, 1.0), (w - 1.0, w - 1.0)
    print(f"name: random-{a.n}")
    print(f"bounds: {{min: [0, 0], max: [{w:g}, {w:g}]}}")
    print(f"start: [{s[0]:g}, {s[1]:g}]\ngoal: [{t[0]:g}, {t[1]:g}]\nobstacles:")
    k = 0
    while k < a.n:
        x, y = rng.uniform(0, w), rng.uniform(0, w)
        if min((x - p[0]) ** 2 + (y - p[1]) ** 2 for p in (s, t)) < 9:
            continue
        r = rng.uniform(a.rmin, a.rmax)
        print(f"  - circles: [[{x:.4f}, {y:.4f}, {r:.3f}]]")
        k += 1


if __name__ == "__main__":
    main()
