"""homospline: homotopy-seeded spline path planning for ground robots with aerial scouts.

Plans are computed in Rust with the GIL released. Errors carry the command line's messages
(file, line, field): ValueError for bad input (and, from `simulate` and `bench_scen`, for
files they cannot read, named in the message), TypeError for arguments of the wrong type,
OSError when `Scene.from_file`, `Graph.load` or `Graph.save` cannot read or write a file.
"""

from os import PathLike
from typing import Any, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, PathLike[str]]

class Scene:
    """A scene: bounds, start, goal and obstacles made of circles (docs/formats.md)."""

    @staticmethod
    def from_file(path: _Path) -> "Scene":
        """Reads a scene file (YAML or JSON)."""
    @staticmethod
    def from_dict(d: dict[str, Any]) -> "Scene":
        """A scene from a dict with the fields of a scene file."""
    @staticmethod
    def example() -> "Scene":
        """The built-in example (the paper's Fig. 5)."""
    @property
    def name(self) -> str: ...
    @property
    def start(self) -> tuple[float, float]: ...
    @property
    def goal(self) -> tuple[float, float]: ...
    def to_dict(self) -> dict[str, Any]:
        """The scene file's fields."""

class Graph:
    """A Voronoi graph, built once and reused by `plan(scene, graph=...)`."""

    @staticmethod
    def load(path: _Path) -> "Graph": ...
    def save(self, path: _Path) -> None: ...
    @property
    def nodes(self) -> int: ...
    @property
    def edges(self) -> int: ...
    def to_dict(self) -> dict[str, Any]:
        """The graph JSON of docs/formats.md."""

class ClassPlan:
    """One optimised homotopy class."""

    @property
    def rank(self) -> int: ...
    @property
    def signature(self) -> str: ...
    @property
    def path(self) -> npt.NDArray[np.float64]:
        """The sampled curve, shape (n, 2)."""
    @property
    def via_points(self) -> npt.NDArray[np.float64]:
        """Start, via-points, goal, shape (k, 2)."""
    @property
    def length(self) -> float: ...
    @property
    def min_clearance(self) -> float: ...
    @property
    def certified_clearance(self) -> float: ...
    @property
    def collision_free(self) -> bool: ...
    @property
    def safe(self) -> bool: ...
    @property
    def cost(self) -> float: ...

class Plan:
    """Every class, ranked, and the chosen one."""

    @property
    def best(self) -> Optional[int]:
        """Rank of the chosen class; None when no class is collision-free."""
    @property
    def classes(self) -> list[ClassPlan]: ...
    @property
    def chosen(self) -> Optional[ClassPlan]: ...
    @property
    def path(self) -> Optional[npt.NDArray[np.float64]]:
        """The chosen path, shape (n, 2), or None."""
    def to_dict(self) -> dict[str, Any]:
        """The plan result of docs/formats.md (what `homospline plan --json` writes)."""

def plan(
    scene: Scene,
    classes: Optional[int] = None,
    preset: str = "paper-voronoi",
    weights: Optional[dict[str, float]] = None,
    optimizer: Optional[str] = None,
    seed: str = "voronoi",
    roughness: Optional[str] = None,
    clearance_floor: float = 0.0,
    graph: Optional[Graph] = None,
    soft_dm: bool = False,
    prune: Optional[Union[str, float]] = None,
    clearance_search: Optional[str] = None,
    polish: Optional[int] = None,
    finish_within: Optional[Union[str, int]] = None,
    time_limit: Optional[float] = None,
) -> Plan:
    """Plans a scene (the `plan` command); `classes` is 1 to 64 (default 5; the straight
    seed plans one class and refuses any other count); `soft_dm` turns the dm rule off; `prune` is
    `"off"` or a ratio (`--prune`; default 1.5); `clearance_search` is `"worst-node"`
    (default) or `"every-stretch"` (`--clearance-search`); `polish` is the chosen class's
    polish rounds, 0 to 10 (`--polish`; default 0); `finish_within` is `"off"` or the work
    budget, in cost evaluations, under which the chosen class gets its interior-point
    finish (`--finish-within`; default 1500; 0 or `"off"`: never; `polish` > 0 replaces
    it). A count out of range raises `ValueError` naming its keyword. `time_limit` is a
    positive number of milliseconds (`--time-limit`): the plan stops at its next growth
    round or class seed once it has passed, and `TimeoutError` is raised; a plan done in
    time is the plan without a limit.

    The plan runs with the GIL released and Ctrl-C (any signal handler that raises) stops
    it between growth rounds: `KeyboardInterrupt` is raised within a round or so. A grid
    larger than the process's address-space limit (`ulimit -v`) raises `MemoryError` with
    what it needs, before anything of its size is allocated."""

def plan_map(
    occupancy: npt.NDArray[np.bool_],
    start: tuple[float, float],
    goal: tuple[float, float],
    resolution: float = 1.0,
    origin: tuple[float, float] = (0.0, 0.0),
    y_down: bool = False,
    classes: Optional[int] = None,
    robot_radius: float = 0.0,
    time_limit: Optional[float] = None,
) -> Plan:
    """Plans on a 2-D bool occupancy array (True = occupied; rows are y, columns x; y up
    from `origin` as in ROS, or rows down the page with `y_down=True`). `robot_radius`
    (map units) is kept from every occupied cell and the array's edge. Raises `NoRoute`
    when no route at that radius joins start and goal, `ValueError` for bad input (a start
    or goal closer than the radius among it). `classes` defaults to 5. Interruptible,
    memory-checked and time-limited (`time_limit`, ms: `TimeoutError`) as `plan`."""

class NoRoute(ValueError):
    """No route joins start and goal for the robot at its radius; the message names the
    widest route's least clearance and where it is."""

def build_graph(scene: Scene, resolution: Optional[float] = None) -> Graph:
    """The Voronoi graph of a scene, start and goal attached."""

def simulate(world: _Path, policy: Optional[str] = None, scouts: Optional[int] = None) -> dict[str, Any]:
    """Runs the mission of a world file (a scene world or a map world with its truth map);
    returns the mission JSON of docs/formats.md. ``policy`` is a registered scout policy's
    name (``none``, ``ahead``, ``alternatives``, ``guard``, ``verified``, ``survey``); None
    takes the library's default, ``verified``."""

def bench_scen(
    files: Sequence[_Path],
    sample: Optional[int] = None,
    limit: Optional[int] = None,
    shard: Optional[tuple[int, int]] = None,
    classes: Optional[int] = None,
    time_limit: Optional[float] = None,
    robot_radius: float = 0.0,
) -> str:
    """Plans MovingAI scenarios (`homospline bench-scen`, `robot_radius` as its
    `--robot-radius`); returns the CSV text."""

def bench_summary(csvs: Sequence[str]) -> str:
    """The summary of the rows of one or more bench_scen CSVs (`homospline bench-merge`)."""
