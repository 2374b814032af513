; Circular column: a circle of radius 150 mm (nozzle centreline) printed in 5
; layers of 20 mm with G2 full circles in I/J form; the last layer is a quarter circle
; (I/J) followed by the remaining three quarters as one R-form arc with R < 0 (the long
; arc). Extrusion by M3 (on) / M5 (off); 150 mm/s (F9000). Made up for printwatt.
; Hand computation: print length 5 x 2 pi 150 + 4 x 20 = 4792.3890 mm.
; generated, do not edit, regenerate with: python3 paths/generate.py
G21 G90 G17
G0 X150 Y0 Z20 F12000
M3 S1200
G1 F9000
G2 X150 Y0 I-150 J0 ; layer 1, full circle
G1 Z40
G2 X150 Y0 I-150 J0 ; layer 2, full circle
G1 Z60
G2 X150 Y0 I-150 J0 ; layer 3, full circle
G1 Z80
G2 X150 Y0 I-150 J0 ; layer 4, full circle
G1 Z100
G2 X0 Y-150 I-150 J0 ; layer 5, quarter
G2 X150 Y0 R-150 ; three quarters, R form (long arc)
M5
G0 Z200
M30
