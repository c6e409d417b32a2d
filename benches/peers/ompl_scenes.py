"""Our plans on the paper's scenes against OMPL in the same run: RRTConnect with OMPL's path
simplifier (the usual "fast feasible path" pipeline), and RRT* given our time and ten times it.

Usage:
    cargo build --release -p homospline-cli
    python3 benches/peers/ompl_scenes.py [SCENE.yaml ...] [--repeat 11] [--homospline PATH]

Needs `pip install ompl pyyaml` (OMPL 2.0's wheels, Python bindings over its C++ library).
Scenes default to fixtures/scenes/*.yaml. For each scene, `--repeat` times in turns: our
whole plan (`homospline plan SCENE --json`, its in-process `timing_ms.total`: Voronoi graph,
5 classes, optimisation, certificates; the process start is not counted) and each peer on a
fresh problem, timed in-process around `solve` and the simplification. The peer's states
are valid when they keep the clearance our plan was asked for (`dm` of our JSON, beyond the
robot's radius) from every circle and lie within the scene's bounds; motions are checked
every 0.2 % of the scene's extent. Printed per scene: the median time of each, the ratio
ours / peer, the chosen (ours) or returned (peer) path's median length and its least
clearance (ours certified; the peer's measured here along its polyline every 0.01 units,
so a motion check that stepped over a corner shows). OMPL's validity checker is a Python
function here, called through the bindings; the line "checks" gives how many calls a peer
run made and what they cost at the rate measured on their own, an estimate of the time a
C++ checker would save (for RRTConnect, which stops at its first path, the summary gives
the ratio without them too; RRT* runs to its limit either way). RRT* plans with OMPL's
path-length objective and stops at its time limit; "no path" counts the runs that returned
none. OMPL's random numbers are seeded once (`--seed`), so a run repeats itself.
"""

import argparse
import glob
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import yaml
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou


def read_scene(path):
    d = yaml.safe_load(open(path))
    rr = float(d.get("robot_radius", 0.0))
    circles = [
        (float(c[0]), float(c[1]), float(c[2]) + rr)
        for o in d.get("obstacles") or []
        for c in o["circles"]
    ]
    return {
        "lo": [float(v) for v in d["bounds"]["min"]],
        "hi": [float(v) for v in d["bounds"]["max"]],
        "start": [float(v) for v in d["start"]],
        "goal": [float(v) for v in d["goal"]],
        "circles": circles,
    }


def ours(exe, scene_path):
    """One plan of ours: (in-process ms, chosen length, chosen certified clearance, dm)."""
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run(
            [exe, "plan", scene_path, "--json", f.name],
            check=True,
            stdout=subprocess.DEVNULL,
        )
        d = json.load(open(f.name))
    best = next(c for c in d["classes"] if c["rank"] == d["best"])
    return d["timing_ms"]["total"], best["length"], best["certified_clearance"], d["dm"]


def clearance_of(points, circles):
    """The polyline's least distance to a circle's rim, every 0.01 units."""
    least = math.inf
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        n = max(1, math.ceil(math.hypot(x1 - x0, y1 - y0) / 0.01))
        for i in range(n + 1):
            t = i / n
            x, y = x0 + t * (x1 - x0), y0 + t * (y1 - y0)
            for cx, cy, r in circles:
                least = min(least, math.hypot(x - cx, y - cy) - r)
    return least


class Peer:
    """One OMPL problem on a scene, rebuilt for every run."""

    def __init__(self, scene, dm):
        self.scene = scene
        self.inflated = [(cx, cy, r + dm) for cx, cy, r in scene["circles"]]
        self.calls = 0

    def valid(self, s):
        self.calls += 1
        x, y = s[0], s[1]
        for cx, cy, r in self.inflated:
            dx, dy = x - cx, y - cy
            if dx * dx + dy * dy < r * r:
                return False
        return True

    def run(self, planner, seconds, simplify):
        """(ms, length, points) or (ms, None, None) when no exact path came back."""
        sc = self.scene
        space = ob.RealVectorStateSpace(2)
        b = ob.RealVectorBounds(2)
        for k in range(2):
            b.setLow(k, sc["lo"][k])
            b.setHigh(k, sc["hi"][k])
        space.setBounds(b)
        ss = og.SimpleSetup(space)
        ss.setStateValidityChecker(self.valid)
        si = ss.getSpaceInformation()
        si.setStateValidityCheckingResolution(0.002)
        start, goal = space.allocState(), space.allocState()
        for k in range(2):
            start[k], goal[k] = sc["start"][k], sc["goal"][k]
        ss.setStartAndGoalStates(start, goal)
        if planner == "rrtstar":
            ss.setOptimizationObjective(ob.PathLengthOptimizationObjective(si))
            ss.setPlanner(og.RRTstar(si))
        else:
            ss.setPlanner(og.RRTConnect(si))
        ss.setup()
        t0 = time.perf_counter()
        solved = ss.solve(seconds)
        exact = ss.haveExactSolutionPath()
        if exact and simplify:
            ss.simplifySolution()
        ms = (time.perf_counter() - t0) * 1e3
        if not (solved and exact):
            return ms, None, None
        p = ss.getSolutionPath()
        pts = [(p.getState(i)[0], p.getState(i)[1]) for i in range(p.getStateCount())]
        return ms, p.length(), pts


def check_rate(peer, n=200_000):
    """Seconds per call of the Python validity checker, on states spread over the scene."""

    class S:
        __slots__ = ("v",)

        def __init__(self, x, y):
            self.v = (x, y)

        def __getitem__(self, k):
            return self.v[k]

    sc = peer.scene
    states = [
        S(
            sc["lo"][0] + (sc["hi"][0] - sc["lo"][0]) * ((i * 0.618034) % 1.0),
            sc["lo"][1] + (sc["hi"][1] - sc["lo"][1]) * ((i * 0.414214) % 1.0),
        )
        for i in range(1000)
    ]
    calls = peer.calls
    t0 = time.perf_counter()
    for i in range(n // 1000):
        for s in states:
            peer.valid(s)
    rate = (time.perf_counter() - t0) / n
    peer.calls = calls
    return rate


def span(v):
    """`median (least to most)` of the values `v`."""
    return f"{statistics.median(v):.2f} ({min(v):.2f} to {max(v):.2f})"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--homospline", default="target/release/homospline")
    ap.add_argument("--repeat", type=int, default=11)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    scenes = a.scenes or sorted(glob.glob("fixtures/scenes/*.yaml"))
    if not os.path.exists(a.homospline):
        sys.exit(f"{a.homospline}: not found (cargo build --release -p homospline-cli)")
    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(a.seed)
    print(
        f"{'scene':15s} {'planner':22s} {'ms':>7s} {'ours/peer':>9s} {'length':>8s} "
        f"{'clearance':>9s} {'no path':>7s}  checks"
    )
    summary = {}
    for path in scenes:
        name = os.path.basename(path).split(".")[0]
        scene = read_scene(path)
        rows = {k: [] for k in ("ours", "rrtconnect", "rrtstar x1", "rrtstar x10")}
        calls = {k: [] for k in rows}
        dm = None
        for _ in range(a.repeat):
            ms, length, clr, dm = ours(a.homospline, path)
            rows["ours"].append((ms, length, [clr]))
            peer = Peer(scene, dm)
            budget = statistics.median(r[0] for r in rows["ours"]) / 1e3
            for key, planner, seconds, simplify in (
                ("rrtconnect", "rrtconnect", 1.0, True),
                ("rrtstar x1", "rrtstar", budget, False),
                ("rrtstar x10", "rrtstar", 10 * budget, False),
            ):
                peer.calls = 0
                ms, length, pts = peer.run(planner, seconds, simplify)
                clr = clearance_of(pts, scene["circles"]) if pts else None
                rows[key].append((ms, length, [clr] if pts else []))
                calls[key].append(peer.calls)
        rate = check_rate(Peer(scene, dm))
        t_ours = statistics.median(r[0] for r in rows["ours"])
        len_ours = statistics.median(r[1] for r in rows["ours"])
        for key, rs in rows.items():
            t = statistics.median(r[0] for r in rs)
            lens = [r[1] for r in rs if r[1] is not None]
            clrs = [c for r in rs for c in r[2]]
            extra = ""
            if key != "ours":
                c = statistics.median(calls[key])
                checks = c * rate * 1e3
                extra = f"{c:.0f} a run, {checks:.2f} ms at {rate * 1e9:.0f} ns each"
                s = summary.setdefault(key, {"time": [], "bare": [], "length": [], "none": 0})
                s["time"].append(t_ours / t)
                s["bare"].append(t_ours / max(t - checks, 1e-3))
                if lens:
                    s["length"].append(statistics.median(lens) / len_ours)
                s["none"] += sum(r[1] is None for r in rs)
            print(
                f"{name:15s} {key:22s} {t:7.2f} {t_ours / t:9.2f} "
                f"{statistics.median(lens) if lens else math.nan:8.2f} "
                f"{min(clrs) if clrs else math.nan:9.3f} "
                f"{sum(r[1] is None for r in rs):4d}/{len(rs):<2d}  {extra}"
            )
    print(
        "over the scenes (median, least to most): time ours / peer (RRTConnect's also with "
        "its Python checks taken off); median length peer / ours"
    )
    for key, s in summary.items():
        # A planner that runs to its time limit would only sample more with cheaper checks.
        bare = f"; without its checks {span(s['bare'])}" if key == "rrtconnect" else ""
        print(
            f"  {key:12s} time {span(s['time'])}{bare}; "
            f"length {span(s['length']) if s['length'] else 'none'}; no path {s['none']} runs"
        )
    sys.stdout.flush()
    # nanobind reports OMPL's objects still alive at interpreter exit; they are not ours.
    os._exit(0)


if __name__ == "__main__":
    main()
