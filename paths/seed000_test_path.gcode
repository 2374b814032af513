; Seed 000 test path, in the spirit of Figure 1 of seed paper 000 ("energy consumption
; model of a robotic arm in 3D concrete printing", ABB arm, RAPID): a closed printed path
; with start, middle and end points Ps, Pm, Pe. The paper shows the path but gives no
; dimensions; ASSUMED: a rounded rectangle 400 x 300 mm (nozzle centreline), corner
; radius 50 mm, 3 layers of 20 mm printed continuously (the nozzle rises
; 20 mm at the seam), 100 mm/s (F6000, assumed).
; Part frame: origin = the path's central reference point (the centre of the rectangle) on
; the print bed; layer k has the nozzle tip at z = 20*k mm. The placements P1-P5 of the
; paper's Table 1 (paths/placements/p1-p5.csv) put this origin in the robot base frame.
; Hand computation: one loop 1314.1593 mm, total 3982.4778 mm; Pm at half of it.
; generated, do not edit, regenerate with: python3 paths/generate.py
G21
G90
G17
G0 X0 Y-150 Z20 F12000
; MARK Ps
M3
G1 F6000
;LAYER:1
G1 X150 Y-150
G3 X200 Y-100 I0 J50
G1 Y100
G3 X150 Y150 I-50 J0
G1 X-150
G3 X-200 Y100 I0 J-50
G1 Y-100
G3 X-150 Y-150 I50 J0
G1 X0
G1 Z40
;LAYER:2
G1 X150 Y-150
G3 X200 Y-100 I0 J50
G1 Y100
G3 X150 Y150 I-50 J0
G1 X0
; MARK Pm
G1 X-150
G3 X-200 Y100 I0 J-50
G1 Y-100
G3 X-150 Y-150 I50 J0
G1 X0
G1 Z60
;LAYER:3
G1 X150 Y-150
G3 X200 Y-100 I0 J50
G1 Y100
G3 X150 Y150 I-50 J0
G1 X-150
G3 X-200 Y100 I0 J-50
G1 Y-100
G3 X-150 Y-150 I50 J0
G1 X0
; MARK Pe
M5
G0 Z160
M30
