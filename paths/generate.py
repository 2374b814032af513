#!/usr/bin/env python3
"""Generate the shipped G-code paths of printwatt (paths/*.gcode).

Run from the repository root:  python3 paths/generate.py
The files it writes say "generated, do not edit, regenerate with python3 paths/generate.py".
wall_rapid.mod and placements/p1-p5.csv are written by hand.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
STAMP = "; generated, do not edit, regenerate with: python3 paths/generate.py\n"


def f(v):
    s = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def write(name, text):
    with open(os.path.join(HERE, name), "w") as fh:
        fh.write(text)


# --- seed paper 001 (Stäubli TX200 machining trajectories, Fig. 4 and Table 1) -------------
SEED001_HEADER = """; {title}
; Source: seed paper 001, "Modelling the energy consumption of an industrial robot with
; different types of trajectory for machining tasks" (Staubli TX200), Fig. 4 and Table 1.
; The paper gives no dimensions. Table 1's energy / (energy per length) gives the path
; lengths: x 8922.42/63.73 = 140.0 mm; y2x 176.6 mm (r = 8) and 174.9 mm (r = 12);
; y2x2y 213.1 mm (r = 8) and 209.7 mm (r = 12). A 90-degree corner of radius r shortens
; a path by r(2 - pi/2), so these are consistent with legs y 40 mm, x 140 mm (, y 40 mm):
; sharp lengths 140, 180 and 220 mm. ASSUMED: the last y leg of y2x2y continues in +y
; (a staircase; a U turn has the same length); the legs start at the part origin.
; Corners are real arcs (G2/G3) of radius {r}.
; ASSUMED feed: F3000 (50 mm/s), a typical robot machining feed; the paper gives none
; (its power levels, ~3.5 kW over 8922 J, suggest ~2.5 s for 140 mm, i.e. ~55 mm/s).
; Path length (hand computation): {length:.4f} mm.
""" + STAMP


def seed001():
    write("seed001_x.gcode",
          SEED001_HEADER.format(title="Seed 001 trajectory x: straight line of 140 mm along x.",
                                r="(none)", length=140.0)
          + "G21\nG90\nG17\nG0 X0 Y0 Z0\nG1 X140 F3000\nM30\n")
    for r in (8, 12):
        k = r * (2 - math.pi / 2)
        body = "G21\nG90\nG17\nG0 X0 Y0 Z0\n"
        body += f"G1 Y{f(40 - r)} F3000\n"
        body += f"G2 X{f(r)} Y40 I{f(r)} J0\n"
        body2 = body + "G1 X140\nM30\n"
        write(f"seed001_y2x_r{r}.gcode",
              SEED001_HEADER.format(title=f"Seed 001 trajectory y2x: 40 mm along +y, then 140 mm "
                                    f"along +x, corner radius {r} mm.", r=f"{r} mm",
                                    length=180 - k) + body2)
        body3 = body + f"G1 X{f(140 - r)}\nG3 X140 Y{f(40 + r)} I0 J{f(r)}\nG1 Y80\nM30\n"
        write(f"seed001_y2x2y_r{r}.gcode",
              SEED001_HEADER.format(title=f"Seed 001 trajectory y2x2y: 40 mm +y, 140 mm +x, 40 mm "
                                    f"+y, corner radius {r} mm.", r=f"{r} mm",
                                    length=220 - 2 * k) + body3)


def rounded_rect_ccw(w, h, r, mid_split=False):
    """G-code lines for one CCW loop of a rounded rectangle centred on the origin, starting and
    ending at the middle of the bottom edge (0, -h/2). With mid_split, the top edge is cut at
    x = 0 and a marker line '@MID' is inserted there."""
    a, b = w / 2, h / 2
    out = [f"G1 X{f(a - r)} Y{f(-b)}",
           f"G3 X{f(a)} Y{f(-b + r)} I0 J{f(r)}",
           f"G1 Y{f(b - r)}",
           f"G3 X{f(a - r)} Y{f(b)} I{f(-r)} J0"]
    if mid_split:
        out += ["G1 X0", "@MID"]
    out += [f"G1 X{f(-a + r)}",
            f"G3 X{f(-a)} Y{f(b - r)} I0 J{f(-r)}",
            f"G1 Y{f(-b + r)}",
            f"G3 X{f(-a + r)} Y{f(-b)} I{f(r)} J0",
            "G1 X0"]
    return out


def rr_length(w, h, r):
    return 2 * (w + h) - 8 * r + 2 * math.pi * r


def seed000():
    w, h, r, dz, layers = 400.0, 300.0, 50.0, 20.0, 3
    per = rr_length(w, h, r)
    total = layers * per + (layers - 1) * dz
    text = f"""; Seed 000 test path, in the spirit of Figure 1 of seed paper 000 ("energy consumption
; model of a robotic arm in 3D concrete printing", ABB arm, RAPID): a closed printed path
; with start, middle and end points Ps, Pm, Pe. The paper shows the path but gives no
; dimensions; ASSUMED: a rounded rectangle {f(w)} x {f(h)} mm (nozzle centreline), corner
; radius {f(r)} mm, {layers} layers of {f(dz)} mm printed continuously (the nozzle rises
; {f(dz)} mm at the seam), 100 mm/s (F6000, assumed).
; Part frame: origin = the path's central reference point (the centre of the rectangle) on
; the print bed; layer k has the nozzle tip at z = {f(dz)}*k mm. The placements P1-P5 of the
; paper's Table 1 (paths/placements/p1-p5.csv) put this origin in the robot base frame.
; Hand computation: one loop {per:.4f} mm, total {total:.4f} mm; Pm at half of it.
""" + STAMP + "G21\nG90\nG17\n"
    text += f"G0 X0 Y{f(-h / 2)} Z{f(dz)} F12000\n; MARK Ps\nM3\nG1 F6000\n"
    for k in range(layers):
        if k > 0:
            text += f"G1 Z{f(dz * (k + 1))}\n"
        text += f";LAYER:{k + 1}\n"
        for line in rounded_rect_ccw(w, h, r, mid_split=(k == 1)):
            text += "; MARK Pm\n" if line == "@MID" else line + "\n"
    text += "; MARK Pe\nM5\nG0 Z" + f(dz * layers + 100) + "\nM30\n"
    write("seed000_test_path.gcode", text)


def wall():
    length, width, dz, layers = 1200.0, 40.0, 15.0, 10
    per = 2 * (length + width)
    a, b = length / 2, width / 2
    ek = 0.05  # E per mm of path (arbitrary: only the sign of the change matters)
    text = f"""; Multi-layer wall, slicer style: a {f(length)} mm x {f(width)} mm rectangular outline
; (nozzle centreline), {layers} layers of {f(dz)} mm, absolute E (M82), retract/unretract,
; Z hop and travel between layers, the seam alternating between two corners, messages,
; heater/fan M-codes that a slicer emits and printwatt ignores.
; Made up for printwatt as a test and example (not from a paper).
; Print F9000 (150 mm/s), travel F12000 (200 mm/s).
; Hand computation: print length {layers} x {f(per)} = {f(layers * per)} mm, {layers} layers.
""" + STAMP
    text += ";FLAVOR:Marlin\nM82 ;absolute extrusion mode\nG21\nG90\nG28 ;home\nM104 S0\nM106 S0\n"
    e = 0.0
    corners = [(-a, -b), (a, -b), (a, b), (-a, b)]
    for k in range(layers):
        z = dz * (k + 1)
        s = 0 if k % 2 == 0 else 2
        order = [corners[(s + i) % 4] for i in range(5)]
        x0, y0 = order[0]
        text += f";LAYER:{k}\nM117 Layer {k + 1} of {layers}\n"
        if k == 0:
            text += f"G0 F12000 X{f(x0)} Y{f(y0)} Z{f(z)}\n"
        else:
            text += f"G1 F2400 E{f(e - 5)} ;retract\n"
            text += f"G0 F12000 Z{f(z + 10)}\nG0 X{f(x0)} Y{f(y0)}\nG0 Z{f(z)}\n"
            text += f"G1 F2400 E{f(e)} ;unretract\n"
        text += ";TYPE:WALL-OUTER\n"
        first = True
        for (x, y), (px, py) in zip(order[1:], order[:-1]):
            e += ek * math.hypot(x - px, y - py)
            text += f"G1 {'F9000 ' if first else ''}X{f(x)} Y{f(y)} E{e:.5f}\n"
            first = False
    text += f"G1 F2400 E{f(e - 5)}\nG0 F12000 Z{f(dz * layers + 50)}\nM107\nM84\n"
    write("wall_multilayer.gcode", text)


def column():
    r, dz, layers = 150.0, 20.0, 5
    total = layers * 2 * math.pi * r + (layers - 1) * dz
    text = f"""; Circular column: a circle of radius {f(r)} mm (nozzle centreline) printed in {layers}
; layers of {f(dz)} mm with G2 full circles in I/J form; the last layer is a quarter circle
; (I/J) followed by the remaining three quarters as one R-form arc with R < 0 (the long
; arc). Extrusion by M3 (on) / M5 (off); 150 mm/s (F9000). Made up for printwatt.
; Hand computation: print length {layers} x 2 pi {f(r)} + {layers - 1} x {f(dz)} = {total:.4f} mm.
""" + STAMP
    text += "G21 G90 G17\n"
    text += f"G0 X{f(r)} Y0 Z{f(dz)} F12000\nM3 S1200\nG1 F9000\n"
    for k in range(layers):
        if k > 0:
            text += f"G1 Z{f(dz * (k + 1))}\n"
        if k < layers - 1:
            text += f"G2 X{f(r)} Y0 I{f(-r)} J0 ; layer {k + 1}, full circle\n"
        else:
            text += f"G2 X0 Y{f(-r)} I{f(-r)} J0 ; layer {k + 1}, quarter\n"
            text += f"G2 X{f(r)} Y0 R{f(-r)} ; three quarters, R form (long arc)\n"
    text += f"M5\nG0 Z{f(dz * layers + 100)}\nM30\n"
    write("column_arcs.gcode", text)


def default():
    w, h, r, z = 2000.0, 1000.0, 100.0, 20.0
    per = rr_length(w, h, r)
    text = f"""; printwatt's default path: one 3DCP layer, a rounded rectangle {f(w)} x {f(h)} mm
; (nozzle centreline) with corner radius {f(r)} mm, printed at 150 mm/s (F9000) with the
; nozzle {f(z)} mm above the part origin, which is the centre of the rectangle on the bed.
; Made up for printwatt as a typical wall outline of a small 3DCP building element.
; Hand computation: length {per:.4f} mm.
""" + STAMP
    text += f"G21\nG90\nG17\nG0 X0 Y{f(-h / 2)} Z{f(z)} F12000\n; MARK Ps\nM3\nG1 F9000\n"
    text += "\n".join(rounded_rect_ccw(w, h, r)) + "\n; MARK Pe\nM5\nM30\n"
    write("default.gcode", text)


def floor():
    """A floor plan larger than one arm's reach: four rooms of 3 x 3 m in a row (12 x 3 m
    outside, nozzle centreline), a door opening in every cross wall (so a crawler can drive
    from room to room along the middle line, and a track can run through them), each wall piece
    printed in two layers back and forth, piece after piece, with a lifted travel between
    pieces."""
    rooms, rw, rh, dz, layers, door = 4, 3000.0, 3000.0, 20.0, 2, 1500.0
    d0, d1 = (rh - door) / 2, (rh + door) / 2
    pieces = []
    for k in range(rooms):
        x0, x1 = k * rw, (k + 1) * rw
        pieces.append(((x0, 0.0), (x1, 0.0)))  # bottom wall of the room
        pieces.append(((x1, 0.0), (x1, d0)))  # its right wall up to the door
        pieces.append(((x1, d1), (x1, rh)))  # and after it (the end wall for the last)
        pieces.append(((x1, rh), (x0, rh)))  # its top wall
        if k == 0:
            pieces.append(((x0, rh), (x0, d1)))  # the left end wall, its door
            pieces.append(((x0, d0), (x0, 0.0)))
    per_layer = sum(math.dist(a, b) for a, b in pieces)
    text = f"""; A floor plan larger than one arm's reach, for multi-station plans (printwatt stations):
; {rooms} rooms of {f(rw)} x {f(rh)} mm in a row, {f(rooms * rw)} x {f(rh)} mm outside (nozzle
; centreline), a {f(door)} mm door opening in the middle of every cross wall (y {f(d0)} to
; {f(d1)} mm: a crawler drives from room to room, a track runs through them),
; {len(pieces)} straight wall pieces printed one after the other, each in
; {layers} layers of {f(dz)} mm back and forth (the nozzle rises at the end of a layer while
; extruding), with a lifted travel (M5, G0 50 mm up, across, down, M3) between pieces.
; Print 150 mm/s (F9000), travel 200 mm/s (F12000). Part frame: origin at the outside
; corner of the first room on the bed; the robot stands on the same floor (z = 0).
; Made up for printwatt as an example (not from a paper).
; Hand computation: {len(pieces)} pieces, {f(per_layer)} mm per layer, {f(layers * per_layer)} mm
; extruded along the walls plus {f(len(pieces) * (layers - 1) * dz)} mm of rises.
""" + STAMP
    (sx, sy) = pieces[0][0]
    text += f"G21\nG90\nG17\nG0 X{f(sx)} Y{f(sy)} Z{f(dz)} F12000\n"
    for n, (a, b) in enumerate(pieces):
        if n > 0:
            text += f"M5\nG0 Z{f(dz + 50)} F12000\nG0 X{f(a[0])} Y{f(a[1])}\nG0 Z{f(dz)}\n"
        text += f"; piece {n + 1}: ({f(a[0])}, {f(a[1])}) to ({f(b[0])}, {f(b[1])}) mm\nM3\nG1 F9000\n"
        ends = [b, a]
        for k in range(layers):
            if k > 0:
                text += f"G1 Z{f(dz * (k + 1))}\n"
            e = ends[k % 2]
            text += f"G1 X{f(e[0])} Y{f(e[1])}\n"
    text += f"M5\nG0 Z{f(dz * layers + 100)}\nM30\n"
    write("floor_four_rooms.gcode", text)


if __name__ == "__main__":
    seed001()
    seed000()
    wall()
    column()
    default()
    floor()
