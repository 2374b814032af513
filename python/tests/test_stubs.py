"""The type stub (python/printwatt.pyi, shipped in the wheel with py.typed) cannot drift from
the module: the same names, the same parameters and defaults, and the keys of every result.
"""

import ast
import inspect
import math
import subprocess
from pathlib import Path

import pytest

import printwatt as pw

ROOT = Path(__file__).resolve().parents[2]
STUB = ROOT / "python" / "printwatt.pyi"


def stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"))


def typing_only(node):
    """A name the stub declares for type checkers only: a TypedDict or a TypeAlias."""
    if isinstance(node, ast.ClassDef):
        return any(isinstance(b, ast.Name) and b.id == "TypedDict" for b in node.bases)
    if isinstance(node, ast.AnnAssign):
        return isinstance(node.annotation, ast.Name) and node.annotation.id == "TypeAlias"
    return False


def stub_names():
    """(exported names, typing-only names) declared at the stub's top level."""
    exported, typing_names = set(), set()
    for node in stub_tree().body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            name = node.name
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            name = node.target.id
        else:
            continue
        (typing_names if typing_only(node) else exported).add(name)
    return exported, typing_names


def typed_dicts():
    """TypedDict name -> its keys, from the stub."""
    out = {}
    for node in stub_tree().body:
        if isinstance(node, ast.ClassDef) and typing_only(node):
            out[node.name] = {
                s.target.id for s in node.body
                if isinstance(s, ast.AnnAssign) and isinstance(s.target, ast.Name)
            }
    return out


def stub_functions():
    return {n.name: n for n in stub_tree().body if isinstance(n, ast.FunctionDef)}


def test_stub_lists_every_export():
    exported, typing_names = stub_names()
    module = set(pw.__all__)
    assert exported == module, (
        f"in the module, not the stub: {sorted(module - exported)}; "
        f"in the stub, not the module: {sorted(exported - module)}"
    )
    # The typing-only names are no attributes at run time (they cannot shadow one).
    assert typing_names and not (typing_names & set(dir(pw))), sorted(typing_names & set(dir(pw)))
    # Every class's public attributes are in the stub.
    classes = {n.name: n for n in stub_tree().body if isinstance(n, ast.ClassDef)}
    for cls in ("Robot", "Toolpath"):
        stubbed = {f.name for f in classes[cls].body if isinstance(f, ast.FunctionDef)}
        real = {a for a in dir(getattr(pw, cls)) if not a.startswith("_")}
        assert stubbed == real, (cls, sorted(stubbed ^ real))


def test_stub_signatures_and_defaults_are_the_modules():
    for name, fn in stub_functions().items():
        sig = inspect.signature(getattr(pw, name))
        a = fn.args
        want = []
        for p in a.posonlyargs + a.args:
            want.append((p.arg, "POSITIONAL_OR_KEYWORD"))
        for p in a.kwonlyargs:
            want.append((p.arg, "KEYWORD_ONLY"))
        got = [(p.name, p.kind.name) for p in sig.parameters.values()]
        assert got == want, (name, got, want)
        defaults = dict(zip([p.arg for p in a.args][len(a.args) - len(a.defaults):], a.defaults))
        defaults.update({p.arg: d for p, d in zip(a.kwonlyargs, a.kw_defaults) if d is not None})
        for p in sig.parameters.values():
            assert p.default is not Ellipsis, f"{name}({p.name}=...): give a literal default"
            if p.name in defaults:
                assert p.default == ast.literal_eval(defaults[p.name]), (name, p.name)
            else:
                assert p.default is inspect.Parameter.empty, (name, p.name, p.default)


def test_results_have_the_keys_the_stub_lists(tmp_path):
    """Each function's result has exactly the keys of its TypedDict in the stub."""
    td = typed_dicts()
    returns = {n: f.returns.id for n, f in stub_functions().items()
               if isinstance(f.returns, ast.Name) and f.returns.id in td}
    robot = pw.load_robot("abb_irb6700_200_260")
    path = pw.load_path(ROOT / "paths" / "default.gcode")
    at = (1.7, 0.0, 0.0, math.pi / 2)
    subprocess.run(
        [str(ROOT / "target" / "release" / "printwatt"), "simulate", "--robot",
         "abb_irb4600_40_255", "--excite", "8", "--hidden", "coulomb=30", "--signal", "tau",
         "--noise", "2", "--rate", "100", "--seed", "7", "--out", str(tmp_path)],
        check=True, capture_output=True,
    )
    log = tmp_path / "log.csv"
    wall = tmp_path / "wall.gcode"
    wall.write_text("G21\nG90\nG0 X0 Y0 Z20 F12000\nM3\nG1 X1500 Y0 F9000\nM5\nG0 Z70\n"
                    "G0 X1500\nG0 Z20\nM3\nG1 X3000\nM5\n")
    results = {
        "energy": pw.energy(robot, path, at),
        "sweep": pw.sweep(robot, path, [1.7], [0.0], yaw=math.pi / 2),
        "optimise": pw.optimise(robot, path, xs=[1.6, 1.8], ys=[0.0], zs=[0.0],
                                yaws=[math.pi / 2], max_evals=2, tolerance=(0.0, 0.0, 0.0),
                                wrist_margin=0.0),
        "compare": pw.compare("abb_irb4600_40_255", log),
        "diagnose": pw.diagnose("abb_irb4600_40_255", log, folds=3),
        "identify": pw.identify("abb_irb4600_40_255", log, "coulomb",
                                drive_out=tmp_path / "cal.toml"),
        "stations": pw.stations(robot, pw.load_path(wall), relocation_cost=5000.0,
                                track=((-0.5, -1.2), (3.5, -1.2)), wrist_margin=0.0),
    }
    assert set(results) == set(returns), sorted(set(returns) ^ set(results))
    for name, r in results.items():
        keys = td[returns[name]]
        assert set(r) == keys, (name, sorted(set(r) - keys), sorted(keys - set(r)))
    # The nested dictionaries typed in the stub.
    assert set(results["energy"]["placement"]) == td["EnergyPlacement"]
    for w in results["energy"]["warnings"]:
        assert set(w) == td["ReaderWarning"]


def test_a_placement_given_as_a_string_is_a_type_error_naming_the_argument():
    robot = pw.load_robot("abb_irb6700_200_260")
    path = pw.load_path(ROOT / "paths" / "default.gcode")
    with pytest.raises(TypeError, match=r"^at: expected a sequence \(x, y, z, yaw\).*str"):
        pw.energy(robot, path, "1.7,0,0,1.57")
    with pytest.raises(TypeError, match=r"^at: .*dict"):
        pw.energy(robot, path, {"x": 1.7})
    with pytest.raises(TypeError, match=r"^baseline: expected a sequence"):
        pw.optimise(robot, path, xs=[1.7], ys=[0.0], zs=[0.0], yaws=[0.0],
                    baseline="1.7,0,0,0")
    with pytest.raises(TypeError, match=r"^xs: expected a sequence of numbers \(m\)"):
        pw.sweep(robot, path, "1.7", [0.0])
    # A NumPy array and a list still work.
    import numpy as np
    e = pw.energy(robot, path, np.array([1.7, 0.0, 0.0, math.pi / 2]))
    assert e["supply_j"] > 0


def test_the_wheel_ships_the_stub_and_py_typed():
    pkg = Path(pw.__file__).parent
    assert (pkg / "py.typed").is_file(), pkg
    stub = pkg / "__init__.pyi"
    assert stub.is_file(), sorted(p.name for p in pkg.iterdir())
    assert stub.read_text(encoding="utf-8") == STUB.read_text(encoding="utf-8")
