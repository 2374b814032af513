"""Every function and class of printwatt used as docs/python.md documents it, for the type
checker: `.ci/run` runs `mypy --strict` on this file and on python/examples/ against the
installed wheel's stub (printwatt.pyi). Not a test (pytest does not collect it); running it
does the work too: `python python/tests/typing_check.py` (a few seconds).
"""

from __future__ import annotations

import math
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

import printwatt as pw

if TYPE_CHECKING:
    from printwatt import (
        CompareResult,
        DiagnoseResult,
        EnergyResult,
        IdentifyResult,
        OptimiseResult,
        StationsResult,
        SweepResult,
    )

ROOT = Path(__file__).resolve().parents[2]
ROBOT = "abb_irb6700_200_260"
PATH = ROOT / "paths" / "default.gcode"


def robot_and_path() -> tuple[pw.Robot, pw.Toolpath]:
    names: list[str] = pw.shipped_robots()
    assert ROBOT in names
    robot = pw.load_robot(ROBOT)
    dof: int = robot.dof
    joints: list[str] = robot.joint_names
    reach: float = robot.reach_m
    assert dof == len(joints) and reach > 0.0
    src: str = robot.source
    warnings: list[str] = robot.warnings
    assert src and isinstance(warnings, list) and robot.name
    path = pw.load_path(PATH, print_speed=0.1, travel_speed=0.25, zone=0.005)
    pts: NDArray[np.float64] = path.points()
    speeds: NDArray[np.float64] = path.speeds()
    assert pts.shape == (path.moves + 1, 3) and speeds.shape == (path.moves,)
    assert path.length_m >= path.print_length_m > 0.0 and path.source
    assert isinstance(path.warnings, list)
    return robot, path


def energy(robot: pw.Robot, path: pw.Toolpath) -> float:
    e: EnergyResult = pw.energy(robot, path, (1.7, 0.0, 0.0, math.pi / 2), period=0.004)
    supply: float = e["supply_j"]
    q: NDArray[np.float64] = e["q"]
    assert q.shape[1] == robot.dof and e["placement"]["yaw_deg"] == 90.0
    for w in e["warnings"]:
        assert w["message"]
    # A path from points, a path file given by name, a robot given by name.
    wall = pw.path_from_points(
        np.array([[0.0, 0.0, 0.0], [0.6, 0.0, 0.0], [0.6, 0.3, 0.0]]), 0.1, name="wall"
    )
    e2 = pw.energy(ROBOT, wall, [1.7, 0.0, 0.0, math.pi / 2, 0.0], regeneration="dc_bus")
    assert e2["duration_s"] > 0.0
    return supply


def sweep(robot: pw.Robot, path: pw.Toolpath) -> None:
    s: SweepResult = pw.sweep(
        robot, path, [1.6, 1.7], np.array([0.0]), yaw=math.pi / 2, objective="drives"
    )
    grid: NDArray[np.float64] = s["energy_j"]
    assert grid.shape == (2, 1) and len(s["reason"]) == 2 and s["feasible"] >= 0


def optimise(robot: pw.Robot, path: pw.Toolpath) -> None:
    o: OptimiseResult = pw.optimise(
        robot,
        path,
        xs=[1.6, 1.8],
        ys=[0.0],
        zs=[0.0],
        yaws=[math.pi / 2],
        max_evals=4,
        tolerance=(0.0, 0.0, 0.0),
        search="pattern",
        wrist_margin=0.0,
    )
    x, y, z, yaw, spin = o["placement"]
    grid_evals, refine_evals = o["evaluations"]
    assert o["energy_j"] > 0.0 and grid_evals == 2 and refine_evals >= 0


def measured(tmp: Path) -> None:
    robot = "abb_irb4600_40_255"
    subprocess.run(
        [str(ROOT / "target" / "release" / "printwatt"), "simulate", "--robot", robot,
         "--excite", "8", "--hidden", "coulomb=30", "--signal", "tau", "--noise", "2",
         "--rate", "100", "--seed", "7", "--out", str(tmp)],
        check=True, capture_output=True,
    )
    log = tmp / "log.csv"
    c: CompareResult = pw.compare(robot, log, without="coulomb")
    rmse: float = c["total"]["rmse"]
    d: DiagnoseResult = pw.diagnose(pw.load_robot(robot), log, folds=3)
    best: str | None = d["best"]
    i: IdentifyResult = pw.identify(robot, log, "coulomb", drive_out=tmp / "cal.toml")
    written: str = i["calibrated_robot"]
    assert rmse > 0.0 and best and Path(written).is_file()


def stations(robot: pw.Robot, tmp: Path) -> None:
    g = tmp / "wall.gcode"
    g.write_text("G21\nG90\nG0 X0 Y0 Z20 F12000\nM3\nG1 X1500 Y0 F9000\nM5\nG0 Z70\n"
                 "G0 X1500\nG0 Z20\nM3\nG1 X3000\nM5\n")
    p: StationsResult = pw.stations(robot, pw.load_path(g), relocation_cost=5000.0,
                                    track=((-0.5, -1.2), (3.5, -1.2)), wrist_margin=0.0)
    for at in p["at"]:
        x, y, z, yaw, spin = at
    assert p["total_j"] >= p["energy_j"] and p["footprint_m"] > 0.0


def errors(robot: pw.Robot, path: pw.Toolpath) -> None:
    try:
        pw.energy(robot, path, (9.0, 0.0, 0.0, 0.0))
    except pw.PrintwattError as e:
        assert "infeasible" in str(e)
    version: str = pw.__version__
    assert version


def main() -> None:
    robot, path = robot_and_path()
    energy(robot, path)
    sweep(robot, path)
    optimise(robot, path)
    errors(robot, path)
    with tempfile.TemporaryDirectory() as t:
        measured(Path(t))
        stations(robot, Path(t))
    print("typing_check: every documented use ran", file=sys.stderr)


if __name__ == "__main__":
    main()
