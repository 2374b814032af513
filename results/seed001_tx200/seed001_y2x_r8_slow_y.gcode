; Seed 001 trajectory y2x: 40 mm along +y, then 140 mm along +x, corner radius 8 mm.
; Source: seed paper 001, "Modelling the energy consumption of an industrial robot with
; different types of trajectory for machining tasks" (Staubli TX200), Fig. 4 and Table 1.
; The paper gives no dimensions. Table 1's energy / (energy per length) gives the path
; lengths: x 8922.42/63.73 = 140.0 mm; y2x 176.6 mm (r = 8) and 174.9 mm (r = 12);
; y2x2y 213.1 mm (r = 8) and 209.7 mm (r = 12). A 90-degree corner of radius r shortens
; a path by r(2 - pi/2), so these are consistent with legs y 40 mm, x 140 mm (, y 40 mm):
; sharp lengths 140, 180 and 220 mm. ASSUMED: the last y leg of y2x2y continues in +y
; (a staircase; a U turn has the same length); the legs start at the part origin.
; Corners are real arcs (G2/G3) of radius 8 mm.
; ASSUMED feed: F3000 (50 mm/s), a typical robot machining feed; the paper gives none
; (its power levels, ~3.5 kW over 8922 J, suggest ~2.5 s for 140 mm, i.e. ~55 mm/s).
; Path length (hand computation): 176.5664 mm.
; generated, do not edit, regenerate with: python3 paths/generate.py
G21
G90
G17
G0 X0 Y0 Z0
G1 Y32 F840
G2 X8 Y40 I8 J0 F3000
G1 X140
M30
