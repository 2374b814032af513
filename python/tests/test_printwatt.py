"""Tests of the printwatt Python package (the built wheel), run by .ci/run with pytest.

Figures are checked against the command-line binary (`target/release/printwatt`, built by
`cargo test --release` before this runs; `PRINTWATT_BIN` overrides the path) on the same
inputs: both call the same library, so the Python figures (full precision) round to the
JSON's (9 significant digits) digit for digit.
"""

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import printwatt as pw

ROOT = Path(__file__).resolve().parents[2]
ROBOT = "abb_irb6700_200_260"
PATH = ROOT / "paths" / "default.gcode"
AT_DEG = (1.7, 0.0, 0.0, 90.0)  # the README's example placement: m, m, m, deg
AT = (1.7, 0.0, 0.0, math.radians(90.0))  # the same in SI for Python

sys.path.insert(0, str(ROOT / "python" / "examples"))
import best_placement  # noqa: E402  (the COMPAS-style example)


def cli(*args, cwd=None):
    """Run the printwatt binary with --json; returns the parsed document."""
    exe = Path(os.environ.get("PRINTWATT_BIN", ROOT / "target" / "release" / "printwatt"))
    assert exe.is_file(), f"{exe}: build the binary first (cargo build --release)"
    out = subprocess.run(
        [str(exe), *args, "--json"], cwd=cwd, capture_output=True, text=True, check=False
    )
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def rounds_to(exact, shown):
    """`exact` rounded to the JSON's 9 significant digits is `shown` (docs/json.md)."""
    return float(f"{exact:.8e}") == shown


def assert_same_numbers(py, js, where=""):
    """Every field of the CLI's JSON `js` is in `py` with the same value: a Python number, at
    full precision, rounds to the JSON's 9 significant digits exactly (a difference of one
    unit in the 9th digit would fail)."""
    if isinstance(js, dict):
        for k, v in js.items():
            if k == "warnings":
                continue
            assert k in py, f"{where}.{k} missing from the Python dict"
            assert_same_numbers(py[k], v, f"{where}.{k}")
    elif isinstance(js, list):
        assert len(py) == len(js), where
        for i, (a, b) in enumerate(zip(py, js)):
            assert_same_numbers(a, b, f"{where}[{i}]")
    elif isinstance(js, int) and not isinstance(js, bool) and isinstance(py, int):
        assert py == js, f"{where}: Python {py!r} vs CLI {js!r}"
    elif isinstance(js, (int, float)) and not isinstance(js, bool):
        assert rounds_to(float(py), float(js)), f"{where}: Python {py!r} vs CLI {js!r}"
    else:
        assert py == js, f"{where}: Python {py!r} vs CLI {js!r}"


@pytest.fixture(scope="module")
def robot():
    return pw.load_robot(ROBOT)


@pytest.fixture(scope="module")
def path():
    return pw.load_path(PATH)


@pytest.fixture(scope="module")
def at_readme(robot, path):
    return pw.energy(robot, path, AT)


def test_energy_at_a_placement_equals_the_cli_total_to_1e9(at_readme):
    doc = cli(
        "energy", "--robot", ROBOT, "--path", str(PATH),
        "--at", ",".join(str(v) for v in AT_DEG),
    )
    total_cli = doc["energy"]["total"]["supply_j"]
    assert total_cli > 1000.0  # a real print, not an empty one
    # The JSON holds 9 significant digits, so "1e-9 relative" is below its resolution (one unit
    # of the 9th digit is up to 1e-8 relative): the exact Python figure must round to the
    # CLI's, and the dict's rounded figure must be the CLI's, digit for digit.
    assert rounds_to(at_readme["supply_j"], total_cli), (at_readme["supply_j"], total_cli)
    assert abs(at_readme["supply_j"] - total_cli) <= 5e-9 * total_cli
    assert rounds_to(at_readme["energy"]["total"]["supply_j"], total_cli)
    # The dict mirrors the JSON document: every field, every number.
    assert_same_numbers(at_readme["energy"], doc["energy"], "energy")
    assert rounds_to(at_readme["print_time_s"], doc["print_time_s"])
    assert at_readme["placement"] == pytest.approx(doc["placement"], rel=1e-15, abs=1e-12)


def test_result_dictionaries_keep_full_precision(at_readme):
    """The dictionaries that mirror a JSON document are not rounded to its 9 digits: the
    total in the document part is the exact figure, and the figures carry more digits than
    the JSON shows."""
    total = at_readme["energy"]["total"]["supply_j"]
    assert total == at_readme["supply_j"]
    numbers = []

    def walk(v):
        if isinstance(v, dict):
            for x in v.values():
                walk(x)
        elif isinstance(v, list):
            for x in v:
                walk(x)
        elif isinstance(v, float) and v != 0.0:
            numbers.append(v)

    walk(at_readme["energy"])
    finer = [v for v in numbers if float(f"{v:.8e}") != v]
    assert len(finer) > len(numbers) // 2, (len(finer), len(numbers))


def test_energy_arrays_have_numpy_shapes_and_dtypes(at_readme, robot):
    e = at_readme
    n = len(e["t"])
    assert n > 100
    for k in ("t", "p_supply"):
        assert e[k].shape == (n,) and e[k].dtype == np.float64, k
    for k in ("q", "qd", "qdd", "tau", "current", "p_mech", "p_el"):
        assert e[k].shape == (n, robot.dof) and e[k].dtype == np.float64, k
    assert e["joint_electrical_j"].shape == (robot.dof,)
    assert np.all(np.diff(e["t"]) > 0)
    assert e["t"][-1] == pytest.approx(e["duration_s"])
    # The arrays are the report's: the trapezoid of the supply power is the supply energy.
    assert np.trapezoid(e["p_supply"], e["t"]) == pytest.approx(e["supply_j"], rel=1e-9)
    # Mechanical power is tau * qd, sample by sample.
    assert np.allclose(e["p_mech"], e["tau"] * e["qd"], rtol=1e-12, atol=1e-9)


def test_path_from_points_matches_the_same_path_read_from_a_csv(robot, tmp_path):
    pts = np.array([[0.0, 0.0, 0.0], [0.6, 0.0, 0.0], [0.6, 0.4, 0.0], [0.0, 0.4, 0.0]])
    csv = tmp_path / "square.csv"
    csv.write_text("x[m],y[m],z[m],speed[m/s]\n" + "\n".join(f"{x},{y},{z},0.1" for x, y, z in pts))
    a = pw.energy(robot, pw.path_from_points(pts, 0.1), AT)
    b = pw.energy(robot, pw.load_path(csv), AT)
    assert a["supply_j"] == b["supply_j"]
    assert pw.path_from_points(pts, 0.1).points().shape == (4, 3)
    # float32 and lists are taken too (converted to float64).
    assert pw.path_from_points(pts.astype(np.float32).tolist(), 0.1).moves == 3


def test_load_path_states_csv_units_as_the_cli_does(tmp_path):
    csv = tmp_path / "unitless.csv"
    csv.write_text("x,y,z\n0,0,0\n0.6,0,0\n0.6,0.4,0\n")
    mm = pw.load_path(csv)
    assert any("mm assumed" in w for w in mm.warnings)
    m = pw.load_path(csv, path_units="m")
    assert not m.warnings
    assert abs(m.length_m - 1000.0 * mm.length_m) < 1e-9
    half = pw.load_path(csv, path_units="m", scale=0.5)
    assert abs(half.length_m - 0.5 * m.length_m) < 1e-12
    with pytest.raises(pw.PrintwattError, match="CSV paths only"):
        pw.load_path(PATH, path_units="m")


def test_bad_input_raises_printwatt_error_with_the_library_message(robot, tmp_path):
    bad = tmp_path / "bad.gcode"
    bad.write_text("G21\nG1 X10 Y0 F6000\nG1 X1O Y5\n")
    with pytest.raises(pw.PrintwattError, match=r"bad\.gcode:3"):
        pw.load_path(bad)
    with pytest.raises(pw.PrintwattError, match="(?i)no such file"):
        pw.load_path(tmp_path / "missing.gcode")
    with pytest.raises(pw.PrintwattError, match="did you mean 1.7 m"):
        pw.energy(robot, pw.load_path(PATH), (1700.0, 0.0, 0.0, 0.0))
    with pytest.raises(pw.PrintwattError, match=r"shipped robots: .*abb_irb6700_200_260"):
        pw.load_robot("abb_irb6700")
    with pytest.raises(pw.PrintwattError, match=r"row 1\).*not a finite"):
        pw.path_from_points([[0, 0, 0], [1, 0, float("nan")]], 0.1)
    with pytest.raises(pw.PrintwattError, match=r"\(N, 3\)"):
        pw.path_from_points(np.zeros((4, 2)), 0.1)
    with pytest.raises(pw.PrintwattError, match="speed"):
        pw.path_from_points([[0, 0, 0], [1, 0, 0]], 0.0)
    with pytest.raises(pw.PrintwattError, match=r"angles are in radians .* 1.5707963"):
        pw.energy(robot, pw.load_path(PATH), (1.7, 0.0, 0.0, 90.0))
    with pytest.raises(pw.PrintwattError, match="infeasible"):
        pw.energy(robot, pw.load_path(PATH), (9.0, 0.0, 0.0, 0.0))


def test_sweep_returns_a_grid_of_energies_equal_to_single_evaluations(robot, path):
    xs, ys = [1.4, 1.6, 1.7, 9.0], [-0.2, 0.2]
    # At z = 0 the wrist passes through q5 = 0 at 1.6 and 1.7 m: the default wrist margin (5°)
    # rejects them, a margin of 0 (rad) lets the wrist pass, as --wrist-margin 0 does.
    d = pw.sweep(robot, path, [1.7], [0.2], yaw=math.pi / 2)
    assert d["reason"][0] == ["wrist_singularity"]
    s = pw.sweep(robot, path, xs, ys, yaw=math.pi / 2, wrist_margin=0.0)
    assert s["energy_j"].shape == (4, 2) and s["energy_j"].dtype == np.float64
    assert s["xs"].tolist() == xs and s["ys"].tolist() == ys
    # 1.4 m keeps joint 3 too near its limit, 9 m is out of reach: NaN with the reason.
    assert np.isnan(s["energy_j"][0]).all() and s["reason"][0] == ["joint_limit_margin"] * 2
    assert np.isnan(s["energy_j"][3]).all() and s["reason"][3] == ["unreachable"] * 2
    assert np.isfinite(s["energy_j"][1:3]).all() and s["reason"][1] == [None, None]
    assert s["infeasible_by_reason"] == {"joint_limit_margin": 2, "unreachable": 2}
    assert s["best"]["placement"]["x_m"] == 1.6
    # The sweep's objective (supply) at a cell is the energy of that placement.
    e = pw.energy(robot, path, (1.7, 0.2, 0.0, math.pi / 2))
    assert s["energy_j"][2, 1] == pytest.approx(e["supply_j"], rel=1e-9)
    assert len(s["rows"]) == 8 and s["rows"][2]["outcome"]["status"] == "feasible"


def test_optimise_returns_the_best_placement_its_energy_and_the_reasons(robot):
    wall = pw.path_from_points([[0, 0, 0], [0.6, 0, 0], [0.6, 0.3, 0], [0, 0.3, 0]], 0.1)
    xs, ys = [1.0, 1.4, 1.8, 9.0], [-0.3, 0.0, 0.3]
    # A wrist margin of 0: near the base at z = 0 the wrist passes through q5 = 0, and the best
    # grid cell would fail its tolerance box under the default margin.
    o = pw.optimise(robot, wall, xs=xs, ys=ys, zs=[0.0], yaws=[0.0], max_evals=20,
                    wrist_margin=0.0)
    x, y, z, yaw, spin = o["placement"]
    assert 1.0 <= x <= 9.0 and -0.3 <= y <= 0.3 and z == 0.0
    # The answer is that placement's energy, and no worse than the grid cell it started from.
    assert o["energy_j"] == pytest.approx(pw.energy(robot, wall, o["placement"])["supply_j"], rel=1e-9)
    assert o["energy_j"] <= o["best_grid"]["outcome"]["energy_j"] * (1 + 1e-9)
    assert o["placements"] == 12 and o["infeasible_by_reason"]["unreachable"] == 3
    assert "passing through it is allowed" in o["search"]["wrist_margin"]
    assert o["feasible"] + sum(o["infeasible_by_reason"].values()) == 12
    assert o["search"]["method"].startswith("nelder-mead")
    # Bad search settings: the library's messages.
    with pytest.raises(pw.PrintwattError, match="at most 0.5 m and 45"):
        pw.optimise(robot, wall, xs=xs, ys=ys, zs=[0.0], yaws=[0.0], tolerance=(0.6, 0.0, 0.0))
    with pytest.raises(pw.PrintwattError, match="z bounds"):
        pw.optimise(robot, wall, xs=xs, ys=ys, zs=[0.0], yaws=[0.0], z_bounds=(0.5, 0.0))
    # Nothing feasible: the command's advice, as an error.
    with pytest.raises(pw.PrintwattError, match="unreachable"):
        pw.optimise(robot, wall, xs=[9.0], ys=[0.0], zs=[0.0], yaws=[0.0])


def test_compare_diagnose_identify_mirror_the_cli_json(tmp_path, monkeypatch):
    robot = "abb_irb4600_40_255"
    subprocess.run(
        [str(ROOT / "target" / "release" / "printwatt"), "simulate", "--robot", robot,
         "--excite", "8", "--hidden", "coulomb=30", "--signal", "tau", "--noise", "2",
         "--rate", "100", "--seed", "7", "--out", str(tmp_path)],
        check=True, capture_output=True,
    )
    log = tmp_path / "log.csv"
    assert_same_numbers(pw.compare(robot, log), cli("compare", "--robot", robot, "--log", str(log)))
    d = pw.diagnose(robot, log)
    assert_same_numbers(d, cli("diagnose", "--robot", robot, "--log", str(log)))
    assert d["best"] == "coulomb"
    out = tmp_path / "id"
    # The calibrated robot is written as the command line writes it: here, by default.
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    i = pw.identify(robot, log, "coulomb")
    assert i["calibrated_robot"].endswith(".calibrated.toml")
    assert (here / i["calibrated_robot"]).is_file() and not out.exists()
    doc = cli("identify", "--robot", robot, "--log", str(log), "--effects", "coulomb",
              "--out", str(out))
    assert_same_numbers(i["identification"], doc["identification"], "identification")
    # drive_out writes a calibrated robot that loads.
    cal = tmp_path / "cal.toml"
    i2 = pw.identify(robot, log, "coulomb", drive_out=cal)
    assert i2["calibrated_robot"] == str(cal)
    c = pw.compare(pw.load_robot(cal), log)
    assert c["total"]["rmse"] < 0.5 * d["base_rmse"]
    with pytest.raises(pw.PrintwattError, match="exists"):
        pw.identify(robot, log, "coulomb", drive_out=cal)


def test_identify_runs_the_cli_round_refusing_an_implausible_fit_and_writing_its_report(
        tmp_path, monkeypatch):
    """Python's identify is the CLI's round: a fit that is not physically plausible (a 1 kg
    payload 3 m out) raises and writes nothing, as `printwatt identify` refuses it; `out`
    writes the round's report as `--out` does."""
    robot = "abb_irb4600_40_255"
    exe = str(ROOT / "target" / "release" / "printwatt")
    subprocess.run(
        [exe, "simulate", "--robot", robot, "--excite", "8", "--hidden", "payload=-29:3",
         "--signal", "tau", "--noise", "1", "--rate", "250", "--seed", "5",
         "--out", str(tmp_path / "p")],
        check=True, capture_output=True,
    )
    monkeypatch.chdir(tmp_path)
    with pytest.raises(pw.PrintwattError, match="not physically plausible.*payload:"):
        pw.identify(robot, tmp_path / "p" / "log.csv", "payload")
    assert not list(tmp_path.glob("*.calibrated.toml")), "nothing written"
    cli_out = subprocess.run(
        [exe, "identify", "--robot", robot, "--log", str(tmp_path / "p" / "log.csv"),
         "--effects", "payload", "--out", str(tmp_path / "cli")],
        capture_output=True, text=True,
    )
    assert cli_out.returncode == 1 and "not physically plausible" in cli_out.stderr
    # A plausible round with `out`: the report, the ladder and the calibrated robot there.
    subprocess.run(
        [exe, "simulate", "--robot", robot, "--excite", "8", "--hidden", "coulomb=30",
         "--signal", "tau", "--noise", "2", "--rate", "100", "--seed", "7",
         "--out", str(tmp_path / "c")],
        check=True, capture_output=True,
    )
    log = tmp_path / "c" / "log.csv"
    i = pw.identify(robot, log, "coulomb", out=tmp_path / "py")
    assert i["calibrated_robot"] == str(tmp_path / "py" / "abb_irb4600_40_255.calibrated.toml")
    cli("identify", "--robot", robot, "--log", str(log), "--effects", "coulomb",
        "--out", str(tmp_path / "cli2"))
    for f in ("report.html", "ladder.svg", "identify.json"):
        assert (tmp_path / "py" / f).is_file(), f
    assert (tmp_path / "py" / "ladder.md").read_text() == (tmp_path / "cli2" / "ladder.md").read_text()


def test_per_joint_effect_subsets_mean_what_they_mean_in_the_cli(tmp_path, monkeypatch):
    """`viscous[2]` in identify (joint 2 fitted, the others held at their prior) and in
    compare (the effect on joint 2 only), as the binary takes them."""
    robot = "abb_irb4600_40_255"
    subprocess.run(
        [str(ROOT / "target" / "release" / "printwatt"), "simulate", "--robot", robot,
         "--excite", "8", "--hidden", "viscous[2]=40", "--signal", "tau", "--noise", "1",
         "--rate", "100", "--seed", "3", "--out", str(tmp_path)],
        check=True, capture_output=True,
    )
    log = tmp_path / "log.csv"
    monkeypatch.chdir(tmp_path)  # identify writes the calibrated robot here
    i = pw.identify(robot, log, "viscous[2]")
    doc = cli("identify", "--robot", robot, "--log", str(log), "--effects", "viscous[2]",
              "--out", str(tmp_path / "id"))
    assert_same_numbers(i["identification"], doc["identification"], "identification")
    held = [h["name"] for h in i["identification"]["held_at_prior"]]
    assert "viscous.f_v[1]" in held and "viscous.f_v[2]" not in held
    for args in (dict(effects="viscous[2]"), dict(without="viscous[2]")):
        flags = [f"--{k}" for k in args] + list(args.values())
        assert_same_numbers(pw.compare(robot, log, **args),
                            cli("compare", "--robot", robot, "--log", str(log), *flags))


def test_stations_plans_a_floor_as_the_cli_does(robot, tmp_path):
    """Two 1.5 m wall pieces, stations along a track beside them: the same plan, energies and
    placements as `printwatt stations --json`; a track under the wall is refused."""
    g = tmp_path / "wall.gcode"
    g.write_text("G21\nG90\nG0 X0 Y0 Z20 F12000\nM3\nG1 X1500 Y0 F9000\nM5\nG0 Z70\n"
                 "G0 X1500\nG0 Z20\nM3\nG1 X3000\nM5\n")
    # From a track beside a straight wall the wrist passes through q5 = 0: a wrist margin of 0.
    p = pw.stations(robot, pw.load_path(g), relocation_cost=5000.0,
                    track=((-0.5, -1.2), (3.5, -1.2)), wrist_margin=0.0)
    doc = cli("stations", "--path", str(g), "--relocation-cost", "5000",
              "--track=-0.5,-1.2:3.5,-1.2", "--wrist-margin", "0")
    assert len(p["segments"]) == doc["stations"] and p["relocations"] == doc["relocations"]
    assert rounds_to(p["total_j"], doc["total_j"]) and rounds_to(p["energy_j"], doc["energy_j"])
    for mine, theirs, at in zip(p["segments"], doc["segments"], p["at"]):
        assert mine["units"] == theirs["units"]
        assert rounds_to(mine["station"]["x_m"], theirs["station"]["x_m"])
        assert rounds_to(mine["station"]["y_m"], theirs["station"]["y_m"])
        assert at[0] == pytest.approx(theirs["at"]["x_m"], abs=1e-9)
    assert p["footprint_m"] > 0 and p["stats"]["units"] == 2
    with pytest.raises(pw.PrintwattError, match="lies under the wall"):
        pw.stations(robot, pw.load_path(g), relocation_cost=5000.0,
                    track=((-0.5, 0.0), (3.5, 0.0)))


def test_compas_style_example_returns_the_robot_frame_in_design_coordinates():
    points, plane = best_placement.demo_wall()
    best = best_placement.best_placement(points, plane, **best_placement.DEMO_SEARCH)
    # The frame maps the designer's points to where printwatt printed them in the robot base
    # frame: base = Rz(yaw) · local + t.
    frame = best["robot_base"]
    o, xa, ya = (np.array(frame.point), np.array(frame.xaxis), np.array(frame.yaxis)) \
        if hasattr(frame, "point") else (np.array(v) for v in frame)
    r_wb = np.column_stack([xa, ya, np.cross(xa, ya)])
    in_base = (points - o) @ r_wb
    x, y, z, yaw, _ = best["placement"]
    c, s = math.cos(yaw), math.sin(yaw)
    expected = best["local_points"] @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]]) + [x, y, z]
    assert np.allclose(in_base, expected, atol=1e-9)
    # The energy is that of the placement.
    e = pw.energy(ROBOT, pw.path_from_points(best["local_points"], 0.1), best["placement"])
    assert best["energy_j"] == pytest.approx(e["supply_j"], rel=1e-9)
    with pytest.raises(ValueError, match="not vertical"):
        best_placement.best_placement(points, ((0, 0, 0), (1, 0, 0), (0, 0.6, 0.8)))


def test_readme_python_block_runs(capsys, monkeypatch):
    """The README's ```python block runs as written, from the repository root."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = text.split("```python\n")[1:]
    assert len(blocks) == 1, "one python block in the README"
    code = blocks[0].split("\n```", 1)[0]
    monkeypatch.chdir(ROOT)
    exec(compile(code, "README.md (python block)", "exec"), {})
    out = capsys.readouterr().out
    assert " J over " in out and "tau (" in out


RAPID = ROOT / "tests" / "data" / "rapid" / "two_workobjects.mod"
RAPID_AT_DEG = (1.6, 0.0, 0.5, 0.0)
RAPID_AT = (1.6, 0.0, 0.5, 0.0)


def test_load_path_proc_chooses_the_rapid_procedure_as_the_cli_does(robot):
    """`proc=` reads the named RAPID procedure instead of `main`, as `--proc` does; every
    path-taking function accepts it for a path given as a file, and refuses it for a path
    already loaded."""
    # The module's main chooses its path at run time: no entry without proc.
    with pytest.raises(pw.PrintwattError, match="rectangulo_mesa"):
        pw.load_path(RAPID)
    plano = pw.load_path(RAPID, proc="path_plano")
    inclinado = pw.load_path(RAPID, proc="PATH_INCLINADO")  # case-insensitive, as in RAPID
    assert plano.moves > 0 and inclinado.moves > 0
    assert plano.length_m != pytest.approx(inclinado.length_m)
    doc = cli(
        "energy", "--robot", ROBOT, "--path", str(RAPID), "--proc", "path_plano",
        "--at", ",".join(str(v) for v in RAPID_AT_DEG),
    )
    e_loaded = pw.energy(robot, plano, RAPID_AT)
    e_file = pw.energy(robot, RAPID, RAPID_AT, proc="path_plano")
    assert rounds_to(e_loaded["energy"]["total"]["supply_j"], doc["energy"]["total"]["supply_j"])
    assert e_file["supply_j"] == e_loaded["supply_j"]
    with pytest.raises(pw.PrintwattError, match="no procedure named 'nope'"):
        pw.load_path(RAPID, proc="nope")
    with pytest.raises(pw.PrintwattError, match="RAPID modules only"):
        pw.load_path(PATH, proc="main")
    with pytest.raises(pw.PrintwattError, match="already read"):
        pw.energy(robot, plano, RAPID_AT, proc="path_plano")
    s = pw.sweep(robot, RAPID, [1.5, 1.6], [0.0], z=0.5, proc="path_plano")
    assert np.isfinite(s["energy_j"]).any()
