#!/usr/bin/env python3
"""Generate the shipped robot files of printwatt: robots/<name>/{robot.urdf, drive.toml, README.md}
and robots/README.md.

    python3 tools/robots/make_robots.py            # (re)write robots/
    python3 tools/robots/make_robots.py --check    # also run the FK / sanity checks and print them

Standard library only.  Every number below carries its source in a comment or in the source
string next to it.  Flags used in the source strings (first token):
  [DS]       manufacturer datasheet / specification
  [ROS-I]    ROS-Industrial or vendor ROS description (URDF / yaml)
  [3rd]      third-party secondary source
  [DERIVED]  computed here from cited inputs (method stated)
  [ESTIMATE] not public; estimated here (method stated)
The facts were collected in the project-external reference notes "robots.md" (public sources,
see each source string); no file of that collection is copied, the numbers are re-typed here.

Sign/frame conventions:
  * URDF joint origins: translation then rpy (URDF standard, R = Rz(yaw) Ry(pitch) Rx(roll)).
  * Inertia tensors are written about the CoM in the axes of the link frame (inertial rpy = 0).
  * tool0: ROS-I convention, z out of the flange.
  * OPW: Brandstoetter et al. / Jmeyer1292 opw_kinematics convention, q_opw = q * sign - offset.
"""
import math
import os
import random
import sys
import xml.etree.ElementTree as ET

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
REF = "/work/shared/reference/robots"   # only used by --check (optional cross-check vs source URDFs)
PI = math.pi
D2R = PI / 180.0
G0 = 9.81

# ------------------------------------------------------------------------------------------------
# source tags (cited in every generated file)
# ------------------------------------------------------------------------------------------------
SRC_ROSI_6700 = ("[ROS-I] ros-industrial/abb_experimental@20b9cf8 "
                 "abb_irb6700_support/urdf/irb6700_200_260_macro.xacro")
SRC_ROSI_4600 = ("[ROS-I] ros-industrial/abb_experimental@20b9cf8 "
                 "abb_irb4600_support/urdf/irb4600_40_255_macro.xacro")
SRC_DWG_4600 = "[DS] ABB dimension drawing 3HAC029038-004 (IRB 4600) agrees"
SRC_DS_TX200 = "[DS] Staubli datasheet 'TX200 series industrial robots' D181.573.04 (09/2013)"
SRC_3RD_TX200 = ("[3rd] ARTE TX200(L)/parameters.m + robotkinematicscatalogue 1.1.2 Staubli_TX200PV.py "
                 "(DH), cross-checked vs " + SRC_DS_TX200[5:])
SRC_UR = ("[ROS-I] UniversalRobots/Universal_Robots_ROS2_Description@2221ec0 (tag 2.4.5) "
          "config/ur10e + urdf/ur.urdf.xacro (UR-maintained)")
SRC_UR_PHYS = "[ROS-I] " + SRC_UR[8:].split(" config")[0] + " config/ur10e/physical_parameters.yaml (official UR masses/CoM)"
SRC_UR_APPROX = ("[ROS-I] physical_parameters.yaml inertia; flagged APPROX: numerically the UR10 (CB3) tensors "
                 "reused with e-Series masses")
SRC_UR_LIM = "[ROS-I] " + SRC_UR[8:].split(" config")[0] + " config/ur10e/joint_limits.yaml"
SRC_UR_DS = "[DS] UR10e user manual (SW 10.6 HTML)"
SRC_PUMA = ("[3rd] Corke & Armstrong-Helouvry, ICRA 1994 consensus model, as coded in "
            "roboticstoolbox-python 1.5.0 models/DH/Puma560.py")
SRC_PUMA_LIM = "[3rd] Wang & Chen 1991 joint limits, as in roboticstoolbox-python 1.5.0 Puma560.py"
SRC_KR210 = ("KUKA KR 210 L150 CAD link masses, ros-industrial/kuka_experimental@e78bbd1 "
             "kuka_kr210_support/urdf/kr210l150_macro.xacro, used for RATIOS only (absolute values are CAD-fake)")

# KR 210 L150 CAD masses [ROS-I, CAD-fake]: base, link_1..link_6 (kg).  Only their ratios are used.
KR210_MASSES = [1572.9, 1385.5, 958.62, 710.03, 173.73, 72.17, 6.3154]
KR210_TOTAL = sum(KR210_MASSES)

# ------------------------------------------------------------------------------------------------
# generic servo-motor classes  [ESTIMATE]
# ------------------------------------------------------------------------------------------------
# Generic 400 V AC permanent-magnet servo motors, rounded values typical of industrial catalogues
# (not one product).  DC-equivalent model: motor torque tau_m = Kt * i, copper loss = R * i^2,
# back-EMF = Kt * omega_m (SI), so the motor constant Km = Kt / sqrt(R) sets the copper loss
# tau_m^2 / Km^2.  Km was set so that the copper loss at continuous stall torque is about 5-9 %
# of the motor's rated mechanical power at 3000 rpm (typical of such motors).
#            T_cont  T_peak  Kt      R      Jm
#            [N m]   [N m]   [N m/A] [ohm]  [kg m^2]
MOTORS = {
    "S":   (1.3,    4.0,    0.8,    16.0,  0.12e-3),   # ~0.4 kW class, Km 0.20 N m/sqrt(W)
    "M":   (4.5,    13.0,   1.2,    5.0,   0.6e-3),    # ~1.4 kW class, Km 0.54
    "L":   (9.0,    28.0,   1.6,    3.2,   1.8e-3),    # ~2.8 kW class, Km 0.89
    "XL":  (20.0,   60.0,   2.0,    2.0,   5.5e-3),    # ~6 kW class,   Km 1.41
    "XXL": (36.0,   110.0,  2.2,    1.3,   12.0e-3),   # ~11 kW class,  Km 1.93
}
MOTOR_MAX_RPM = 3000.0     # [ESTIMATE] nominal max motor speed used to size the gear ratios
T_RAMP_MAIN = 0.5          # [ESTIMATE] s to reach max speed, axes 1-3 of the large arms
T_RAMP_WRIST = 0.35        # [ESTIMATE] s, wrist axes of the large arms
T_JERK = 0.1               # [ESTIMATE] s to build up the acceleration (jerk = acc / T_JERK)
FRICTION_FRACTION = 0.03   # [ESTIMATE] Coulomb = 3 % of rated joint torque, viscous = 3 % at max speed
# Axis-2 balancers (printwatt `balancer` effect, docs/effects.md): no manufacturer publishes the spring force
# or stiffness, so the nominal values are SIZED here: least squares (F0, k >= 0) so that the balancer
# cancels BALANCER_SHARE of the change of the static axis-2 gravity torque from the upright pose
# (q2 = 0, all other joints 0, nominal payload) over q2 in [-BALANCER_RANGE_DEG, +BALANCER_RANGE_DEG].
BALANCER_SHARE = 0.7       # [ESTIMATE] share of the lower-arm gravity moment a balancer is taken to carry
BALANCER_RANGE_DEG = 45    # [ESTIMATE] working range of axis 2 about upright used for the sizing


def fmt(x):
    """Shortest round-trip representation of a float (repr), ints as floats."""
    if isinstance(x, int):
        x = float(x)
    if x == 0.0:
        return "0.0"
    return repr(x)


# ------------------------------------------------------------------------------------------------
# small linear algebra (3x3 / 4x4 lists)
# ------------------------------------------------------------------------------------------------
def matmul(A, B):
    return [[sum(A[i][k] * B[k][j] for k in range(len(B))) for j in range(len(B[0]))] for i in range(len(A))]


def transpose(A):
    return [list(r) for r in zip(*A)]


def rx(a):
    c, s = math.cos(a), math.sin(a)
    return [[1, 0, 0], [0, c, -s], [0, s, c]]


def ry(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0, s], [0, 1, 0], [-s, 0, c]]


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def rpy_to_R(r, p, y):
    return matmul(rz(y), matmul(ry(p), rx(r)))


def axis_angle(axis, q):
    x, y, z = axis
    n = math.sqrt(x * x + y * y + z * z)
    x, y, z = x / n, y / n, z / n
    c, s = math.cos(q), math.sin(q)
    C = 1 - c
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def T_of(R, p):
    return [R[0] + [p[0]], R[1] + [p[1]], R[2] + [p[2]], [0, 0, 0, 1]]


def T_R(T):
    return [row[:3] for row in T[:3]]


def T_p(T):
    return [T[0][3], T[1][3], T[2][3]]


def mv(R, v):
    return [sum(R[i][k] * v[k] for k in range(3)) for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def clean(x, eps=1e-14):
    return 0.0 if abs(x) < eps else x


def rot_inertia(R, I6):
    """I6 = (ixx, iyy, izz, ixy, ixz, iyz) expressed in frame B; R maps B -> A.  Returns in A."""
    ixx, iyy, izz, ixy, ixz, iyz = I6
    I = [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]
    J = matmul(R, matmul(I, transpose(R)))
    return tuple(clean(v) for v in (J[0][0], J[1][1], J[2][2], J[0][1], J[0][2], J[1][2]))


def cylinder_inertia(m, r, L):
    """Solid cylinder along its local z: (ixx, iyy, izz) about the CoM."""
    it = m * (3 * r * r + L * L) / 12.0
    return (it, it, m * r * r / 2.0)


def segment_cylinder(m, p0, p1, r):
    """Solid cylinder of mass m, radius r, between points p0 and p1 (link frame).
    Returns CoM and inertia tensor about the CoM in link axes."""
    d = [p1[i] - p0[i] for i in range(3)]
    L = math.sqrt(sum(v * v for v in d))
    com = [(p0[i] + p1[i]) / 2.0 for i in range(3)]
    ixx, iyy, izz = cylinder_inertia(m, r, L)
    # rotation taking local z onto d
    if L < 1e-12:
        R = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    else:
        u = [v / L for v in d]
        ax = cross([0, 0, 1], u)
        s = math.sqrt(sum(v * v for v in ax))
        c = u[2]
        R = axis_angle(ax, math.atan2(s, c)) if s > 1e-12 else ([[1, 0, 0], [0, 1, 0], [0, 0, 1]] if c > 0 else rx(PI))
    I = rot_inertia(R, (ixx, iyy, izz, 0.0, 0.0, 0.0))
    return [clean(c_) for c_ in com], tuple(round(v, 12) for v in I), L


# ------------------------------------------------------------------------------------------------
# robot definitions
# ------------------------------------------------------------------------------------------------
def joint(name, parent, child, xyz, rpy, axis, lower, upper, vel, effort, src_origin, src_limit,
          jtype="revolute", mimic=None):
    return dict(name=name, type=jtype, parent=parent, child=child, xyz=xyz, rpy=rpy, axis=axis,
                lower=lower, upper=upper, vel=vel, effort=effort, src_origin=src_origin,
                src_limit=src_limit, mimic=mimic)


def fixed(name, parent, child, xyz, rpy, src):
    return dict(name=name, type="fixed", parent=parent, child=child, xyz=xyz, rpy=rpy, src_origin=src)


def pt(p):
    return "(" + ", ".join("%.4g" % v for v in p) + ")"


def estimate_inertials(weight, weight_src, segments, radii):
    """Distribute `weight` over base_link, link_1..link_6 in proportion to the KR 210 L150 CAD
    masses; each link a solid cylinder between two points of its frame (segments) with radius radii."""
    links = []
    names = ["base_link"] + ["link_%d" % i for i in range(1, 7)]
    for i, name in enumerate(names):
        frac = KR210_MASSES[i] / KR210_TOTAL
        m = round(weight * frac, 3)
        p0, p1 = segments[i]
        com, I, L = segment_cylinder(m, p0, p1, radii[i])
        src = ("[ESTIMATE] mass = %s kg total (%s) x %.4f (KR 210 L150 CAD mass ratio %s/%s); CoM and inertia: "
               "solid cylinder r = %.3f m, L = %.3f m from %s to %s (link frame)"
               % (fmt(weight), weight_src.split(']')[0].strip('['), frac, fmt(KR210_MASSES[i]), "%.2f" % KR210_TOTAL,
                  radii[i], L, pt(p0), pt(p1)))
        links.append(dict(name=name, mass=m, com=com, inertia=I, src=src))
    return links


def drive_entry(name, G, motor, eff, vmax, t_ramp, why_motor, why_G):
    Tc, Tp, Kt, R, Jm = MOTORS[motor]
    rated_joint = G * Tc * eff
    coul = round(FRICTION_FRACTION * rated_joint, 3)
    visc = round(FRICTION_FRACTION * rated_joint / vmax, 3)
    acc = round(vmax / t_ramp, 4)
    return dict(
        name=name,
        acceleration_limit_rad_s2=(acc, "ESTIMATE: velocity limit %.4f rad/s reached in %.2f s" % (vmax, t_ramp)),
        jerk_limit_rad_s3=(round(acc / T_JERK, 3), "ESTIMATE: acceleration limit built up in %.2f s" % T_JERK),
        gear_ratio=(float(G), "ESTIMATE: " + why_G),
        torque_constant_nm_per_a=(Kt, "ESTIMATE: generic servo class %s (%s N m cont.), %s" % (motor, fmt(Tc), why_motor)),
        winding_resistance_ohm=(R, "ESTIMATE: generic servo class %s, DC-equivalent (Km = Kt/sqrt(R) = %.2f N m/sqrt(W))"
                                % (motor, Kt / math.sqrt(R))),
        rotor_inertia_kg_m2=(Jm, "ESTIMATE: generic servo class %s (incl. brake)" % motor),
        viscous_nm_s_per_rad=(visc, "ESTIMATE: %d %% of rated joint torque (G*Tcont*eff = %.0f N m) at the velocity limit"
                              % (int(FRICTION_FRACTION * 100), rated_joint)),
        coulomb_nm=(coul, "ESTIMATE: %d %% of rated joint torque (%.0f N m)" % (int(FRICTION_FRACTION * 100), rated_joint)),
        gear_efficiency=(eff, "ESTIMATE: typical RV/cycloidal reducer %s" % ("(main axis)" if eff >= 0.9 else "+ wrist bevel stage")),
        motor_class=motor,
    )


def gear_for(vmax):
    G = round(MOTOR_MAX_RPM * 2 * PI / 60.0 / vmax)
    return G, "motor max %.0f rpm / joint max %.1f deg/s, rounded" % (MOTOR_MAX_RPM, vmax / D2R)


def cylinder_payload(mass, r, L, desc, src):
    ixx, iyy, izz = cylinder_inertia(mass, r, L)
    return dict(mass=mass, com=[0.0, 0.0, L / 2.0], inertia=[round(ixx, 6), round(iyy, 6), round(izz, 6), 0.0, 0.0, 0.0],
                description=desc, src=src + "; ESTIMATE: solid cylinder r = %.2f m, L = %.2f m along tool0 z" % (r, L),
                r=r, L=L)


# Collision geometry of the print head and hose ([tool.geometry], flange frame). ESTIMATE: the head is the
# payload's cylinder (radius r) from the flange to the nozzle tip; the hose is a straight piece of a 2-inch
# concrete hose (60 mm outer diameter; 20 mm for the lab-scale extruders) running up the side of the head
# from 0.8 L below the flange to the flange plane, where it is clamped to the head's mounting plate; above the
# clamp the hose is free and routed clear of the wrist (not modelled: a rigid piece behind the flange would
# run into the forearm's fork, which no site rigs).
def tool_geometry(rb):
    P = rb["payload"]
    if "r" not in P:
        return None
    r, L = P["r"], P["L"]
    hose_r = 0.03 if P["mass"] >= 20 else 0.01
    x = round(r + hose_r, 4)
    return dict(head=r, hose=hose_r, hose_from=[x, 0.0, round(0.8 * L, 4)], hose_to=[x, 0.0, 0.0],
                src="ESTIMATE: head = the payload's cylinder (r = %s m) from the flange to the nozzle tip; hose = "
                    "%s m radius (%s), straight up the side of the head from 0.8 L below the flange to the flange plane (clamped to the head's mounting plate; the free hose above is routed clear of the wrist)"
                    % (fmt(r), fmt(hose_r), "2-inch concrete hose, 60 mm OD" if hose_r >= 0.03 else "lab-scale feed hose, 20 mm OD"))


# Ranges of the estimated numbers ([uncertainty] in drive.toml), drawn by `printwatt optimise --uncertainty`.
# Half-widths of uniform ranges, relative unless the key names a unit.
def uncertainty(rb):
    if rb["name"] in ("abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"):
        inert = (0.20, 0.10, 0.50, "ESTIMATE: the stated accuracy of the inertial estimates (README: total mass +-20 %, "
                 "CoMs +-0.2 m, inertias +-50 %; CoM range per axis 0.1 m, i.e. up to 0.17 m in 3-D)")
    elif rb["name"] == "ur10e":
        inert = (0.05, 0.01, 0.30, "ESTIMATE: masses and CoMs are the official [ROS-I] values (+-5 %, +-1 cm), "
                 "inertias APPROX (+-30 %)")
    else:
        inert = (0.10, 0.02, 0.20, "ESTIMATE: complete published model [3rd] (Corke 1994): +-10 % masses, +-2 cm, "
                 "+-20 % inertias")
    U = [("link_mass_rel", inert[0], inert[3]), ("link_com_m", inert[1], "see link_mass_rel"),
         ("link_inertia_rel", inert[2], "see link_mass_rel"),
         ("payload_mass_rel", 0.25, "ESTIMATE: print head, hose and material share are not known to better than a quarter"),
         ("torque_constant_rel", 0.20, "ESTIMATE: generic servo classes, a real motor of the class differs by up to 20 %"),
         ("winding_resistance_rel", 0.30, "ESTIMATE: generic servo classes; R also rises ~40 % from 20 to 120 C"),
         ("viscous_rel", 0.50, "ESTIMATE: friction sized as 3 % of the rated torque; real reducers differ by a factor ~2"),
         ("coulomb_rel", 0.50, "ESTIMATE: as viscous_rel"),
         ("gear_efficiency_abs", 0.05, "ESTIMATE: typical spread of RV/cycloidal and bevel-stage efficiencies"),
         ("standby_power_rel", 0.50, "ESTIMATE: the cabinet's draw is an order-of-magnitude figure")]
    if rb.get("balancer"):
        U += [("balancer_absent_probability", 0.2, "ESTIMATE: the balancer model (geometry ESTIMATE, force SIZED) may not "
               "describe the robot at all"),
              ("balancer_force_rel", 0.50, "ESTIMATE: preload and stiffness are SIZED, not published")]
    return U


def abb_like(name, title, p, limits, lim_src, org_src, weight, weight_src, radii, motors, payload, reach, rated,
             provenance, extra_joints=(), extra_links=(), opw_src="", notes=(), balancer=None):
    """ABB-type chain (ROS-I layout): arm at zero = lower arm vertical, upper arm horizontal."""
    a1, a2, c1, c2, c3, c4 = p["a1"], p["a2"], p["c1"], p["c2"], p["c3"], p["c4"]
    org = [((0, 0, c1), (0, 0, 1)), ((a1, 0, 0), (0, 1, 0)), ((0, 0, c2), (0, 1, 0)),
           ((0, 0, -a2), (1, 0, 0)), ((c3, 0, 0), (0, 1, 0)), ((c4, 0, 0), (1, 0, 0))]
    joints = []
    for i in range(6):
        lo, up, v = limits[i]
        parent = "base_link" if i == 0 else "link_%d" % i
        joints.append(joint("joint_%d" % (i + 1), parent, "link_%d" % (i + 1), org[i][0], (0, 0, 0), org[i][1],
                            lo, up, v, 0.0, org_src, lim_src))
    joints += list(extra_joints)
    joints.append(fixed("joint_6-flange", "link_6", "flange", (0, 0, 0), (0, 0, 0), org_src))
    joints.append(fixed("link_6-tool0", "flange", "tool0", (0, 0, 0), (0, PI / 2, 0), org_src + " (tool0: z out of flange)"))
    # geometric model for the inertials (ESTIMATE), points in each link frame:
    segs = [((0, 0, 0), (0, 0, 0.5 * c1)),                 # base: pedestal, lower half of the shoulder height
            ((0, 0, -0.5 * c1), (a1, 0, 0)),               # link_1: turret from pedestal top to the A2 axis
            ((0, 0, 0), (0, 0, c2)),                       # link_2: lower arm A2 -> A3
            ((-0.2 * c3, 0, -a2 / 2), (0.2 * c3, 0, -a2 / 2)),  # link_3: elbow housing (wrist motors) centred on A3
            ((0, 0, 0), (c3, 0, 0)),                       # link_4: forearm tube A4 -> wrist centre
            ((0, 0, 0), (c4, 0, 0)),                       # link_5: wrist housing, wrist centre -> flange
            ((-0.04, 0, 0), (0, 0, 0))]                    # link_6: flange disc
    inert = estimate_inertials(weight, weight_src, segs, radii)
    links = inert + list(extra_links) + [dict(name="flange"), dict(name="tool0")]
    drives = []
    for i in range(6):
        v = limits[i][2]
        G, why = gear_for(v)
        motor, why_m, eff = motors[i]
        drives.append(drive_entry("joint_%d" % (i + 1), G, motor, eff, v, T_RAMP_MAIN if i < 3 else T_RAMP_WRIST, why_m, why))
    opw = dict(a1=a1, a2=a2, b=0.0, c1=c1, c2=c2, c3=c3, c4=c4, offsets=[0.0, 0.0, -PI / 2, 0.0, 0.0, 0.0],
               signs=[1] * 6, src=opw_src)
    return dict(name=name, title=title, joints=joints, links=links, drives=drives, opw=opw, payload=payload,
                reach=reach, rated=rated, provenance=provenance, weight=(weight, weight_src), notes=list(notes),
                balancer=balancer,
                tool=dict(xyz=[0.0, 0.0, 0.30], rpy=[0.0, 0.0, 0.0],
                          src="ESTIMATE: 3DCP nozzle tip 0.30 m below the flange, pointing along tool0 z"),
                cabinet=dict(standby=(250.0, "ESTIMATE: order of magnitude of an IRC5-class cabinet (electronics, fans, "
                                              "brakes released); not measured"),
                             regen=("dc_bus", "ESTIMATE: IRC5-class drive units share a DC link with a bleeder resistor; "
                                              "no regenerative supply assumed")))


def irb6700():
    s_lim = "[ROS-I] irb6700_200_260_macro.xacro limits"
    limits = [(-170 * D2R, 170 * D2R, 110 * D2R), (-65 * D2R, 85 * D2R, 110 * D2R), (-180 * D2R, 70 * D2R, 110 * D2R),
              (-300 * D2R, 300 * D2R, 190 * D2R), (-130 * D2R, 130 * D2R, 150 * D2R), (-360 * D2R, 360 * D2R, 210 * D2R)]
    p = dict(a1=0.32, a2=-0.2, c1=0.78, c2=1.125, c3=1.1425, c4=0.2)   # ROS-I joint origins (robots.md 1.1)
    # passive balancer joints, origins and limits as in the ROS-I URDF; massless links
    extra_j = [
        joint("cylinder_joint", "link_1", "cylinder", (-0.349, -0.194, -0.142), (0, 0, 0), (0, 1, 0),
              -0.28361600344907856, 0.37088246604879505, 100.0, 0.0, SRC_ROSI_6700 + " (passive balancer cylinder)",
              SRC_ROSI_6700, mimic=("joint_2", -0.25, 0.0)),
        joint("piston_joint", "cylinder", "piston", (0, 0, 0), (0.20897, 0, -PI / 2), (0, 1, 0),
              -0.25, 0.25, 100.0, 0.0, SRC_ROSI_6700 + " (passive balancer piston)", SRC_ROSI_6700,
              jtype="prismatic", mimic=("joint_2", 0.15, 0.0)),
    ]
    extra_l = [dict(name="cylinder"), dict(name="piston")]
    w_src = ("[ESTIMATE] 1170 kg: commonly cited weight of the IRB 6700-200/2.60, NOT verified (ABB product "
             "specification 3HAC044265-001 not accessible); plausibility: IRB 6640 family 1310-1405 kg [3rd, Joseph, "
             "Mastering ROS] x ~0.85-0.9 for the lighter IRB 6700 generation")
    radii = [0.45, 0.40, 0.20, 0.28, 0.15, 0.13, 0.10]   # ESTIMATE: rough half-widths of the housings
    motors = [("XL", "A1 inertial load (~1500 kg m^2 x 3.8 rad/s^2)", 0.9),
              ("XXL", "A2 carries the arm + payload against gravity (no balancer modelled)", 0.9),
              ("XL", "A3 gravity of forearm + payload", 0.9),
              ("L", "wrist", 0.85), ("L", "wrist", 0.85), ("M", "wrist", 0.85)]
    payload = cylinder_payload(60.0, 0.15, 0.30, "3DCP extruder head (~45 kg) + hose and material share (~15 kg)",
                               "ESTIMATE: typical 3DCP print head for a 200 kg-class arm")
    return abb_like("abb_irb6700_200_260", "ABB IRB 6700-200/2.60", p, limits, s_lim, SRC_ROSI_6700, 1170.0, w_src,
                    radii, motors, payload,
                    (2.60, "[DS] model designation (reach 2.60 m)"), (200.0, "[DS] model designation (200 kg)"),
                    "kinematics and limits [ROS-I]; OPW [DERIVED]; inertials ESTIMATE (1170 kg est., KR 210 mass ratios, "
                    "cylinder model); drive data ESTIMATE (generic servo classes)",
                    extra_joints=extra_j, extra_links=extra_l,
                    opw_src="[DERIVED] from the ROS-I joint origins (reference robots.md 1.3, verified there to 9e-16 m)",
                    balancer=dict(a=(0.25, "ESTIMATE: lever of the piston end on the lower arm, behind the A2 pivot "
                                           "(the ROS-I piston link gives no attachment point)"),
                                  b=(0.6840, "[DERIVED] distance of the ROS-I cylinder_joint origin (-0.349, -0.194, -0.142) "
                                             "in link_1 from the joint_2 origin (0.32, 0, 0), in the x-z plane: "
                                             "sqrt(0.669^2 + 0.142^2)"),
                                  src="hydraulic-spring balancer on axis 2 (ABB); force and stiffness not public"),
                    notes=["The real IRB 6700 has a hydraulic-spring balancer on axis 2. It is modelled as the `balancer` "
                           "effect ([effects] in drive.toml: geometry from the ROS-I cylinder origin + ESTIMATE, force "
                           "SIZED, not published); cylinder_joint/piston_joint in the URDF stay kinematic (visual) only, "
                           "massless, mimic of joint_2."])


def irb4600():
    s_lim = "[ROS-I] irb4600_40_255_macro.xacro limits"
    limits = [(-PI, PI, 175 * D2R), (-PI / 2, 150 * D2R, 175 * D2R), (-PI, 75 * D2R, 175 * D2R),
              (-400 * D2R, 400 * D2R, 250 * D2R), (-125 * D2R, 120 * D2R, 250 * D2R), (-400 * D2R, 400 * D2R, 360 * D2R)]
    p = dict(a1=0.175, a2=-0.175, c1=0.495, c2=1.095, c3=1.27, c4=0.135)   # ROS-I + ABB drawing 3HAC029038-004
    w_src = ("[DERIVED] 443 kg implied by the static foundation force F_z = 4350 N in ABB product manual IRB 4600 "
             "3HAC033453-001 rev. H p. 59 (4350/9.81); not the tabulated weight")
    radii = [0.33, 0.30, 0.14, 0.20, 0.11, 0.09, 0.07]   # ESTIMATE
    motors = [("XL", "A1 inertial load", 0.9), ("XL", "A2 gravity of arm + payload (no balancer modelled)", 0.9),
              ("L", "A3 gravity of forearm + payload", 0.9),
              ("M", "wrist", 0.85), ("M", "wrist", 0.85), ("S", "wrist", 0.85)]
    payload = cylinder_payload(30.0, 0.12, 0.30, "light 3DCP extruder head (~22 kg) + hose and material share (~8 kg)",
                               "ESTIMATE: 3DCP print head sized for a 40 kg-class arm")
    return abb_like("abb_irb4600_40_255", "ABB IRB 4600-40/2.55", p, limits, s_lim, SRC_ROSI_4600 + "; " + SRC_DWG_4600,
                    443.0, w_src, radii, motors, payload,
                    (2.55, "[DS] model designation (reach 2.55 m)"), (40.0, "[DS] model designation (40 kg)"),
                    "kinematics and limits [ROS-I] (+ABB drawing); OPW [DERIVED]; inertials ESTIMATE (443 kg [DERIVED], "
                    "KR 210 mass ratios, cylinder model); drive data ESTIMATE (generic servo classes)",
                    opw_src="[DERIVED] from the ROS-I joint origins (reference robots.md 2, verified there to 1e-15 m)",
                    balancer=dict(a=(0.15, "ESTIMATE: lever of the spring rod end on the lower arm, ~0.6 x the IRB 6700 "
                                           "lever (housings about 0.6 x the size)"),
                                  b=(0.42, "ESTIMATE: distance of the spring housing's pivot on the frame from the A2 "
                                           "pivot, ~0.6 x the IRB 6700 value"),
                                  src="spring balancer on axis 2 (ABB); force and stiffness not public"),
                    notes=["Axis 2 of the real IRB 4600 has a spring balancer; it is modelled as the `balancer` effect "
                           "([effects] in drive.toml) with ESTIMATE geometry and a SIZED force (not published)."])


def tx200():
    a1, a2, b, c1, c2, c3, c4 = 0.25, 0.0, 0.0, 0.642, 0.95, 0.8, 0.194
    rng = [(-180, 180), (-120, 120), (-140, 145), (-270, 270), (-120, 120), (-270, 270)]   # [DS]
    spd = [160, 160, 160, 260, 260, 400]                                                    # [DS] deg/s
    limits = [(r[0] * D2R, r[1] * D2R, s * D2R) for r, s in zip(rng, spd)]
    s_geo = SRC_3RD_TX200 + "; OPW set robots.md 4.2 (zero pose = arm straight up)"
    # arm-up chain: j1 z at c1, j2 y at a1, j3 y at c2 (up), j4 z along forearm, j5 y at c3, j6 z at c4
    org = [((0, 0, c1), (0, 0, 1)), ((a1, b, 0), (0, 1, 0)), ((0, 0, c2), (0, 1, 0)),
           ((a2, 0, 0), (0, 0, 1)), ((0, 0, c3), (0, 1, 0)), ((0, 0, c4), (0, 0, 1))]
    joints = []
    for i in range(6):
        lo, up, v = limits[i]
        joints.append(joint("joint_%d" % (i + 1), "base_link" if i == 0 else "link_%d" % i, "link_%d" % (i + 1),
                            org[i][0], (0, 0, 0), org[i][1], lo, up, v, 0.0, s_geo,
                            SRC_DS_TX200 + " (range, max speed)"))
    joints.append(fixed("joint_6-flange", "link_6", "flange", (0, 0, 0), (0, -PI / 2, 0),
                        "[DERIVED] ROS-I flange convention (x out of the flange)"))
    joints.append(fixed("link_6-tool0", "flange", "tool0", (0, 0, 0), (0, PI / 2, 0),
                        "[DERIVED] tool0 = OPW end frame (z out of the flange)"))
    segs = [((0, 0, 0), (0, 0, 0.5 * c1)), ((0, 0, -0.5 * c1), (a1, 0, 0)), ((0, 0, 0), (0, 0, c2)),
            ((0, 0, -0.2 * c3), (0, 0, 0.2 * c3)), ((0, 0, 0), (0, 0, c3)), ((0, 0, 0), (0, 0, c4)),
            ((0, 0, -0.04), (0, 0, 0))]
    radii = [0.40, 0.35, 0.18, 0.25, 0.14, 0.12, 0.09]   # ESTIMATE
    links = estimate_inertials(1000.0, "[DS] weight 1000 kg, " + SRC_DS_TX200[5:], segs, radii)
    links += [dict(name="flange"), dict(name="tool0")]
    motors = [("XL", "A1 inertial load", 0.9), ("XXL", "A2 gravity of arm + payload", 0.9),
              ("XL", "A3 gravity of forearm + payload", 0.9),
              ("L", "wrist", 0.85), ("L", "wrist", 0.85), ("M", "wrist", 0.85)]
    drives = []
    for i in range(6):
        v = limits[i][2]
        G, why = gear_for(v)
        drives.append(drive_entry("joint_%d" % (i + 1), G, motors[i][0], motors[i][2], v,
                                  T_RAMP_MAIN if i < 3 else T_RAMP_WRIST, motors[i][1], why))
    payload = cylinder_payload(45.0, 0.13, 0.30, "3DCP extruder head (~35 kg) + hose and material share (~10 kg)",
                               "ESTIMATE: 3DCP print head for a 100 kg-class arm")
    return dict(name="staubli_tx200", title="Staubli TX200", joints=joints, links=links, drives=drives,
                opw=dict(a1=a1, a2=a2, b=b, c1=c1, c2=c2, c3=c3, c4=c4, offsets=[0.0] * 6, signs=[1] * 6,
                         src="[DERIVED] reference robots.md 4.2 (verified there vs two DH models, 7e-16 m)"),
                payload=payload, reach=(2.194, SRC_DS_TX200 + " reach axis 1 to 6, 2194 mm"),
                rated=(100.0, SRC_DS_TX200 + " nominal load (130 kg max under special conditions)"),
                provenance="kinematics OPW geometry [3rd]+[DS] (no public URDF; URDF built here); limits [DS]; inertials "
                           "ESTIMATE (1000 kg [DS], KR 210 mass ratios, cylinder model); drive data ESTIMATE",
                weight=(1000.0, SRC_DS_TX200), tool=dict(xyz=[0.0, 0.0, 0.30], rpy=[0.0, 0.0, 0.0],
                                                           src="ESTIMATE: 3DCP nozzle tip 0.30 m below the flange, along tool0 z"),
                cabinet=dict(standby=(250.0, "ESTIMATE: order of magnitude of a CS8C HP cabinet (electronics, fans); not measured"),
                             regen=("dc_bus", "ESTIMATE: CS8C drives share a DC bus with a braking resistor")),
                notes=["No public URDF of the TX200 exists: the URDF here is built from the OPW geometry with the "
                       "Staubli zero (arm straight up). URDF joint values = Staubli controller values (offsets 0, signs +1).",
                       "a2 = b = 0 come from the two third-party DH models and are not independently confirmed.",
                       "Axis 2 of the real TX200 has a spring balancer; it is modelled as the `balancer` effect "
                       "([effects] in drive.toml) with ESTIMATE geometry and a SIZED force (not published)."],
                balancer=dict(a=(0.2, "ESTIMATE: lever of the spring rod end on the arm, behind the A2 pivot"),
                              b=(0.55, "ESTIMATE: distance of the spring housing's pivot on the shoulder from the A2 pivot"),
                              src="spring balancer on axis 2 (Staubli); force and stiffness not public"))


def ur10e():
    S = SRC_UR
    h = PI / 2
    # DH (UR article / default_kinematics.yaml): d1 0.1807, a2 -0.6127, a3 -0.57155, d4 0.17415, d5 0.11985, d6 0.11655
    vel = [120 * D2R, 120 * D2R, 180 * D2R, 180 * D2R, 180 * D2R, 180 * D2R]         # joint_limits.yaml
    eff = [330.0, 330.0, 150.0, 54.0, 54.0, 54.0]                                     # joint_limits.yaml
    lim = [(-2 * PI, 2 * PI), (-2 * PI, 2 * PI), (-PI, PI), (-2 * PI, 2 * PI), (-2 * PI, 2 * PI), (-2 * PI, 2 * PI)]
    org = [((0, 0, 0.1807), (0, 0, PI)),    # base_link -> base_link_inertia (rpy 0 0 pi) folded into joint_1 origin
           ((0, 0, 0), (h, 0, 0)),
           ((-0.6127, 0, 0), (0, 0, 0)),
           ((-0.57155, 0, 0.17415), (0, 0, 0)),
           ((0, -0.11985, 0), (h, 0, 0)),
           ((0, 0.11655, 0), (h, PI, PI))]
    joints = []
    urnames = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]
    for i in range(6):
        joints.append(joint("joint_%d" % (i + 1), "base_link" if i == 0 else "link_%d" % i, "link_%d" % (i + 1),
                            org[i][0], org[i][1], (0, 0, 1), lim[i][0], lim[i][1], vel[i], eff[i],
                            S + " ur.urdf.xacro (%s)" % urnames[i], SRC_UR_LIM))
    joints.append(fixed("joint_6-flange", "link_6", "flange", (0, 0, 0), (0, -h, -h), S + " (wrist_3-flange)"))
    joints.append(fixed("link_6-tool0", "flange", "tool0", (0, 0, 0), (h, 0, h), S + " (flange-tool0)"))
    # inertials: (mass, com xyz, rpy of the source inertial frame, I in that frame)
    src_in = [
        (4.0, (0, 0, 0), (0, 0, 0), (0.0061063308908, 0.0061063308908, 0.01125, 0, 0, 0)),
        (7.369, (0.021, -0.027, 0.0), (h, 0, 0), (0.03408, 0.03529, 0.02156, 2e-05, -0.00425, 8e-05)),
        (13.051, (-0.2327, 0.0, 0.158), (0, 0, 0), (0.02814, 0.77068, 0.76943, 5e-05, -0.01561, 2e-05)),
        (3.989, (-0.33155, 0.0, 0.068), (0, 0, 0), (0.01014, 0.30928, 0.30646, 8e-05, 0.00916, 0.0)),
        (2.1, (0.0, -0.018, 0.007), (h, 0, 0), (0.00296, 0.00222, 0.00258, -1e-05, 0.0, -0.00024)),
        (1.98, (0.0, 0.018, -0.007), (-h, 0, 0), (0.00296, 0.00222, 0.00258, -1e-05, 0.0, -0.00024)),
        (0.615, (0.0, 0.0, -0.026), (0, 0, 0), (0.0004, 0.00041, 0.00034, 0, 0, 0)),
    ]
    names = ["base_link"] + ["link_%d" % i for i in range(1, 7)]
    urlinks = ["base_link_inertia", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link", "wrist_3_link"]
    links = []
    for i, (m, c, rpy, I) in enumerate(src_in):
        Ir = rot_inertia(rpy_to_R(*rpy), I)
        src = (SRC_UR_PHYS + " (%s mass, CoM); inertia " % urlinks[i] + SRC_UR_APPROX[8:] +
               ("; rotated from the source inertial rpy %s into link axes" % (tuple(round(v, 6) for v in rpy),) if any(rpy) else ""))
        if i == 0:
            src += "; base mass 4.0 flagged 'might be incorrect' upstream (fixed base: no effect on joint torques)"
        links.append(dict(name=names[i], mass=m, com=list(c), inertia=Ir, src=src))
    links += [dict(name="flange"), dict(name="tool0")]
    # drives: ESTIMATE
    G = 101.0
    mot = [(0.17, 0.20, 7e-5), (0.17, 0.20, 7e-5), (0.13, 0.30, 3.5e-5), (0.075, 0.60, 1.5e-5), (0.075, 0.60, 1.5e-5),
           (0.075, 0.60, 1.5e-5)]
    coul = [12.0, 12.0, 8.0, 3.0, 3.0, 3.0]
    visc = [8.0, 8.0, 5.0, 1.5, 1.5, 1.5]
    drives = []
    for i in range(6):
        acc = round(vel[i] / 0.3, 4)
        Kt, R, Jm = mot[i]
        drives.append(dict(
            name="joint_%d" % (i + 1),
            acceleration_limit_rad_s2=(acc, "ESTIMATE: velocity limit reached in 0.30 s (UR acceleration limits not public)"),
            jerk_limit_rad_s3=(round(acc / T_JERK, 3), "ESTIMATE: acceleration built up in %.2f s" % T_JERK),
            gear_ratio=(G, "ESTIMATE: strain-wave gear 1:101, the ratio commonly reported for UR joints (not verified)"),
            torque_constant_nm_per_a=(Kt, "ESTIMATE: frameless BLDC motor on a 48 V DC bus, Ke sized for ~%0.f rpm motor speed"
                                      % (vel[i] * G * 60 / (2 * PI))),
            winding_resistance_ohm=(R, "ESTIMATE: DC-equivalent, frameless 48 V BLDC of this size (Km = %.2f N m/sqrt(W))"
                                    % (Kt / math.sqrt(R))),
            rotor_inertia_kg_m2=(Jm, "ESTIMATE: frameless rotor + encoder/brake hub of this size"),
            viscous_nm_s_per_rad=(visc[i], "ESTIMATE: order of magnitude of identified strain-wave cobot joint friction"),
            coulomb_nm=(coul[i], "ESTIMATE: ~3-5 %% of the %s N m joint torque limit" % fmt(eff[i])),
            gear_efficiency=(0.8, "ESTIMATE: typical strain-wave gear efficiency under load"),
            motor_class="48V-BLDC"))
    payload = cylinder_payload(4.0, 0.06, 0.15, "small paste/clay extruder with cartridge (lab-scale printing)",
                               "ESTIMATE: lab-scale extruder for a 12.5 kg cobot")
    return dict(name="ur10e", title="Universal Robots UR10e", joints=joints, links=links, drives=drives, opw=None,
                payload=payload, reach=(1.30, SRC_UR_DS + " 'workspace of 1300 mm'"),
                rated=(12.5, SRC_UR_DS + " 'Maximum Payload' (10 kg on older labels)"),
                provenance="kinematics, masses, CoM [ROS-I official UR]; inertias [ROS-I, APPROX = UR10 CB3 values]; "
                           "drive data and friction ESTIMATE",
                weight=(sum(l["mass"] for l in links if "mass" in l), "[DERIVED] sum of the URDF link masses (incl. 4.0 kg base)"),
                tool=dict(xyz=[0.0, 0.0, 0.15], rpy=[0.0, 0.0, 0.0], src="ESTIMATE: nozzle tip 0.15 m below the flange"),
                cabinet=dict(standby=(40.0, "ESTIMATE: order of magnitude of the UR control box idle draw; not measured"),
                             regen=("dc_bus", "ESTIMATE: joints share the 48 V DC bus; surplus burnt in the box")),
                notes=["Joint and link names are printwatt's uniform joint_i/link_i; UR names: " +
                       ", ".join("joint_%d = %s" % (i + 1, n) for i, n in enumerate(urnames)) + ".",
                       "The fixed base_link -> base_link_inertia rotation (rpy 0 0 pi) is folded into the joint_1 origin.",
                       "UR's xacro writes pi/2 as 1.570796327 in some origins (giving ~2e-11 m offsets); exact pi/2 is used "
                       "here, so tool0 differs from the upstream URDF by ~1e-10 m.",
                       "No OPW set: the UR wrist is not spherical; [kinematics] is omitted from drive.toml.",
                       "Inertia tensors: UR's APPROX values rotated into the link axes (the source gives some with an "
                       "inertial rpy); physically identical.",
                       "Wrist-joint UR joint-position limits are +-360 deg; the elbow is limited to +-180 deg upstream on purpose."])


def puma560():
    # standard DH (Corke & Armstrong-Helouvry 1994, roboticstoolbox Puma560.py, pedestal variant d1 = 0.67183 m)
    d = [0.67183, 0.0, 0.15005, 0.4318, 0.0, 0.0]
    a = [0.0, 0.4318, 0.0203, 0.0, 0.0, 0.0]
    al = [PI / 2, 0.0, -PI / 2, PI / 2, -PI / 2, 0.0]
    m = [0.0, 17.4, 4.8, 0.82, 0.34, 0.09]
    r = [(0, 0, 0), (-0.3638, 0.006, 0.2275), (-0.0203, -0.0141, 0.070), (0, 0.019, 0), (0, 0, 0), (0, 0, 0.032)]
    I = [(0, 0.35, 0), (0.13, 0.524, 0.539), (0.066, 0.086, 0.0125), (1.8e-3, 1.3e-3, 1.8e-3), (0.3e-3, 0.4e-3, 0.3e-3),
         (0.15e-3, 0.15e-3, 0.04e-3)]
    Jm = [200e-6, 200e-6, 200e-6, 33e-6, 33e-6, 33e-6]
    Gs = [-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686]
    B = [1.48e-3, 0.817e-3, 1.38e-3, 71.2e-6, 82.6e-6, 36.7e-6]
    Tc = [(0.395, -0.435), (0.126, -0.071), (0.132, -0.105), (11.2e-3, -16.9e-3), (9.26e-3, -14.5e-3), (3.96e-3, -10.5e-3)]
    qlim = [(-2.7925268032, 2.7925268032), (-0.7853981634, 3.926990817), (-3.926990817, 0.7853981634),
            (-1.9198621772, 2.9670597284), (-1.745329252, 1.745329252), (-4.6425758103, 4.6425758103)]
    nm = 3000.0 * 2 * PI / 60
    vel = [round(nm / abs(g), 4) for g in Gs]     # ESTIMATE
    joints, links = [], [dict(name="base_link")]
    for i in range(6):
        if i == 0:
            xyz, rpy = (0, 0, 0), (0, 0, 0)
            so = SRC_PUMA + " (base frame = DH frame 0)"
        else:
            xyz, rpy = (a[i - 1], 0, d[i - 1]), (al[i - 1], 0, 0)
            so = SRC_PUMA + " [DERIVED] standard DH row %d -> origin Trans(a,0,d) Rx(alpha)" % i
        joints.append(joint("joint_%d" % (i + 1), "base_link" if i == 0 else "link_%d" % i, "link_%d" % (i + 1), xyz, rpy,
                            (0, 0, 1), qlim[i][0], qlim[i][1], vel[i], 0.0, so,
                            SRC_PUMA_LIM + "; velocity ESTIMATE 3000 rpm motor speed / |G|"))
        Rx_ = rx(al[i])
        com = [clean(v) for v in [a[i] + mv(Rx_, r[i])[0], mv(Rx_, r[i])[1], d[i] + mv(Rx_, r[i])[2]]]
        Il = rot_inertia(Rx_, (I[i][0], I[i][1], I[i][2], 0, 0, 0))
        src = SRC_PUMA + " mass/CoM/inertia of link %d (DH frame %d), [DERIVED] moved into the URDF link frame" % (i + 1, i + 1)
        if i == 0:
            src += "; m1 = 0 with Iyy = 0.35 is the published consensus (inertia about axis 1)"
        if i == 2:
            src += "; violates the triangle inequality in the published data"
        links.append(dict(name="link_%d" % (i + 1), mass=m[i], com=[round(v, 12) for v in com], inertia=Il, src=src))
    joints.append(fixed("joint_6-flange", "link_6", "flange", (0, 0, 0), (0, -PI / 2, 0),
                        "[DERIVED] ROS-I flange convention (x along DH z6)"))
    joints.append(fixed("link_6-tool0", "flange", "tool0", (0, 0, 0), (0, PI / 2, 0),
                        "[DERIVED] tool0 = DH frame 6 (z out of the flange)"))
    links += [dict(name="flange"), dict(name="tool0")]
    drives = []
    kt = [(0.26, 1.6)] * 3 + [(0.09, 3.9)] * 3
    for i in range(6):
        g = abs(Gs[i])
        acc = round(vel[i] / 0.25, 4)
        c_mean = g * (abs(Tc[i][0]) + abs(Tc[i][1])) / 2
        drives.append(dict(
            name="joint_%d" % (i + 1),
            acceleration_limit_rad_s2=(acc, "ESTIMATE: velocity limit reached in 0.25 s"),
            jerk_limit_rad_s3=(round(acc / T_JERK, 3), "ESTIMATE: acceleration built up in %.2f s" % T_JERK),
            gear_ratio=(g, SRC_PUMA + " |G| = %s (source sign %s encodes motor direction)" % (fmt(g), "-" if Gs[i] < 0 else "+")),
            torque_constant_nm_per_a=(kt[i][0], "ESTIMATE: [NOT FOUND] publicly; generic value for a brushed DC servo of this "
                                                "size (lead: Corke 1994 PhD thesis tables)"),
            winding_resistance_ohm=(kt[i][1], "ESTIMATE: [NOT FOUND] publicly; generic brushed DC servo armature resistance"),
            rotor_inertia_kg_m2=(Jm[i], SRC_PUMA + " Jm"),
            viscous_nm_s_per_rad=(round(g * g * B[i], 6), "[DERIVED] G^2 * B, B = %s N m s/rad motor side, " % fmt(B[i]) + SRC_PUMA),
            coulomb_nm=(round(c_mean, 6), "[DERIVED] |G| * mean(|Tc+|, |Tc-|), Tc = (%s, %s) N m motor side, %s; "
                        "direction-dependent values %.4f / %.4f N m" % (fmt(Tc[i][0]), fmt(Tc[i][1]), SRC_PUMA,
                                                                         g * abs(Tc[i][0]), g * abs(Tc[i][1]))),
            gear_efficiency=(1.0, "ESTIMATE: 1.0 because the identified motor-side B and Tc already contain the gear losses"),
            motor_class="PUMA DC"))
    payload = cylinder_payload(1.0, 0.04, 0.10, "small syringe-type extruder (test payload)",
                               "ESTIMATE: test payload, well under the commonly cited 2.5 kg rating")
    return dict(name="puma560", title="Unimation PUMA 560 (Corke & Armstrong-Helouvry 1994)", joints=joints, links=links,
                drives=drives,
                opw=dict(a1=0.0, a2=-0.0203, b=0.15005, c1=0.67183, c2=0.4318, c3=0.4318, c4=0.0,
                         offsets=[PI, PI / 2, -PI / 2, 0.0, 0.0, PI], signs=[1] * 6,
                         src="[DERIVED] reference robots.md 7, set A (verified there vs the DH FK, < 1e-9 m)"),
                payload=payload, reach=(0.8636, "[DERIVED] a2 + d4 = 0.4318 + 0.4318 m (shoulder to wrist centre), " + SRC_PUMA),
                rated=(2.5, "[3rd] commonly cited PUMA 560 rating, not verified against a Unimation document"),
                provenance="kinematics, inertials, Jm, G, friction [3rd] Corke & Armstrong-Helouvry 1994 (pedestal variant); "
                           "Kt/R, velocity/acceleration limits ESTIMATE",
                weight=(sum(m), "[DERIVED] sum of the link masses of the source (arm only, m1 = 0)"),
                tool=dict(xyz=[0.0, 0.0, 0.10], rpy=[0.0, 0.0, 0.0], src="ESTIMATE: nozzle 0.10 m beyond the flange"),
                cabinet=dict(standby=(0.0, "ESTIMATE: unknown (Unimate controller); excluded"),
                             regen=("none", "ESTIMATE: linear/PWM DC amplifiers without energy return")),
                notes=["Friction convention: joint side, symmetric. The source stores motor-side Tc as a direction pair "
                       "[Tc0 applied when qd>0, Tc1 when qd<0] (toolbox code); drive.toml gives |G| * mean(|Tc0|, |Tc1|). "
                       "The two direction values are in the comment. viscous = G^2 * B.",
                       "Reflected rotor inertia G^2 Jm = 0.784, 2.325, 0.577, 0.191, 0.171, 0.194 kg m^2 is NOT in the URDF; "
                       "it comes from drive.toml (rotor_inertia * gear_ratio^2).",
                       "Link 1 has m = 0 and Iyy = 0.35 (published consensus); link 3 violates the triangle inequality "
                       "(published data). Loaders must accept or warn.",
                       "Joint velocity limits are [NOT FOUND]; estimated as 3000 rpm motor speed / |G|.",
                       "URDF: link_i frame = DH frame i-1 rotated by q_i; inertials moved from DH frame i into it; "
                       "tool0 = DH frame 6."])


ROBOTS = [irb6700, irb4600, tx200, ur10e, puma560]


# ------------------------------------------------------------------------------------------------
# writers
# ------------------------------------------------------------------------------------------------
def xesc(s):
    return s.replace("--", "- -").replace("&", "and").replace("<", "(").replace(">", ")")


def v3(v):
    return " ".join(fmt(float(x)) for x in v)


def collision_elements(rb, link, urdf_path):
    """The link's <collision> elements, one per convex piece that tools/robots/collision_hulls.py
    wrote (committed files next to the URDF, robots/<name>/collision/<link>-<k>.obj); nothing
    otherwise."""
    d = os.path.join(os.path.dirname(urdf_path), "collision")
    if not os.path.isdir(d):
        return []
    pieces = sorted((f for f in os.listdir(d) if f.startswith(link + "-") and f.endswith(".obj")),
                    key=lambda f: int(f[len(link) + 1:-4]))
    if not pieces:
        return []
    L = ["    <!-- collision: %d convex piece(s) from the published meshes (conservative); source, commit, "
         "method and licence in collision/README.md -->" % len(pieces)]
    for f in pieces:
        L += ["    <collision>",
              '      <origin xyz="0.0 0.0 0.0" rpy="0.0 0.0 0.0"/>',
              '      <geometry><mesh filename="collision/%s"/></geometry>' % f,
              "    </collision>"]
    return L


def write_urdf(rb, path):
    L = ['<?xml version="1.0"?>',
         "<!-- generated by tools/robots/make_robots.py, do not edit -->",
         "<!-- %s. Provenance: %s -->" % (xesc(rb["title"]), xesc(rb["provenance"])),
         "<!-- Units SI. Inertia tensors about the CoM in link axes. tool0: z out of the flange (ROS-I). -->",
         '<robot name="%s">' % rb["name"]]
    for l in rb["links"]:
        if "mass" not in l:
            L.append('  <link name="%s"/>' % l["name"])
            continue
        I = l["inertia"]
        L += ['  <link name="%s">' % l["name"],
              "    <!-- %s -->" % xesc(l["src"]),
              "    <inertial>",
              '      <origin xyz="%s" rpy="0.0 0.0 0.0"/>' % v3(l["com"]),
              '      <mass value="%s"/>' % fmt(l["mass"]),
              '      <inertia ixx="%s" ixy="%s" ixz="%s" iyy="%s" iyz="%s" izz="%s"/>' % tuple(
                  fmt(I[k]) for k in (0, 3, 4, 1, 5, 2)),
              "    </inertial>"]
        L += collision_elements(rb, l["name"], path)
        L.append("  </link>")
    for j in rb["joints"]:
        L.append('  <joint name="%s" type="%s">' % (j["name"], j["type"]))
        L.append("    <!-- origin: %s -->" % xesc(j["src_origin"]))
        L.append('    <origin xyz="%s" rpy="%s"/>' % (v3(j["xyz"]), v3(j["rpy"])))
        L.append('    <parent link="%s"/>' % j["parent"])
        L.append('    <child link="%s"/>' % j["child"])
        if j["type"] != "fixed":
            L.append('    <axis xyz="%s"/>' % v3(j["axis"]))
            L.append("    <!-- limits: %s -->" % xesc(j["src_limit"]))
            L.append('    <limit lower="%s" upper="%s" velocity="%s" effort="%s"/>' % (
                fmt(j["lower"]), fmt(j["upper"]), fmt(j["vel"]), fmt(j["effort"])))
            if j["mimic"]:
                L.append('    <mimic joint="%s" multiplier="%s" offset="%s"/>' % (
                    j["mimic"][0], fmt(j["mimic"][1]), fmt(j["mimic"][2])))
        L.append("  </joint>")
    L.append("</robot>")
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


def tstr(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def tarr(v, ints=False):
    return "[" + ", ".join(str(int(x)) if ints else fmt(float(x)) for x in v) + "]"


def write_drive(rb, path):
    P = rb["payload"]
    L = ["# drive.toml of %s -- generated by tools/robots/make_robots.py, do not edit" % rb["title"],
         "# printwatt drive file: payload, tool, cabinet and per-axis drive-train data (all SI, unit in the key).",
         "# Every number has its source or 'ESTIMATE: how' beside it. Provenance: " + rb["provenance"],
         "# Motor model: DC-equivalent, tau_m = Kt i, copper loss R i^2, back-EMF Kt omega_m; joint torque = G * tau_m.",
         "",
         "[robot]",
         "name = %s" % tstr(rb["title"]),
         "reach_m = %s  # %s" % (fmt(rb["reach"][0]), rb["reach"][1]),
         "rated_payload_kg = %s  # %s" % (fmt(rb["rated"][0]), rb["rated"][1]),
         "provenance = %s" % tstr(rb["provenance"]),
         'tool_link = "tool0"  # URDF link ending the arm chain (flange frame, z out of the flange)',
         ""]
    if rb["opw"]:
        o = rb["opw"]
        L += ["[kinematics]  # %s" % o["src"],
              'type = "opw"  # Brandstoetter / Jmeyer1292 opw_kinematics convention, q_opw = q*sign - offset'] + [
            "%s_m = %s  # %s" % (k, fmt(o[k]), o["src"].split("]")[0] + "]") for k in ("a1", "a2", "b", "c1", "c2", "c3", "c4")] + [
            "offsets_rad = %s  # %s" % (tarr(o["offsets"]), o["src"].split("]")[0] + "]"),
            "signs = %s  # %s" % (tarr(o["signs"], True), o["src"].split("]")[0] + "]"),
            ""]
    T = rb["tool"]
    L += ["[tool]  # nozzle tip relative to tool_link, URDF xyz/rpy convention",
          "xyz_m = %s  # %s" % (tarr(T["xyz"]), T["src"]),
          "rpy_rad = %s  # %s" % (tarr(T["rpy"]), T["src"]),
          ""]
    G = tool_geometry(rb)
    if G:
        L += ["[tool.geometry]  # print head and hose for collision checks, flange (tool_link) frame, m; " + G["src"],
              "head_radius_m = %s  # ESTIMATE: see the table comment" % fmt(G["head"]),
              "hose_radius_m = %s  # ESTIMATE: see the table comment" % fmt(G["hose"]),
              "hose_from_m = %s  # ESTIMATE: see the table comment" % tarr(G["hose_from"]),
              "hose_to_m = %s  # ESTIMATE: see the table comment" % tarr(G["hose_to"]),
              ""]
    L += ["[payload]  # extruder + hose + material, rigidly attached to tool_link",
          "mass_kg = %s  # %s" % (fmt(P["mass"]), P["src"]),
          "com_m = %s  # in tool_link frame; %s" % (tarr(P["com"]), P["src"]),
          "inertia_kg_m2 = %s  # [ixx, iyy, izz, ixy, ixz, iyz] about the CoM, tool_link axes; %s" % (tarr(P["inertia"]), P["src"]),
          "description = %s" % tstr(P["description"]),
          "",
          "[cabinet]",
          "standby_power_w = %s  # %s" % (fmt(rb["cabinet"]["standby"][0]), rb["cabinet"]["standby"][1]),
          "regeneration = %s  # %s" % (tstr(rb["cabinet"]["regen"][0]), rb["cabinet"]["regen"][1]),
          ""]
    B = rb.get("balancer")
    if B:
        how = ("ESTIMATE: SIZED, not published: least squares (F0, k >= 0) so that it cancels %.0f %% of the change of the "
               "static axis-2 gravity torque from upright over q2 in [-%d, +%d] deg (other joints 0, nominal payload); "
               "achieved: %.0f %% at q2 = -%d deg, %.0f %% at +%d deg"
               % (100 * BALANCER_SHARE, BALANCER_RANGE_DEG, BALANCER_RANGE_DEG, 100 * B["achieved"][0],
                  BALANCER_RANGE_DEG, 100 * B["achieved"][1], BALANCER_RANGE_DEG))
        L += ["[effects]  # axis-2 balancer, printwatt `balancer` effect (docs/effects.md): %s" % B["src"],
              "balancer_joint = 2  # the shoulder axis",
              "balancer_lever_m = %s  # %s" % (fmt(B["a"][0]), B["a"][1]),
              "balancer_base_m = %s  # %s" % (fmt(B["b"][0]), B["b"][1]),
              "balancer_upright_rad = 0.0  # zero pose = lower arm vertical (cylinder shortest there)",
              "balancer_preload_n = %s  # %s" % (fmt(B["F0"]), how),
              "balancer_stiffness_n_per_m = %s  # %s" % (fmt(B["k"]), how),
              ""]
    L += ["[uncertainty]  # ranges of the ESTIMATE numbers above (half-widths of uniform ranges, relative unless the key "
          "names a unit), drawn by `printwatt optimise --uncertainty N`"]
    L += ["%s = %s  # %s" % (k, fmt(v), why) for k, v, why in uncertainty(rb)]
    L.append("")
    keys = ["acceleration_limit_rad_s2", "jerk_limit_rad_s3", "gear_ratio", "torque_constant_nm_per_a",
            "winding_resistance_ohm", "rotor_inertia_kg_m2", "viscous_nm_s_per_rad", "coulomb_nm", "gear_efficiency"]
    for d in rb["drives"]:
        L += ["[[joints]]", 'name = "%s"' % d["name"]]
        for k in keys:
            L.append("%s = %s  # %s" % (k, fmt(d[k][0]), d[k][1]))
        L.append("")
    with open(path, "w") as f:
        f.write("\n".join(L))


def flag(src):
    s = src.strip()
    if s.startswith("ESTIMATE") or s.startswith("[ESTIMATE]"):
        return "[ESTIMATE]"
    if s.startswith("["):
        return s.split("]")[0] + "]"
    return "?"


def write_readme(rb, path, check):
    o = rb["opw"]
    L = ["# %s (`robots/%s`)" % (rb["title"], rb["name"]), "",
         "Generated by `tools/robots/make_robots.py`; do not edit. Files: `robot.urdf`, `drive.toml`.", "",
         "**Provenance:** " + rb["provenance"], "",
         "Flags: [DS] datasheet, [ROS-I] ROS-Industrial/vendor ROS description, [3rd] third-party, "
         "[DERIVED] computed here from cited inputs, [ESTIMATE] not public, estimated (method given).", "",
         "## Basic facts", "",
         "| Quantity | Value | Source | Flag |", "|---|---|---|---|",
         "| Reach | %s m | %s | %s |" % (fmt(rb["reach"][0]), rb["reach"][1], flag(rb["reach"][1])),
         "| Rated payload | %s kg | %s | %s |" % (fmt(rb["rated"][0]), rb["rated"][1], flag(rb["rated"][1])),
         "| Robot weight used | %.3f kg | %s | %s |" % (rb["weight"][0], rb["weight"][1], flag(rb["weight"][1])),
         "| Sum of URDF link masses | %.3f kg (moving links %.3f kg) | sum of the table below | [DERIVED] |" % (
             sum(l.get("mass", 0) for l in rb["links"]),
             sum(l.get("mass", 0) for l in rb["links"] if l["name"] != "base_link")),
         "", "## Kinematics (URDF joints)", "",
         "| Joint | type | origin xyz (m) | origin rpy (rad) | axis | lower / upper | velocity (rad/s) | effort (N m) | source (origin; limits) | flag |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for j in rb["joints"]:
        if j["type"] == "fixed":
            L.append("| %s | fixed | %s | %s | – | – | – | – | %s | %s |" % (
                j["name"], v3(j["xyz"]), v3([round(x, 12) for x in j["rpy"]]), j["src_origin"], flag(j["src_origin"])))
        else:
            mim = " (mimic %s × %s)" % (j["mimic"][0], fmt(j["mimic"][1])) if j["mimic"] else ""
            L.append("| %s | %s%s | %s | %s | %s | %.6g / %.6g | %.6g | %s | %s; %s | %s/%s |" % (
                j["name"], j["type"], mim, v3(j["xyz"]), v3([round(x, 12) for x in j["rpy"]]), v3(j["axis"]),
                j["lower"], j["upper"], j["vel"], fmt(j["effort"]), j["src_origin"], j["src_limit"],
                flag(j["src_origin"]), flag(j["src_limit"].split(";")[-1] if "ESTIMATE" in j["src_limit"] else j["src_limit"])))
    if o:
        L += ["", "## OPW parameters (`[kinematics]` in drive.toml)", "",
              "| a1 | a2 | b | c1 | c2 | c3 | c4 | offsets (rad) | signs | source |", "|---|---|---|---|---|---|---|---|---|---|",
              "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                  fmt(o["a1"]), fmt(o["a2"]), fmt(o["b"]), fmt(o["c1"]), fmt(o["c2"]), fmt(o["c3"]), fmt(o["c4"]),
                  tarr(o["offsets"]), tarr(o["signs"], True), o["src"])]
    L += ["", "## Link inertials", "",
          "| Link | mass (kg) | CoM (m, link frame) | Ixx, Iyy, Izz, Ixy, Ixz, Iyz (kg m², about CoM, link axes) | source | flag |",
          "|---|---|---|---|---|---|"]
    for l in rb["links"]:
        if "mass" in l:
            L.append("| %s | %s | %s | %s | %s | %s |" % (l["name"], fmt(l["mass"]), v3(l["com"]),
                                                         ", ".join("%.6g" % x for x in l["inertia"]), l["src"], flag(l["src"])))
        else:
            L.append("| %s | – (massless frame) | | | | |" % l["name"])
    P = rb["payload"]
    L += ["", "## Tool and payload (drive.toml)", "", "| Quantity | Value | Source | Flag |", "|---|---|---|---|",
          "| Nozzle xyz / rpy rel. tool0 | %s / %s | %s | %s |" % (tarr(rb["tool"]["xyz"]), tarr(rb["tool"]["rpy"]),
                                                                  rb["tool"]["src"], flag(rb["tool"]["src"])),
          "| Payload mass | %s kg | %s | [ESTIMATE] |" % (fmt(P["mass"]), P["src"]),
          "| Payload CoM | %s m | %s | [ESTIMATE] |" % (tarr(P["com"]), P["src"]),
          "| Payload inertia | %s kg m² | %s | [ESTIMATE] |" % (tarr(P["inertia"]), P["src"]),
          "| Cabinet standby | %s W | %s | %s |" % (fmt(rb["cabinet"]["standby"][0]), rb["cabinet"]["standby"][1], "[ESTIMATE]"),
          "| Regeneration | %s | %s | [ESTIMATE] |" % (rb["cabinet"]["regen"][0], rb["cabinet"]["regen"][1]),
          "", "## Drive data (drive.toml `[[joints]]`)", ""]
    keys = [("gear_ratio", "G"), ("torque_constant_nm_per_a", "Kt (N m/A)"), ("winding_resistance_ohm", "R (Ω)"),
            ("rotor_inertia_kg_m2", "Jm (kg m²)"), ("viscous_nm_s_per_rad", "viscous (N m s/rad, joint)"),
            ("coulomb_nm", "Coulomb (N m, joint)"), ("gear_efficiency", "gear eff."),
            ("acceleration_limit_rad_s2", "acc. limit (rad/s²)"), ("jerk_limit_rad_s3", "jerk limit (rad/s³)")]
    L += ["| Quantity | " + " | ".join(d["name"] for d in rb["drives"]) + " | source | flag |",
          "|---|" + "---|" * (len(rb["drives"]) + 2)]
    for k, lab in keys:
        srcs = sorted(set(d[k][1] for d in rb["drives"]))
        L.append("| %s | %s | %s | %s |" % (lab, " | ".join("%.6g" % d[k][0] for d in rb["drives"]),
                                          "<br>".join(srcs), "/".join(sorted(set(flag(s) for s in srcs)))))
    if any(d["motor_class"] in MOTORS for d in rb["drives"]):
        L += ["", "Motor classes used: " + ", ".join("%s = %s" % (d["name"], d["motor_class"]) for d in rb["drives"]) +
              ". Generic servo classes (ESTIMATE, typical 400 V PM servo catalogue values, not a specific product): " +
              "; ".join("%s: Tcont %s, Tpeak %s N m, Kt %s N m/A, R %s Ω, Jm %s kg m²" % ((k,) + tuple(fmt(x) for x in v))
                        for k, v in MOTORS.items()) +
              ". Gear ratio = %d rpm motor speed / joint velocity limit. Acceleration limit = velocity limit / %.2f s "
              "(axes 1–3) or / %.2f s (wrist); jerk = acceleration / %.2f s. Friction: Coulomb = %d %% of the rated "
              "joint torque G·Tcont·η; viscous gives %d %% of it at the velocity limit." % (
                  MOTOR_MAX_RPM, T_RAMP_MAIN, T_RAMP_WRIST, T_JERK, FRICTION_FRACTION * 100, FRICTION_FRACTION * 100)]
    if rb["name"] in ("abb_irb6700_200_260", "abb_irb4600_40_255", "staubli_tx200"):
        L += ["", "### How the inertials were estimated", "",
              "1. Total weight: see *Robot weight used* above.",
              "2. Split over base_link, link_1 … link_6 in proportion to the KR 210 L150 CAD link masses "
              "(%s kg; %s). These CAD masses are ~4× too large in absolute terms, but their distribution "
              "is the only public per-link mass breakdown of a large 6-axis arm." % (
                  ", ".join(fmt(m) for m in KR210_MASSES), SRC_KR210),
              "3. Each link is a uniform solid cylinder between two points of its frame (table column *source*): "
              "base = pedestal, link_1 = turret from the pedestal top to the A2 axis, link_2 = lower arm A2→A3, "
              "link_3 = elbow housing centred on A3 (wrist motors balance the forearm), link_4 = forearm A4→wrist centre, "
              "link_5 = wrist housing wrist centre→flange, link_6 = flange disc. Radii are rough half-widths of the "
              "housings (ESTIMATE). CoM = cylinder centre; inertia = solid-cylinder tensor rotated into link axes.",
              "4. Expected accuracy: total mass ±20 %, CoMs ±0.2 m, inertias ±50 %. Good enough to rank toolpaths, not "
              "to predict absolute energy to better than ~±30 %."]
    if check.get(rb["name"]):
        L += ["", "## Checks (`python3 tools/robots/make_robots.py --check`)", ""] + ["- " + c for c in check[rb["name"]]]
    L += ["", "## Limitations", ""] + ["- " + n for n in rb["notes"]] + [
        "- Drive data (gear ratios, motor constants, rotor inertias, friction, efficiencies, acceleration and jerk limits) "
        "are not published by the manufacturer%s; all such values marked ESTIMATE are engineering estimates." % (
            " except the PUMA values from Corke 1994" if rb["name"] == "puma560" else ""),
        "- No cable/hose drag, no temperature dependence of friction, no motor iron losses or drive-electronics losses "
        "beyond the cabinet standby power."]
    with open(path, "w") as f:
        f.write("\n".join(L) + "\n")


# ------------------------------------------------------------------------------------------------
# checks
# ------------------------------------------------------------------------------------------------
def parse_urdf(path):
    root = ET.parse(path).getroot()
    joints = {}
    for j in root.findall("joint"):
        o = j.find("origin")
        xyz = [float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
        rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
        ax = j.find("axis")
        axis = [float(v) for v in ax.get("xyz").split()] if ax is not None else [1, 0, 0]
        lim = j.find("limit")
        joints[j.find("child").get("link")] = dict(name=j.get("name"), type=j.get("type"), parent=j.find("parent").get("link"),
                                                   T=T_of(rpy_to_R(*rpy), xyz), axis=axis,
                                                   lower=float(lim.get("lower")) if lim is not None else 0,
                                                   upper=float(lim.get("upper")) if lim is not None else 0,
                                                   mimic=j.find("mimic") is not None)
    links = {}
    for l in root.findall("link"):
        i = l.find("inertial")
        if i is not None:
            o = i.find("origin")
            links[l.get("name")] = (float(i.find("mass").get("value")), [float(v) for v in o.get("xyz").split()])
    return joints, links


def chain(joints, tip):
    c = []
    link = tip
    while link in joints:
        c.append(link)
        link = joints[link]["parent"]
    return link, c[::-1]


def fk_urdf(joints, tip, q, want_links=False):
    """Pose of `tip` for actuated joint values q (in chain order); also every link frame if want_links."""
    root, ch = chain(joints, tip)
    T = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    k = 0
    frames = {root: T}
    axes = []
    for link in ch:
        j = joints[link]
        T = matmul(T, j["T"])
        if j["type"] in ("revolute", "continuous"):
            axes.append((T_p(T), mv(T_R(T), j["axis"]), link))
            T = matmul(T, T_of(axis_angle(j["axis"], q[k]), [0, 0, 0]))
            k += 1
        elif j["type"] == "prismatic":
            raise ValueError("prismatic joint in the arm chain")
        frames[link] = T
    return (T, frames, axes) if want_links else T


def opw_fk(o, qs):
    q = [qs[i] * o["signs"][i] - o["offsets"][i] for i in range(6)]
    a1, a2, b, c1, c2, c3, c4 = (o[k] for k in ("a1", "a2", "b", "c1", "c2", "c3", "c4"))
    psi3 = math.atan2(a2, c3)
    k = math.sqrt(a2 * a2 + c3 * c3)
    cx1 = c2 * math.sin(q[1]) + k * math.sin(q[1] + q[2] + psi3) + a1
    cy1 = b
    cz1 = c2 * math.cos(q[1]) + k * math.cos(q[1] + q[2] + psi3)
    cx0 = cx1 * math.cos(q[0]) - cy1 * math.sin(q[0])
    cy0 = cx1 * math.sin(q[0]) + cy1 * math.cos(q[0])
    cz0 = cz1 + c1
    R0c = matmul(rz(q[0]), ry(q[1] + q[2]))
    Rce = matmul(rz(q[3]), matmul(ry(q[4]), rz(q[5])))
    R = matmul(R0c, Rce)
    p = [cx0 + c4 * R[0][2], cy0 + c4 * R[1][2], cz0 + c4 * R[2][2]]
    return T_of(R, p)


def pose_err(A, B):
    dp = max(abs(A[i][3] - B[i][3]) for i in range(3))
    dR = max(abs(A[i][j] - B[i][j]) for i in range(3) for j in range(3))
    return dp, dR


def random_q(joints, tip, rng):
    _, ch = chain(joints, tip)
    return [rng.uniform(joints[l]["lower"], joints[l]["upper"]) for l in ch if joints[l]["type"] == "revolute"]


def gravity_torques(joints, links, tip, q, payload):
    """Static joint torques holding the arm (pure Python): tau_i = axis_i . sum_{j downstream} (c_j - p_i) x (m_j g)."""
    T, frames, axes = fk_urdf(joints, tip, q, want_links=True)
    _, ch = chain(joints, tip)
    masses = []
    for link in ch:
        if link in links:
            m, c = links[link]
            Tl = frames[link]
            masses.append((ch.index(link), m, [a + b for a, b in zip(mv(T_R(Tl), c), T_p(Tl))]))
    masses.append((len(ch), payload["mass"], [a + b for a, b in zip(mv(T_R(T), payload["com"]), T_p(T))]))
    tau = []
    for (p, ax, link) in axes:
        idx = ch.index(link)
        t = 0.0
        for (li, m, c) in masses:
            if li >= idx:
                f = [0, 0, -m * G0]
                t += sum(a * b for a, b in zip(ax, cross([c[i] - p[i] for i in range(3)], f)))
        tau.append(-t)   # torque the motor must supply
    return tau


def balancer_shape(a, b, q):
    """printwatt `balancer` regressor [dL/dq, (L - L_min) dL/dq] at q (rad from upright)."""
    L = math.sqrt(a * a + b * b - 2 * a * b * math.cos(q))
    dl = a * b * math.sin(q) / L
    return [dl, (L - abs(b - a)) * dl]


def size_balancer(rb, urdf_path):
    """Size the nominal axis-2 balancer (F0, k >= 0) by least squares; see BALANCER_SHARE."""
    B = rb.get("balancer")
    if not B:
        return
    joints, links = parse_urdf(urdf_path)
    a, b = B["a"][0], B["b"][0]

    def tau2(q2):
        return gravity_torques(joints, links, "tool0", [0.0, q2, 0.0, 0.0, 0.0, 0.0], rb["payload"])[1]
    t0 = tau2(0.0)
    X, y = [], []
    for deg in range(-BALANCER_RANGE_DEG, BALANCER_RANGE_DEG + 1):
        q = deg * D2R
        X.append(balancer_shape(a, b, q))
        y.append(-BALANCER_SHARE * (tau2(q) - t0))
    s00 = sum(r[0] * r[0] for r in X)
    s01 = sum(r[0] * r[1] for r in X)
    s11 = sum(r[1] * r[1] for r in X)
    g0 = sum(r[0] * t for r, t in zip(X, y))
    g1 = sum(r[1] * t for r, t in zip(X, y))
    det = s00 * s11 - s01 * s01
    F0, k = (s11 * g0 - s01 * g1) / det, (s00 * g1 - s01 * g0) / det
    if F0 < 0 or k < 0:   # active bound: the better one-parameter fit
        cands = [(max(g0 / s00, 0.0), 0.0), (0.0, max(g1 / s11, 0.0))]
        F0, k = min(cands, key=lambda c: sum((c[0] * r[0] + c[1] * r[1] - t) ** 2 for r, t in zip(X, y)))
    F0, k = float("%.4g" % F0), float("%.4g" % k)
    ach = []
    for q in (-BALANCER_RANGE_DEG * D2R, BALANCER_RANGE_DEG * D2R):
        sh = balancer_shape(a, b, q)
        ach.append((F0 * sh[0] + k * sh[1]) / -(tau2(q) - t0))
    B.update(F0=F0, k=k, achieved=ach)


def run_checks(rb, urdf_path):
    out = []
    joints, links = parse_urdf(urdf_path)
    rng = random.Random(1234)
    N = 2000
    if rb["opw"]:
        ep = eR = 0.0
        for _ in range(N):
            q = random_q(joints, "tool0", rng)
            a, b = fk_urdf(joints, "tool0", q), opw_fk(rb["opw"], q)
            dp, dR = pose_err(a, b)
            ep, eR = max(ep, dp), max(eR, dR)
        out.append("OPW forward kinematics vs URDF chain base_link→tool0, %d random poses within the joint limits: "
                   "max position error %.2e m, max rotation-matrix element error %.2e." % (N, ep, eR))
    ref = {"abb_irb6700_200_260": ("abb_irb6700/irb6700_200_260.urdf", "tool0"),
           "abb_irb4600_40_255": ("abb_irb4600/irb4600_40_255.urdf", "tool0"),
           "ur10e": ("ur10e/ur10e.urdf", "tool0"),
           "puma560": ("puma560/puma560_corke1994_generated.urdf", "flange")}.get(rb["name"])
    if ref and os.path.exists(os.path.join(REF, ref[0])):
        rj, rl = parse_urdf(os.path.join(REF, ref[0]))
        ep = eR = 0.0
        root, _ = chain(rj, ref[1])
        for _ in range(N):
            q = random_q(joints, "tool0", rng)
            a = fk_urdf(joints, "tool0", q)
            bT = fk_urdf(rj, ref[1], q)
            if rb["name"] == "ur10e":   # reference chain starts at 'world' = base_link (identity)
                pass
            dp, dR = pose_err(a, bT)
            ep, eR = max(ep, dp), max(eR, dR)
        out.append("tool0 vs the source URDF (%s, link %s), %d random poses: max position error %.2e m, max rotation "
                   "error %.2e." % (ref[0].split("/")[-1], ref[1], N, ep, eR))
    # static gravity torque with payload, worst case over random poses; compared with the motor peak capability
    gmax = [0.0] * 6
    for _ in range(N):
        q = random_q(joints, "tool0", rng)
        t = gravity_torques(joints, links, "tool0", q, rb["payload"])
        gmax = [max(a, abs(b)) for a, b in zip(gmax, t)]
    cap = []
    for i, d in enumerate(rb["drives"]):
        G, eta = d["gear_ratio"][0], d["gear_efficiency"][0]
        if d["motor_class"] in MOTORS:
            Tc, Tp = MOTORS[d["motor_class"]][:2]
            cap.append("%s %.0f N m (motor %.1f N m = %.0f %% of Tcont %s)" % (d["name"], gmax[i], gmax[i] / G / eta,
                                                                             100 * gmax[i] / G / eta / Tc, fmt(Tc)))
        else:
            cap.append("%s %.1f N m (motor %.3f N m)" % (d["name"], gmax[i], gmax[i] / G / eta))
    out.append("Max static gravity torque with the drive.toml payload over %d random poses (pure-Python check): %s." % (
        N, "; ".join(cap)))
    return out


def main():
    do_check = "--check" in sys.argv
    rbs = [f() for f in ROBOTS]
    checks = {}
    for rb in rbs:
        d = os.path.join(ROOT, "robots", rb["name"])
        os.makedirs(d, exist_ok=True)
        write_urdf(rb, os.path.join(d, "robot.urdf"))
        size_balancer(rb, os.path.join(d, "robot.urdf"))
        write_drive(rb, os.path.join(d, "drive.toml"))
        if do_check:
            checks[rb["name"]] = run_checks(rb, os.path.join(d, "robot.urdf"))
            for c in checks[rb["name"]]:
                print("%s: %s" % (rb["name"], c))
        write_readme(rb, os.path.join(d, "README.md"), checks)
    write_summary(rbs)


def write_summary(rbs):
    q = {"abb_irb6700_200_260": "kinematics good ([ROS-I], OPW verified); inertials and drives ESTIMATE (weight itself estimated)",
         "abb_irb4600_40_255": "kinematics good ([ROS-I] + ABB drawing); weight [DERIVED] from foundation load; inertials/drives ESTIMATE",
         "staubli_tx200": "geometry [3rd] consistent with [DS]; limits and weight [DS]; inertials/drives ESTIMATE",
         "ur10e": "kinematics, masses, CoMs official [ROS-I]; inertias APPROX; drives ESTIMATE",
         "puma560": "complete published model (inertials, Jm, G, friction) [3rd]; Kt/R and speed limits ESTIMATE"}
    L = ["# Shipped robots", "",
         "Generated by `tools/robots/make_robots.py` (run it to regenerate; `--check` adds the FK checks). "
         "Each directory holds `robot.urdf` (kinematics, limits, inertials), `drive.toml` (payload, tool, cabinet, "
         "drive-train data) and a `README.md` with the source of every number.", "",
         "| Directory | Robot | Reach (m) | Rated payload (kg) | Joints | Link masses in URDF (kg) | OPW | Provenance quality |",
         "|---|---|---|---|---|---|---|---|"]
    for rb in rbs:
        act = [j for j in rb["joints"] if j["type"] != "fixed" and not j["mimic"]]
        pas = [j for j in rb["joints"] if j["type"] != "fixed" and j["mimic"]]
        L.append("| `%s` | %s | %s | %s | %d revolute%s | %.1f | %s | %s |" % (
            rb["name"], rb["title"], fmt(rb["reach"][0]), fmt(rb["rated"][0]), len(act),
            (" + %d passive mimic (%s)" % (len(pas), ", ".join(j["name"] for j in pas))) if pas else "",
            sum(l.get("mass", 0) for l in rb["links"]), "yes" if rb["opw"] else "no", q[rb["name"]]))
    L += ["", "Conventions: SI units; inertia about the CoM in link axes; `tool0` has z out of the flange (ROS-I); "
          "OPW sets follow opw_kinematics (q_opw = q·sign − offset). The drive data of every industrial arm are "
          "ESTIMATES: energy results for them rank toolpaths, they are not calibrated predictions.",
          "", "Reference data computed with pinocchio from these files: `tests/data/pinocchio/` (see `tools/reference/`).",
          "", "## Drive-file tables beyond the drive train", "",
          "- `[effects]` (robots with an axis-2 balancer: IRB 6700, IRB 4600, TX200): `balancer_joint` (1-based axis), "
          "`balancer_lever_m` (lever a of the cylinder's end on the moving link, m), `balancer_base_m` (distance b of its "
          "fixed end from the axis, m), `balancer_upright_rad` (joint angle at which the cylinder is shortest), "
          "`balancer_preload_n` (force F0 at that angle, N) and `balancer_stiffness_n_per_m` (k, N/m). "
          "The torque is that of a spring cylinder between the two ends (equations in `docs/effects.md`); every value "
          "names its source, the forces are SIZED (ESTIMATE) to carry 70 % of the change of the static axis-2 torque.",
          "- `[tool.geometry]` (flange frame, m): `head_radius_m` (the print head, a cylinder from the flange to the "
          "nozzle tip), `hose_radius_m`, `hose_from_m`, `hose_to_m` (the material hose as a straight capsule). "
          "ESTIMATE for every shipped robot: the head is the payload's cylinder, the hose a 2-inch concrete hose "
          "(60 mm OD; 20 mm for the lab-scale extruders of the UR10e and PUMA 560) up the side of the head. The head "
          "is exempt from bed and part checks (it prints on them).",
          "- `[uncertainty]`: half-widths of uniform ranges of the estimated numbers (`link_mass_rel`, `link_com_m`, "
          "`link_inertia_rel`, `payload_mass_rel`, `torque_constant_rel`, `winding_resistance_rel`, `viscous_rel`, "
          "`coulomb_rel`, `gear_efficiency_abs`, `standby_power_rel`, and for balanced arms "
          "`balancer_absent_probability`, `balancer_force_rel`), each with its reason; drawn by "
          "`printwatt optimise --uncertainty N`. A calibrated robot (written by `identify`) draws its identified "
          "parameters from their standard errors instead.",
          "", "## Collision geometry", "",
          "The IRB 6700, IRB 4600 and UR10e have `<collision>` meshes on the base and every link: convex pieces made "
          "from the published meshes (ros-industrial/abb_experimental, Apache-2.0; "
          "UniversalRobots/Universal_Robots_ROS2_Description, BSD-3-Clause): one hull of the published collision mesh "
          "per link (at most 64 vertices), and for the ABB forearms, whose end forks around the wrist, a convex "
          "decomposition of the published visual mesh (4 pieces on the IRB 6700, 8 on the IRB 4600), so the fork is "
          "open; each piece grown so that together they contain the source mesh, in "
          "`collision/` with a README naming source, commit and licence (made once by "
          "`tools/robots/collision_hulls.py`, which `--check` verifies against the sources). "
          "The IRB 6700's balancer cylinder and piston (mimic links) are not modelled. "
          "The TX200 and PUMA 560 have no published meshes under a licence that allows shipping them: their links are "
          "capsules from each joint origin to the next, sized as a fraction of the reach (base 0.07 R, arms 0.045 R, "
          "wrist 0.025 R: ESTIMATE, rough half-widths of the housings). Every arm adds the print head and hose of "
          "`[tool.geometry]`. A user's URDF with `<collision>` boxes, cylinders, spheres or STL/OBJ meshes (as convex "
          "hulls) is used as given."]
    with open(os.path.join(ROOT, "robots", "README.md"), "w") as f:
        f.write("\n".join(L) + "\n")


if __name__ == "__main__":
    main()
