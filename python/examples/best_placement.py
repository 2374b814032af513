"""Where to put the robot for a designer's toolpath: a COMPAS-style use of printwatt.

A 3DCP designer has a toolpath as a list of points in the model's coordinates (x, y, z in
metres, +z up, as in COMPAS or Rhino) and the plane of the print bed (an origin, an x-axis and
a y-axis, the way a COMPAS ``Frame`` holds them). ``best_placement`` asks printwatt for the
minimum-energy placement and hands it back in the designer's coordinates: the frame where the
robot's base must stand, plus the energy (J) and the print time (s).

With COMPAS installed, ``plane`` may be a ``compas.geometry.Frame`` and the frames returned are
``Frame`` objects; without it, plain ``(origin, xaxis, yaxis)`` tuples are taken and returned.
COMPAS is never required.

Run it: ``python python/examples/best_placement.py`` (a three-layer wall, small search grid;
a few seconds). The bed plane must be horizontal (its normal along +z): printwatt keeps the
nozzle vertical.
"""

import math
from typing import Any, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

import printwatt

Vec3 = Tuple[float, float, float]
# A plane or frame as plain tuples: (origin, xaxis, yaxis), each three floats (m).
PlainFrame = Tuple[Vec3, Vec3, Vec3]

_CompasFrame: Optional[Any]
try:  # COMPAS is optional: accepted and returned when it is importable.
    from compas.geometry import Frame as _CompasFrame  # type: ignore[import-not-found, unused-ignore, no-redef]
except ImportError:  # pragma: no cover - depends on the environment
    _CompasFrame = None


def _unit(v: ArrayLike, what: str) -> NDArray[np.float64]:
    a: NDArray[np.float64] = np.asarray(v, dtype=float)
    n = float(np.linalg.norm(a))
    if a.shape != (3,) or not np.isfinite(a).all() or n < 1e-12:
        raise ValueError(f"{what}: expected a non-zero 3-vector, got {a!r}")
    out: NDArray[np.float64] = a / n
    return out


def plane_axes(plane: Any) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(origin, R) of a plane given as a COMPAS Frame or (origin, xaxis, yaxis) in metres.

    R's columns are the plane's x, y and z (= x × y) axes, orthonormalised (the y-axis is made
    perpendicular to the x-axis, as COMPAS' Frame does).
    """
    if _CompasFrame is not None and isinstance(plane, _CompasFrame):
        origin, xaxis, yaxis = plane.point, plane.xaxis, plane.yaxis
    else:
        try:
            origin, xaxis, yaxis = plane
        except (TypeError, ValueError):
            raise ValueError(
                "plane: expected a compas.geometry.Frame or (origin, xaxis, yaxis) in m"
            ) from None
    o = np.asarray(origin, dtype=float)
    if o.shape != (3,) or not np.isfinite(o).all():
        raise ValueError(f"plane origin: expected three finite coordinates (m), got {origin!r}")
    x = _unit(xaxis, "plane xaxis")
    y: NDArray[np.float64] = np.asarray(yaxis, dtype=float) - np.dot(yaxis, x) * x
    y = _unit(y, "plane yaxis (parallel to the x-axis?)")
    z = np.cross(x, y)
    return o, np.column_stack([x, y, z])


def _frame_out(origin: ArrayLike, xaxis: ArrayLike, yaxis: ArrayLike) -> Any:
    """A COMPAS Frame if COMPAS is importable, else a PlainFrame."""
    o, x, y = (_vec3(v) for v in (origin, xaxis, yaxis))
    if _CompasFrame is not None:
        return _CompasFrame(o, x, y)
    plain: PlainFrame = (o, x, y)
    return plain


def _vec3(v: ArrayLike) -> Vec3:
    a = np.asarray(v, dtype=float)
    return (float(a[0]), float(a[1]), float(a[2]))


def _rz(a: float) -> NDArray[np.float64]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def best_placement(
    points: ArrayLike,
    plane: Any,
    robot: str = "abb_irb6700_200_260",
    speed: float = 0.1,
    zone: float = 0.005,
    **search: Any,
) -> dict[str, Any]:
    """The minimum-energy placement of a designer's toolpath, in the designer's coordinates.

    points: (N, 3) x, y, z in m in the designer's coordinates (+z up), printed in order at
        `speed` (m/s) with corners blended within `zone` (m).
    plane: the print bed's plane in the designer's coordinates, as a COMPAS Frame or
        (origin, xaxis, yaxis) in m; it must be horizontal (x-axis × y-axis along +z within
        1e-6), since the nozzle prints vertically.
    robot: a shipped robot's name or a robot path (see printwatt.load_robot).
    search: passed to printwatt.optimise (e.g. xs, ys, zs, yaws in m and rad, max_evals).

    Returns a dict:
      robot_base: the frame where the robot's base goes, in the designer's coordinates (m): a
          COMPAS Frame if COMPAS is importable, else (origin, xaxis, yaxis);
      bed_in_robot: the bed plane in the robot's base frame (the work object to program), same
          form;
      nozzle_spin: rotation of the nozzle about its vertical axis relative to the bed, rad;
      energy_j: the supply energy of the print at that placement, J;
      duration_s: the print time, s;
      placement: printwatt's (x, y, z, yaw, spin) in m, m, m, rad, rad;
      local_points: the toolpath in the bed frame (m), as printwatt printed it.
    """
    o, r = plane_axes(plane)
    if abs(r[2, 2] - 1.0) > 1e-6:
        raise ValueError(
            f"plane: its normal {tuple(r[:, 2])} is not vertical; printwatt prints with a "
            "vertical nozzle on a horizontal bed (give a plane whose x- and y-axes are horizontal)"
        )
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points: expected (N, 3) x, y, z in m, got shape {pts.shape}")
    local = (pts - o) @ r  # each row: R^T (p - o)
    path = printwatt.path_from_points(local, speed, zone=zone, name="designer points")
    res = printwatt.optimise(robot, path, **search)
    x, y, z, yaw, spin = res["placement"]
    # The bed (part) frame in the robot base frame: base = Rz(yaw) · part + t.
    t = np.array([x, y, z])
    rb = _rz(yaw)
    bed_in_robot = _frame_out(t, rb[:, 0], rb[:, 1])
    # The robot base in the designer's coordinates: world = plane ∘ (base → part).
    r_wb = r @ rb.T
    o_wb = o - r_wb @ t
    return {
        "robot_base": _frame_out(o_wb, r_wb[:, 0], r_wb[:, 1]),
        "bed_in_robot": bed_in_robot,
        "nozzle_spin": spin,
        "energy_j": res["supply_j"],
        "duration_s": res["duration_s"],
        "placement": res["placement"],
        "local_points": local,
    }


def demo_wall() -> Tuple[NDArray[np.float64], PlainFrame]:
    """A 0.8 m × 0.4 m rectangular wall of three 20 mm layers, in a designer's model where the
    bed sits at (10, 5, 0.3) m turned 30° about the vertical. Returns (points, plane)."""
    yaw = math.radians(30.0)
    o = np.array([10.0, 5.0, 0.3])
    x, y = np.array([math.cos(yaw), math.sin(yaw), 0.0]), np.array([-math.sin(yaw), math.cos(yaw), 0.0])
    corners = [(0.0, 0.0), (0.8, 0.0), (0.8, 0.4), (0.0, 0.4), (0.0, 0.0)]
    pts = [o + u * x + v * y + np.array([0.0, 0.0, 0.02 * layer]) for layer in range(3) for u, v in corners]
    return np.array(pts), (_vec3(o), _vec3(x), _vec3(y))


# A small search for the demo and CI: 5 × 5 cells, bed on the floor, two yaws, 40 refinement steps.
DEMO_SEARCH: dict[str, Any] = dict(
    xs=[1.2, 1.4, 1.6, 1.8, 2.0],
    ys=[-0.6, -0.3, 0.0, 0.3, 0.6],
    zs=[0.0],
    yaws=[0.0, math.pi / 2],
    max_evals=40,
)


def main() -> None:
    points, plane = demo_wall()
    best = best_placement(points, plane, **DEMO_SEARCH)
    print(f"energy {best['energy_j']:.1f} J over {best['duration_s']:.1f} s")
    print(f"robot base in the design: {best['robot_base']}")
    print(f"bed in the robot base frame: {best['bed_in_robot']}")
    print(f"nozzle spin {math.degrees(best['nozzle_spin']):.1f} deg")


if __name__ == "__main__":
    main()
