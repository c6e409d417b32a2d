"""The Python package against the command line: same plans for the same inputs, errors as
exceptions with the same messages, NumPy shapes and dtypes, bad arrays refused."""

import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import homospline

ROOT = pathlib.Path(__file__).resolve().parents[3]


def cli():
    """The homospline binary: $HOMOSPLINE_BIN, else target/release or target/debug."""
    env = os.environ.get("HOMOSPLINE_BIN")
    for p in [env] if env else [ROOT / "target/release/homospline", ROOT / "target/debug/homospline"]:
        if p and pathlib.Path(p).is_file():
            return str(p)
    raise AssertionError("no homospline binary: build it (cargo build) or set HOMOSPLINE_BIN")


def cli_json(args, tmp_path):
    out = tmp_path / "plan.json"
    subprocess.run([cli(), *args, "--json", str(out)], cwd=ROOT, check=True, capture_output=True)
    return json.loads(out.read_text())


def timeless(d):
    """A plan dict without its wall-clock fields."""
    d = json.loads(json.dumps(d))
    d.pop("timing_ms", None)
    for c in d["classes"]:
        c.pop("time_ms", None)
    return d


@pytest.mark.parametrize("scene", ["convex", "narrow-pass", "field"])
def test_plan_equals_the_cli_plan(scene, tmp_path):
    path = ROOT / "fixtures/scenes" / f"{scene}.yaml"
    ours = homospline.plan(homospline.Scene.from_file(path)).to_dict()
    theirs = cli_json(["plan", str(path)], tmp_path)
    assert timeless(ours) == timeless(theirs)


def test_soft_dm_equals_the_cli_flag(tmp_path):
    path = ROOT / "fixtures/scenes/field.yaml"
    scene = homospline.Scene.from_file(path)
    ruled = homospline.plan(scene).to_dict()
    soft = homospline.plan(scene, soft_dm=True).to_dict()
    assert timeless(soft) == timeless(cli_json(["plan", str(path), "--soft-dm"], tmp_path))
    best = lambda p: p["classes"][p["best"] - 1]
    assert best(ruled)["safe"] and not best(soft)["safe"]


def movingai_array(path):
    rows = path.read_text().splitlines()[4:]
    return np.array([[c not in ".G" for c in r] for r in rows if r], dtype=bool)


def test_plan_map_equals_the_cli_plan_on_the_same_map(tmp_path):
    path = ROOT / "fixtures/maps/movingai/maze-32-32-2.map"
    grid = movingai_array(path)
    assert grid.shape == (32, 32)
    ours = homospline.plan_map(grid, (19.5, 2.5), (4.5, 27.5), y_down=True).to_dict()
    theirs = cli_json(["plan", str(path), "--start", "19.5,2.5", "--goal", "4.5,27.5"], tmp_path)
    ours.pop("scene"), theirs.pop("scene")
    assert timeless(ours) == timeless(theirs)


def test_plan_map_with_a_robot_radius_equals_the_cli_and_refuses_a_start_too_near(tmp_path):
    path = ROOT / "fixtures/maps/movingai/room-32-32-4.map"
    grid = movingai_array(path)
    ours = homospline.plan_map(grid, (1.5, 1.5), (30.5, 30.5), y_down=True, robot_radius=0.3).to_dict()
    theirs = cli_json(
        ["plan", str(path), "--start", "1.5,1.5", "--goal", "30.5,30.5", "--robot-radius", "0.3"], tmp_path
    )
    ours.pop("scene"), theirs.pop("scene")
    assert timeless(ours) == timeless(theirs)
    with pytest.raises(ValueError, match="less than the robot radius 0.7"):
        homospline.plan_map(grid, (1.5, 1.5), (30.5, 30.5), y_down=True, robot_radius=0.7)
    with pytest.raises(ValueError, match="robot_radius=-1"):
        homospline.plan_map(grid, (1.5, 1.5), (30.5, 30.5), y_down=True, robot_radius=-1.0)


def test_plan_map_checks_resolution_and_origin_as_a_ros_map_yaml_is_checked():
    grid = np.zeros((40, 60), dtype=bool)
    # Below a nanometre, not finite, or reaching past 1e9: refused by keyword, as the CLI
    # refuses the same values in a ROS map's YAML (they planned nothing silently, named the
    # start outside a map of NaN, or took 78 s).
    for resolution in (1e-10, float("nan"), 1e300, 1e13):
        with pytest.raises(ValueError, match="resolution=.*(at least 1e-9|coordinates must stay within 1e9)"):
            homospline.plan_map(grid, (5.5, 20.5), (55.5, 20.5), resolution=resolution)
    with pytest.raises(ValueError, match="origin=.*must be finite"):
        homospline.plan_map(grid, (5.5, 20.5), (55.5, 20.5), origin=(float("nan"), 0.0))


def test_no_route_for_the_robot_is_its_own_exception_naming_the_widest_route():
    grid = movingai_array(ROOT / "fixtures/maps/movingai/room-32-32-4.map")
    # The rooms' doors are one cell wide: a disc of radius 1 passes none.
    with pytest.raises(homospline.NoRoute, match="the widest route between start and goal keeps 0.5 at"):
        homospline.plan_map(grid, (2.5, 2.5), (30.5, 30.5), y_down=True, robot_radius=1.0)
    assert issubclass(homospline.NoRoute, ValueError)


def test_a_scene_walled_apart_is_no_route_naming_the_obstacles():
    # Grown by the robot's radius 3, the two discs touch each other and the bounds.
    walled = homospline.Scene.from_dict(
        {"bounds": {"min": [0, 0], "max": [60, 60]}, "start": [5, 30], "goal": [55, 30],
         "robot_radius": 3,
         "obstacles": [{"name": "top", "circles": [[30, 45, 12]]},
                       {"name": "bot", "circles": [[30, 15, 12]]}]}
    )
    with pytest.raises(homospline.NoRoute, match="walled apart by 'top', 'bot'"):
        homospline.plan(walled)


def test_a_time_limit_raises_timeout_error_and_never_changes_a_plan():
    scene = homospline.Scene.example()
    # 10 microseconds for plans of 64 classes, tens of milliseconds and more (a scene's
    # graph alone takes about one): the watchdog stops them even when it wakes late.
    field = homospline.Scene.from_file(str(ROOT / "fixtures/scenes/field.yaml"))
    with pytest.raises(TimeoutError, match=r"no plan within time_limit=0.01 ms"):
        homospline.plan(field, classes=64, time_limit=0.01)
    grid = movingai_array(ROOT / "fixtures/maps/movingai/room-32-32-4.map")
    with pytest.raises(TimeoutError, match=r"array: no plan within time_limit=0.01 ms"):
        homospline.plan_map(grid, (2.5, 2.5), (30.5, 30.5), y_down=True, classes=64, time_limit=0.01)
    free, limited = homospline.plan(scene, classes=2), homospline.plan(scene, classes=2, time_limit=6e5)
    assert [c.length for c in free.classes] == [c.length for c in limited.classes]
    for bad in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="time_limit=.*must be a positive number of ms"):
            homospline.plan(scene, time_limit=bad)


def test_a_quoted_number_in_a_scene_is_refused():
    with pytest.raises(ValueError, match="start: expected a number .*not the string '5'"):
        homospline.Scene.from_dict(
            {"bounds": {"min": [0, 0], "max": [60, 60]}, "start": ["5", 30], "goal": [55, 30]}
        )


def test_results_are_numpy_arrays_of_points():
    p = homospline.plan(homospline.Scene.example(), classes=3)
    assert p.best == 1
    for c in p.classes:
        assert c.path.dtype == np.float64 and c.path.ndim == 2 and c.path.shape[1] == 2
        assert c.via_points.shape[1] == 2 and c.via_points.shape[0] >= 2
    assert np.allclose(p.path[0], homospline.Scene.example().start)
    assert np.allclose(p.path[-1], homospline.Scene.example().goal)
    assert p.chosen.collision_free


def test_a_ros_style_grid_plans_with_y_up_and_a_resolution():
    grid = np.zeros((40, 60), dtype=bool)
    grid[10:30, 25:35] = True  # a block in the middle
    p = homospline.plan_map(grid, (0.45, 1.05), (5.45, 1.05), resolution=0.1, origin=(-0.5, -1.0))
    assert p.best is not None
    xs, ys = p.path[:, 0], p.path[:, 1]
    # Around the block ([2.0, 3.0] x [0.0, 2.0] in the world frame), never through it.
    inside = (xs > 2.0) & (xs < 3.0) & (ys > 0.0) & (ys < 2.0)
    assert not inside.any()


@pytest.mark.parametrize(
    "array, error, message",
    [
        (np.zeros((4, 4), dtype=np.int64), TypeError, "expected dtype bool"),
        (np.zeros(10, dtype=bool), ValueError, "expected a 2-D array"),
        (np.zeros((0, 3), dtype=bool), ValueError, "the array is empty"),
        ([[True, False]], TypeError, "expected a NumPy array of bool"),
    ],
)
def test_bad_arrays_are_refused_clearly(array, error, message):
    with pytest.raises(error, match=message):
        homospline.plan_map(array, (0.5, 0.5), (1.5, 1.5))


def test_errors_are_exceptions_with_the_cli_messages():
    for name in ["nan-coordinate", "goal-inside-obstacle", "missing-goal"]:
        expected = (ROOT / "fixtures/invalid" / f"{name}.expected").read_text().strip()
        with pytest.raises(ValueError) as e:
            _from_rel(name)
        assert str(e.value) == expected
    with pytest.raises(OSError, match="cannot read"):
        homospline.Scene.from_file(ROOT / "no-such-scene.yaml")
    with pytest.raises(ValueError, match="classes=0: must be between 1 and 64"):
        homospline.plan(homospline.Scene.example(), classes=0)
    with pytest.raises(ValueError, match="classes=3: seed straight plans one class"):
        homospline.plan(homospline.Scene.example(), seed="straight", classes=3)
    assert len(homospline.plan(homospline.Scene.example(), seed="straight", classes=1).classes) == 1
    example = homospline.Scene.example()
    with pytest.raises(ValueError, match="graph gives the Voronoi seed's classes; seed straight plans one class from the straight line"):
        homospline.plan(example, seed="straight", graph=homospline.build_graph(example))
    with pytest.raises(ValueError, match="unknown weight or parameter 'safty'"):
        homospline.plan(homospline.Scene.example(), weights={"safty": 1.0})
    with pytest.raises(ValueError, match="radius must be > 0"):
        homospline.Scene.from_dict(
            {"bounds": {"min": [0, 0], "max": [10, 10]}, "start": [1, 1], "goal": [9, 9],
             "obstacles": [{"circles": [[5, 5, -1]]}]}
        )


def _from_rel(name):
    """Reads an invalid fixture by the path the goldens name it with."""
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        return homospline.Scene.from_file(f"fixtures/invalid/{name}.yaml")
    finally:
        os.chdir(cwd)


def test_a_saved_graph_gives_the_same_plan(tmp_path):
    scene = homospline.Scene.from_file(ROOT / "fixtures/scenes/two-homotopies.yaml")
    g = homospline.build_graph(scene)
    assert g.nodes > 0 and g.edges > 0
    g.save(tmp_path / "g.msgpack")
    again = homospline.Graph.load(tmp_path / "g.msgpack")
    assert timeless(homospline.plan(scene, graph=again).to_dict()) == timeless(homospline.plan(scene).to_dict())
    # A graph built for another start or goal is refused, as by `plan --graph`.
    other = homospline.Scene.from_file(ROOT / "fixtures/scenes/convex.yaml")
    with pytest.raises(ValueError, match="another start or goal"):
        homospline.plan(other, graph=again)


def test_a_mission_reaches_its_goal():
    r = homospline.simulate(ROOT / "fixtures/worlds/narrow-pass-blocked.yaml", policy="ahead")
    assert r["reached"] and r["replans"] >= 1
    assert any(e["kind"] == "discovered" for e in r["events"])


def test_a_mission_on_a_map_world_reaches_its_goal():
    r = homospline.simulate(ROOT / "fixtures/worlds/maps/room-blocked.yaml", policy="none")
    assert r["reached"] and r["replans"] >= 1
    assert r["map_updates"] and r["map_updates"][0]["cells"] >= 1


def test_shards_merge_into_the_whole_sweep():
    files = [str(ROOT / "fixtures/maps/movingai/maze-32-32-2-random-1.scen")]
    whole = homospline.bench_scen(files, sample=4, classes=2)
    parts = [homospline.bench_scen(files, sample=4, classes=2, shard=(k, 2)) for k in (1, 2)]
    strip = lambda text: sorted(",".join(r.split(",")[:14] + r.split(",")[15:]) for r in text.splitlines()[1:])
    assert strip(whole) == sorted(strip(parts[0]) + strip(parts[1]))
    summary = homospline.bench_summary(parts)
    assert "success      4/4" in summary
    with pytest.raises(ValueError, match="overlapping shards"):
        homospline.bench_summary([parts[0], parts[0]])
    # Errors name the keyword arguments, not the command line's flags.
    for kwargs, message in [
        ({"sample": 0}, "sample=0: must be at least 1"),
        ({"sample": 2, "limit": 2}, "limit and sample exclude each other"),
        ({"classes": 65}, "classes=65: must be between 1 and 64"),
        ({"robot_radius": -1.0}, "robot_radius=-1: must be a finite number >= 0"),
        ({"time_limit": 0.0}, "time_limit=0: must be a positive number of ms"),
    ]:
        with pytest.raises(ValueError, match=message):
            homospline.bench_scen(files, **kwargs)


def test_prune_equals_the_cli_flag(tmp_path):
    path = ROOT / "fixtures/scenes/convex.yaml"
    scene = homospline.Scene.from_file(path)
    for value, flag in [("off", "off"), (3.0, "3")]:
        ours = homospline.plan(scene, prune=value).to_dict()
        assert timeless(ours) == timeless(cli_json(["plan", str(path), "--prune", flag], tmp_path))
    assert any(c["pruned"] for c in homospline.plan(scene).to_dict()["classes"])
    assert not any(c["pruned"] for c in homospline.plan(scene, prune="off").to_dict()["classes"])
    with pytest.raises(ValueError, match="prune=0.5: expected off or a ratio of at least 1"):
        homospline.plan(scene, prune=0.5)


def test_clearance_search_equals_the_cli_flag(tmp_path):
    path = ROOT / "fixtures/scenes/convex.yaml"
    scene = homospline.Scene.from_file(path)
    every = homospline.plan(scene, clearance_search="every-stretch").to_dict()
    cli = cli_json(["plan", str(path), "--clearance-search", "every-stretch"], tmp_path)
    assert timeless(every) == timeless(cli)
    with pytest.raises(ValueError, match="clearance_search='exact': unknown clearance search"):
        homospline.plan(scene, clearance_search="exact")


def test_polish_equals_the_cli_flag(tmp_path):
    path = ROOT / "fixtures/scenes/convex.yaml"
    scene = homospline.Scene.from_file(path)
    polished = homospline.plan(scene, polish=1).to_dict()
    cli = cli_json(["plan", str(path), "--polish", "1"], tmp_path)
    assert timeless(polished) == timeless(cli)
    plain = homospline.plan(scene).to_dict()
    def chosen(p):
        return p["classes"][p["best"] - 1]
    assert chosen(polished)["cost"]["total"] < chosen(plain)["cost"]["total"]
    with pytest.raises(ValueError, match="polish=11: must be between 0 and 10"):
        homospline.plan(scene, polish=11)


def test_finish_within_equals_the_cli_flag(tmp_path):
    # Convex's classes spend 1,324 evaluations: under the default budget (1,500) its chosen
    # class gets the interior-point finish; "off" or a budget of 1,000 leave it out.
    path = ROOT / "fixtures/scenes/convex.yaml"
    scene = homospline.Scene.from_file(path)
    default = homospline.plan(scene).to_dict()
    off = homospline.plan(scene, finish_within="off").to_dict()
    assert timeless(off) == timeless(cli_json(["plan", str(path), "--finish-within", "off"], tmp_path))
    small = homospline.plan(scene, finish_within=1000).to_dict()
    assert timeless(small) == timeless(cli_json(["plan", str(path), "--finish-within", "1000"], tmp_path))
    def chosen(p):
        return p["classes"][p["best"] - 1]
    assert chosen(small)["path"] == chosen(off)["path"]
    assert chosen(default)["cost"]["total"] < 0.95 * chosen(off)["cost"]["total"]
    assert chosen(default)["iterations"] == chosen(off)["iterations"] + 1
    with pytest.raises(ValueError, match="finish_within='never': expected \"off\" or a number of evaluations"):
        homospline.plan(scene, finish_within="never")
    with pytest.raises(TypeError, match="finish_within"):
        homospline.plan(scene, finish_within=1.5)


def _lattice_scene(n=30):
    """A square of n x n discs: many classes, a plan of seconds with many of them."""
    obstacles = [
        {"name": f"o{i}_{j}", "circles": [[3 + i * 3.1, 3 + j * 3.1, 0.8]]}
        for i in range(n)
        for j in range(n)
    ]
    return homospline.Scene.from_dict(
        {"name": "lattice", "bounds": {"min": [0, 0], "max": [96, 96]}, "start": [1, 1],
         "goal": [95, 95], "obstacles": obstacles}
    )


def test_ctrl_c_interrupts_a_plan_within_a_round():
    # KeyboardInterrupt arrived only when the plan returned: 7 s with 20 classes, twice
    # that with 40.
    import signal
    import threading
    import time

    scene = _lattice_scene()
    timer = threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            homospline.plan(scene, classes=40)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 5.0
    # The next plan is not interrupted.
    assert homospline.plan(homospline.Scene.example()).classes


def test_a_grid_beyond_the_address_space_limit_is_a_memory_error():
    # Under `ulimit -v` the interpreter aborted (SIGABRT) half way through the map.
    code = (
        "import resource, numpy as np, homospline\n"
        "resource.setrlimit(resource.RLIMIT_AS, (400_000_000, resource.RLIM_INFINITY))\n"
        "try:\n"
        "    homospline.plan_map(np.zeros((2048, 2048), bool), (10.5, 10.5), (2000.5, 2000.5))\n"
        "except MemoryError as e:\n"
        "    print('MemoryError:', e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "MemoryError: occupancy (2048 x 2048 cells) needs up to about 713 MB" in out.stdout
    assert "this process may use 400 MB" in out.stdout


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda s: homospline.plan(s, classes=-1), "classes=-1: must be a whole number >= 0"),
        (lambda s: homospline.plan(s, polish=-1), "polish=-1: must be a whole number >= 0"),
        (lambda s: homospline.plan(s, finish_within=-1), 'finish_within=-1: expected "off" or a number of evaluations'),
        (lambda s: homospline.plan_map(np.zeros((4, 4), bool), (0.5, 0.5), (3.5, 3.5), classes=-2),
         "classes=-2: must be a whole number >= 0"),
        (lambda s: homospline.simulate(ROOT / "fixtures/worlds/convex-blocked.yaml", scouts=-1),
         "scouts=-1: must be a whole number >= 0"),
    ],
)
def test_negative_counts_are_value_errors_naming_the_keyword(call, message):
    # They were OverflowError (or TypeError for finish_within) naming nothing.
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        call(homospline.Scene.example())


def test_a_mission_setting_out_of_range_names_the_keyword():
    # The mission's own check (MissionConfig::check), spelled as Python's keywords.
    with pytest.raises(ValueError, match="^scouts=65: must be at most 64$"):
        homospline.simulate(ROOT / "fixtures/worlds/convex-blocked.yaml", scouts=65)


def test_simulate_takes_every_registered_policy_and_names_them_when_one_is_unknown():
    r = homospline.simulate(ROOT / "fixtures/worlds/narrow-pass-blocked.yaml")
    assert r["policy"] == "survey" and r["reached"]
    with pytest.raises(ValueError, match="none, ahead, alternatives, guard"):
        homospline.simulate(ROOT / "fixtures/worlds/narrow-pass-blocked.yaml", policy="bogus")
