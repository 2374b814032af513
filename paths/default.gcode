; printwatt's default path: one 3DCP layer, a rounded rectangle 2000 x 1000 mm
; (nozzle centreline) with corner radius 100 mm, printed at 150 mm/s (F9000) with the
; nozzle 20 mm above the part origin, which is the centre of the rectangle on the bed.
; Made up for printwatt as a typical wall outline of a small 3DCP building element.
; Hand computation: length 5828.3185 mm.
; generated, do not edit, regenerate with: python3 paths/generate.py
G21
G90
G17
G0 X0 Y-500 Z20 F12000
; MARK Ps
M3
G1 F9000
G1 X900 Y-500
G3 X1000 Y-400 I0 J100
G1 Y400
G3 X900 Y500 I-100 J0
G1 X-900
G3 X-1000 Y400 I0 J-100
G1 Y-400
G3 X-900 Y-500 I100 J0
G1 X0
; MARK Pe
M5
M30
