"""Type stubs of the printwatt Python module (the PyO3 extension built from python/src/lib.rs).

SI units in and out (m, rad, s, kg, N·m, W, J, m/s). Functions whose result mirrors a
`printwatt <command> --json` document return a plain ``dict``; its keys are listed here as a
``TypedDict`` (``EnergyResult``, ``SweepResult``, …), with nested parts typed where they are
fixed and ``dict[str, Any]`` where they follow docs/json.md. The ``TypedDict`` classes and the
``Literal`` aliases (``Objective``, ``Regeneration``, …) exist for type checkers only: import
them under ``typing.TYPE_CHECKING``; at run time the results are ordinary dictionaries.

python/tests/test_stubs.py checks that this file lists exactly the names the module exports,
with the same parameters and defaults, and that every result has the keys listed here.
"""

import os
from typing import Any, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray
from typing_extensions import TypeAlias

__version__: str

# ---------------------------------------------------------------------------------------------
# Argument types (typing only)

#: A file or directory: a ``str`` or a path object.
StrPath: TypeAlias = Union[str, "os.PathLike[str]"]
#: A sequence of numbers: a list, a tuple or a 1-D NumPy array of floats.
Floats: TypeAlias = Union[Sequence[float], NDArray[np.floating[Any]]]
#: A placement (x, y, z, yaw) or (x, y, z, yaw, spin) in m, m, m, rad, rad.
At: TypeAlias = Union[
    Tuple[float, float, float, float],
    Tuple[float, float, float, float, float],
    Sequence[float],
    NDArray[np.floating[Any]],
]
#: What a placement search minimises (J).
Objective: TypeAlias = Literal[
    "supply", "drives", "mechanical", "mechanical_positive", "mechanical_abs"
]
#: Where regenerated energy goes (default: the drive file's).
Regeneration: TypeAlias = Literal["none", "per_axis", "dc_bus", "grid"]
#: The refinement of `optimise`.
Search: TypeAlias = Literal["nelder-mead", "pattern"]
#: How `optimise` evaluates a long repeating path.
Evaluation: TypeAlias = Literal["auto", "full", "reduced"]
#: The robust criterion of `optimise` with `uncertainty`.
Robust: TypeAlias = Literal["expected", "regret"]
#: A placement as returned: (x, y, z, yaw, spin) in m, m, m, rad, rad.
Placement5: TypeAlias = Tuple[float, float, float, float, float]

# ---------------------------------------------------------------------------------------------
# Result dictionaries (typing only)

class ReaderWarning(TypedDict):
    """One reader warning: the file, the line (None: the line is inside the message), the
    message."""

    file: str
    line: Optional[int]
    message: str

class EnergyPlacement(TypedDict):
    """The placement of an `energy` result, in m and degrees."""

    x_m: float
    y_m: float
    z_m: float
    yaw_deg: float
    nozzle_spin_deg: float

class EnergyResult(TypedDict):
    """`energy`'s result: the `printwatt energy --json` document plus exact figures and
    per-sample NumPy arrays (float64)."""

    schema_version: int
    robot: str
    input: str
    placement: EnergyPlacement
    print_time_s: float
    #: Where a joint limit bound and the path was slowed (docs/json.md).
    slowdowns: list[dict[str, Any]]
    #: Always None here (the command line's CSV file).
    output_csv: None
    #: The energy report: `total` and `joints[]`, J, W, N·m (docs/json.md).
    energy: dict[str, Any]
    warnings: list[ReaderWarning]
    #: Total supply energy, J (unrounded).
    supply_j: float
    #: Print time, s (unrounded).
    duration_s: float
    #: (dof,) J.
    joint_electrical_j: NDArray[np.float64]
    #: (dof,) J.
    joint_mechanical_j: NDArray[np.float64]
    #: (N,) s.
    t: NDArray[np.float64]
    #: (N, dof) rad.
    q: NDArray[np.float64]
    #: (N, dof) rad/s.
    qd: NDArray[np.float64]
    #: (N, dof) rad/s².
    qdd: NDArray[np.float64]
    #: (N, dof) N·m.
    tau: NDArray[np.float64]
    #: (N, dof) A.
    current: NDArray[np.float64]
    #: (N, dof) W.
    p_mech: NDArray[np.float64]
    #: (N, dof) W.
    p_el: NDArray[np.float64]
    #: (N,) W.
    p_supply: NDArray[np.float64]

class SweepResult(TypedDict):
    """`sweep`'s result."""

    schema_version: int
    objective: str
    #: (nx,) m.
    xs: NDArray[np.float64]
    #: (ny,) m.
    ys: NDArray[np.float64]
    #: (nx, ny) J, NaN where infeasible.
    energy_j: NDArray[np.float64]
    #: nx lists of ny: None (feasible) or the reason's name.
    reason: list[list[Optional[str]]]
    #: The best evaluated placement (as `sweep --json`'s `best`), or None.
    best: Optional[dict[str, Any]]
    feasible: int
    infeasible_by_reason: dict[str, int]
    #: Every evaluated placement, x-major (as `sweep --json`'s `rows`).
    rows: list[dict[str, Any]]

class OptimiseResult(TypedDict):
    """`optimise`'s result."""

    schema_version: int
    objective: str
    placement: Placement5
    #: The objective at the answer, J.
    energy_j: float
    supply_j: float
    duration_s: float
    best: dict[str, Any]
    best_grid: dict[str, Any]
    #: (grid evaluations, refinement evaluations).
    evaluations: Tuple[int, int]
    placements: int
    feasible: int
    infeasible_by_reason: dict[str, int]
    search: Optional[dict[str, Any]]
    #: The objective after each refinement step, J.
    history_j: NDArray[np.float64]
    #: The document `printwatt optimise --json` prints (docs/json.md).
    summary: dict[str, Any]

class CompareResult(TypedDict):
    """`compare`'s result: the `printwatt compare --json` document (docs/json.md)."""

    schema_version: int
    warnings: list[ReaderWarning]
    calibration: Optional[str]
    log: str
    signal: str
    unit: str
    samples: int
    duration_s: float
    effects: list[str]
    channels: list[dict[str, Any]]
    total: dict[str, Any]
    worst_windows: list[dict[str, Any]]
    failures: list[dict[str, Any]]
    profiles: list[dict[str, Any]]
    regimes: list[dict[str, Any]]
    regimes_all: list[dict[str, Any]]

class DiagnoseResult(TypedDict):
    """`diagnose`'s result: the `printwatt diagnose --json` document (docs/json.md)."""

    schema_version: int
    warnings: list[ReaderWarning]
    calibration: Optional[str]
    base_rmse: float
    folds: int
    noise_floor: float
    noise_floor_per_channel: list[float]
    correlation_time_s: float
    block_length_s: float
    model_effects: list[str]
    candidates: list[dict[str, Any]]
    best: Optional[str]
    unexplained: list[dict[str, Any]]
    verdict: str
    not_observable: list[Any]

class IdentifyResult(TypedDict):
    """`identify`'s result: the `printwatt identify --json` document (docs/json.md)."""

    schema_version: int
    warnings: list[ReaderWarning]
    #: `validation`, `ladder[]`, `params[]`, … (docs/json.md).
    identification: dict[str, Any]
    #: The calibrated robot (drive .toml) written.
    calibrated_robot: str
    #: The calibration summary of the robot given, or None for a nominal robot.
    started_from: Optional[str]
    refitted_from_earlier_rounds: list[str]

class StationsResult(TypedDict):
    """`stations`' result: the plan of `printwatt stations --json` (docs/json.md; one entry
    of `segments` per station) plus `at` and `footprint_m`."""

    schema_version: int
    relocations: int
    relocation_distance_m: float
    ways: list[dict[str, Any]]
    relocation_j: float
    energy_j: float
    total_j: float
    segments: list[dict[str, Any]]
    units: list[dict[str, Any]]
    stats: dict[str, Any]
    #: Per segment, the placement the station amounts to (what `energy` takes).
    at: list[Placement5]
    #: Radius of the floor disc a station occupies, m.
    footprint_m: float

# ---------------------------------------------------------------------------------------------
# The module

class PrintwattError(Exception):
    """An error from printwatt: bad input (the message names the file and the line, column or
    field), an infeasible placement, or a model error. The message is the library's."""

class Robot:
    """A robot arm: kinematics, inertias and (with a drive file) motors, gears, friction,
    payload and tool. Load one with `load_robot`."""

    @property
    def name(self) -> str: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def source(self) -> str: ...
    @property
    def reach_m(self) -> float: ...
    @property
    def warnings(self) -> list[str]: ...

class Toolpath:
    """A toolpath in its part frame (m, m/s), from `load_path` or `path_from_points`."""

    @property
    def source(self) -> str: ...
    @property
    def moves(self) -> int: ...
    @property
    def length_m(self) -> float: ...
    @property
    def print_length_m(self) -> float: ...
    def points(self) -> NDArray[np.float64]:
        """The start point and every move's end point, (N+1, 3) m."""
    def speeds(self) -> NDArray[np.float64]:
        """Commanded TCP speed of every move, (N,) m/s."""
    @property
    def warnings(self) -> list[str]: ...

def load_robot(robot: StrPath, tool: Optional[StrPath] = None) -> Robot:
    """A shipped robot's name, a robot directory, a .urdf or a drive .toml; `tool`: a tool
    preset .toml."""

def shipped_robots() -> list[str]:
    """Names of the shipped robots, sorted."""

def load_path(
    file: StrPath,
    print_speed: float = 0.1,
    travel_speed: float = 0.25,
    zone: float = 0.005,
    path_units: Optional[Literal["mm", "m"]] = None,
    scale: float = 1.0,
    proc: Optional[str] = None,
) -> Toolpath:
    """Read a G-code, CSV or RAPID toolpath (speeds m/s, zone m); `proc`: the RAPID
    procedure to read instead of `main`."""

def path_from_points(
    points: ArrayLike, speed: float, zone: float = 0.005, name: str = "points"
) -> Toolpath:
    """A printing toolpath through (N, 3) points in m at `speed` m/s."""

def energy(
    robot: Union[Robot, StrPath],
    path: Union[Toolpath, StrPath],
    at: At,
    *,
    period: float = 0.004,
    accel: float = 1.0,
    jerk: float = 10.0,
    regeneration: Optional[Regeneration] = None,
    payload: bool = True,
    friction: bool = True,
    proc: Optional[str] = None,
) -> EnergyResult:
    """The energy of `path` printed at placement `at` (x, y, z, yaw[, spin]) m and rad."""

def sweep(
    robot: Union[Robot, StrPath],
    path: Union[Toolpath, StrPath],
    xs: Floats,
    ys: Floats,
    *,
    z: float = 0.0,
    yaw: float = 0.0,
    spin: float = 0.0,
    objective: Objective = "supply",
    period: float = 0.004,
    accel: float = 1.0,
    jerk: float = 10.0,
    regeneration: Optional[Regeneration] = None,
    payload: bool = True,
    friction: bool = True,
    joint_margin: float = 0.05235987755982989,
    wrist_margin: float = 0.08726646259971647,
    collisions: bool = True,
    check_every: int = 10,
    proc: Optional[str] = None,
) -> SweepResult:
    """Evaluate the placements of `path` on the grid `xs` × `ys` (m)."""

def optimise(
    robot: Union[Robot, StrPath],
    path: Union[Toolpath, StrPath],
    *,
    xs: Optional[Floats] = None,
    ys: Optional[Floats] = None,
    zs: Optional[Floats] = None,
    yaws: Optional[Floats] = None,
    spins: Optional[Floats] = None,
    objective: Objective = "supply",
    tolerance: Optional[Tuple[float, float, float]] = None,
    z_bounds: Optional[Tuple[float, float]] = None,
    max_evals: int = 120,
    seed: int = 42,
    fixed_yaw: bool = False,
    fixed_spin: bool = False,
    search: Search = "nelder-mead",
    evaluation: Evaluation = "auto",
    baseline: Optional[At] = None,
    uncertainty: Optional[int] = None,
    robust: Robust = "expected",
    prints_per_year: float = 1000.0,
    grid_kg_co2_per_kwh: float = 0.4,
    pareto: bool = False,
    margin_trade: bool = True,
    period: float = 0.004,
    accel: float = 1.0,
    jerk: float = 10.0,
    regeneration: Optional[Regeneration] = None,
    payload: bool = True,
    friction: bool = True,
    joint_margin: float = 0.05235987755982989,
    wrist_margin: float = 0.08726646259971647,
    collisions: bool = True,
    check_every: int = 10,
    proc: Optional[str] = None,
) -> OptimiseResult:
    """The minimum-energy placement of `path`, as `printwatt optimise` finds it."""

def compare(
    robot: Union[Robot, StrPath],
    log: StrPath,
    *,
    effects: Optional[str] = None,
    without: Optional[str] = None,
    columns: Optional[str] = None,
) -> CompareResult:
    """Compare the model with a measured log."""

def diagnose(
    robot: Union[Robot, StrPath],
    log: StrPath,
    *,
    folds: int = 5,
    effects: Optional[str] = None,
    without: Optional[str] = None,
    columns: Optional[str] = None,
) -> DiagnoseResult:
    """Rank the catalogue's effects by how much of the residual on `log` each explains."""

def identify(
    robot: StrPath,
    log: StrPath,
    effects: str,
    *,
    validate_log: Optional[StrPath] = None,
    drive_out: Optional[StrPath] = None,
    force: bool = False,
    columns: Optional[str] = None,
    out: Optional[StrPath] = None,
) -> IdentifyResult:
    """Fit the parameters of `effects` on `log` and write the calibrated robot (and, with
    `out`, the round's report); a physically implausible fit raises PrintwattError."""

def stations(
    robot: Union[Robot, StrPath],
    path: Union[Toolpath, StrPath],
    *,
    relocation_cost: float,
    relocation_cost_per_m: float = 0.0,
    station_step: float = 0.5,
    track: Optional[Tuple[Tuple[float, float], Tuple[float, float]]] = None,
    headings: Optional[Sequence[float]] = None,
    z: float = -0.5,
    spin: float = 0.0,
    footprint: Optional[float] = None,
    objective: Objective = "supply",
    period: float = 0.004,
    accel: float = 1.0,
    jerk: float = 10.0,
    regeneration: Optional[Regeneration] = None,
    payload: bool = True,
    friction: bool = True,
    joint_margin: float = 0.05235987755982989,
    wrist_margin: float = 0.08726646259971647,
    collisions: bool = True,
    check_every: int = 10,
    proc: Optional[str] = None,
) -> StationsResult:
    """A multi-station plan for a path larger than one placement's reach."""
