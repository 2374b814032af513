"""Parity of the Python module and the command line: each Python function and the binary run
on the same inputs give the same answer (placement, energies to the JSON's printed digits).
Both convert their arguments into the same library job and show its outcome, so a difference
is a front end taking its own route.

The binary is `target/release/printwatt` (`PRINTWATT_BIN` overrides it), as in
test_printwatt.py.
"""

import json
import math
import os
import subprocess
from pathlib import Path

import pytest

import printwatt as pw

ROOT = Path(__file__).resolve().parents[2]
ROBOT = "abb_irb6700_200_260"
PATH = ROOT / "paths" / "default.gcode"
EXE = Path(os.environ.get("PRINTWATT_BIN", ROOT / "target" / "release" / "printwatt"))

# A small optimisation: 18 grid placements at one bed height (the optimise_small transcript's).
XS, YS, ZS = [1.4, 1.6, 1.8], [-0.2, 0.0, 0.2], [0.2]
YAWS_DEG = [0.0, 90.0]


def cli(*args, cwd=None):
    """Run the binary with --json; the parsed document."""
    assert EXE.is_file(), f"{EXE}: build the binary first (cargo build --release)"
    out = subprocess.run(
        [str(EXE), *args, "--json"], cwd=cwd, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def shown(v):
    """`v` as the JSON shows it: 9 significant digits (docs/json.md)."""
    return float(f"{v:.8e}")


def same_numbers(py, js, where=""):
    """Every field of the binary's document `js` is in `py` with the same value."""
    if isinstance(js, dict):
        for k, v in js.items():
            if k == "warnings":
                continue
            assert k in py, f"{where}.{k} missing from the Python answer"
            same_numbers(py[k], v, f"{where}.{k}")
    elif isinstance(js, list):
        assert len(py) == len(js), where
        for i, (a, b) in enumerate(zip(py, js)):
            same_numbers(a, b, f"{where}[{i}]")
    elif isinstance(js, float):
        assert shown(py) == js, f"{where}: Python {py}, command line {js}"
    else:
        assert py == js, f"{where}: Python {py!r}, command line {js!r}"


def grid_flags():
    return [
        "--path", str(PATH),
        "--x", ",".join(map(str, XS)),
        "--y", ",".join(map(str, YS)),
        "--z", ",".join(map(str, ZS)),
        "--yaw", ",".join(str(int(y)) for y in YAWS_DEG),
        "--no-report",
    ]


def py_grid():
    return dict(xs=XS, ys=YS, zs=ZS, yaws=[math.radians(y) for y in YAWS_DEG])


def same_optimisation(py, doc):
    """The Python answer and the binary's document agree: the placement, its figures, the
    baseline, the savings and the search, to the printed digits."""
    best = doc["optimise"]["best"]
    same_numbers(py["best"], best, "best")
    p = best["placement"]
    assert [shown(v) for v in py["placement"][:3]] == [p["x_m"], p["y_m"], p["z_m"]]
    assert shown(py["energy_j"]) == best["outcome"]["energy_j"]
    # The whole `optimise --json` document but the facts of the front end (the path as named).
    for k in ("optimise", "baseline", "rows"):
        if k in doc:
            same_numbers(py["summary"][k], doc[k], k)


def test_optimise_with_the_defaults_is_the_cli_answer():
    """The same route and the same defaults: Nelder–Mead, 120 evaluations, seed 42, ±20 mm
    and ±1°, the baseline at the centre of the feasible region with its tolerance check."""
    py = pw.optimise(ROBOT, str(PATH), **py_grid())
    doc = cli("optimise", *grid_flags())
    same_optimisation(py, doc)
    assert py["summary"]["optimise"].get("savings") is not None


def test_optimise_pattern_search_budget_and_baseline_are_the_cli_answer():
    at = (1.6, 0.0, 0.2, math.radians(90.0))
    py = pw.optimise(ROBOT, str(PATH), **py_grid(), search="pattern", max_evals=15, seed=7,
                     tolerance=(0.0, 0.0, 0.0), baseline=at)
    doc = cli("optimise", *grid_flags(), "--search", "pattern", "--max-evals", "15",
              "--seed", "7", "--tolerance", "0,0", "--baseline", "1.6,0,0.2,90")
    same_optimisation(py, doc)


def test_optimise_uncertainty_study_is_the_cli_answer():
    py = pw.optimise(ROBOT, str(PATH), **py_grid(), max_evals=10, tolerance=(0.0, 0.0, 0.0),
                     uncertainty=4)
    doc = cli("optimise", *grid_flags(), "--max-evals", "10", "--tolerance", "0,0",
              "--uncertainty", "4")
    same_optimisation(py, doc)
    assert py["summary"]["optimise"]["uncertainty"] is not None


def test_optimise_pareto_is_the_cli_answer():
    py = pw.optimise(ROBOT, str(PATH), **py_grid(), max_evals=10, pareto=True)
    doc = cli("optimise", *grid_flags(), "--max-evals", "10", "--pareto")
    same_optimisation(py, doc)
    pts = py["summary"]["optimise"]["decision"]["pareto"]
    assert [p["scale"] for p in pts] == [0.5, 0.75, 1.0, 1.5, 2.0]
    assert any(p["pareto"] for p in pts)


def test_energy_is_the_cli_answer():
    at = (1.7, 0.0, 0.0, math.radians(90.0))
    py = pw.energy(ROBOT, str(PATH), at)
    doc = cli("energy", "--path", str(PATH), "--at", "1.7,0,0,90")
    same_numbers(py["energy"], doc["energy"], "energy")
    assert shown(py["print_time_s"]) == doc["print_time_s"]


def test_identify_writes_the_calibrated_robot_as_the_cli_does(tmp_path, monkeypatch):
    robot = "abb_irb4600_40_255"
    subprocess.run(
        [str(EXE), "simulate", "--robot", robot, "--excite", "8", "--hidden", "coulomb=30",
         "--signal", "tau", "--noise", "2", "--rate", "100", "--seed", "7",
         "--out", str(tmp_path)],
        check=True, capture_output=True,
    )
    log = tmp_path / "log.csv"
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    doc = cli("identify", "--robot", robot, "--log", str(log), "--effects", "coulomb",
              cwd=tmp_path / "cli")
    monkeypatch.chdir(tmp_path / "py")
    py = pw.identify(robot, log, "coulomb")
    same_numbers(py["identification"], doc["identification"], "identification")
    cli_file = Path(doc["calibrated_robot"])
    py_file = Path(py["calibrated_robot"])
    assert cli_file.name == py_file.name and cli_file.name.endswith(".calibrated.toml")
    assert (tmp_path / "cli" / cli_file).is_file() and (tmp_path / "py" / py_file).is_file()
    assert (tmp_path / "cli" / cli_file).read_text() == (tmp_path / "py" / py_file).read_text()
    # A second round does not replace it unless asked, as the command line.
    with pytest.raises(pw.PrintwattError, match="exists"):
        pw.identify(robot, log, "coulomb")
