; A floor plan larger than one arm's reach, for multi-station plans (printwatt stations):
; 4 rooms of 3000 x 3000 mm in a row, 12000 x 3000 mm outside (nozzle
; centreline), a 1500 mm door opening in the middle of every cross wall (y 750 to
; 2250 mm: a crawler drives from room to room, a track runs through them),
; 18 straight wall pieces printed one after the other, each in
; 2 layers of 20 mm back and forth (the nozzle rises at the end of a layer while
; extruding), with a lifted travel (M5, G0 50 mm up, across, down, M3) between pieces.
; Print 150 mm/s (F9000), travel 200 mm/s (F12000). Part frame: origin at the outside
; corner of the first room on the bed; the robot stands on the same floor (z = 0).
; Made up for printwatt as an example (not from a paper).
; Hand computation: 18 pieces, 31500 mm per layer, 63000 mm
; extruded along the walls plus 360 mm of rises.
; generated, do not edit, regenerate with: python3 paths/generate.py
G21
G90
G17
G0 X0 Y0 Z20 F12000
; piece 1: (0, 0) to (3000, 0) mm
M3
G1 F9000
G1 X3000 Y0
G1 Z40
G1 X0 Y0
M5
G0 Z70 F12000
G0 X3000 Y0
G0 Z20
; piece 2: (3000, 0) to (3000, 750) mm
M3
G1 F9000
G1 X3000 Y750
G1 Z40
G1 X3000 Y0
M5
G0 Z70 F12000
G0 X3000 Y2250
G0 Z20
; piece 3: (3000, 2250) to (3000, 3000) mm
M3
G1 F9000
G1 X3000 Y3000
G1 Z40
G1 X3000 Y2250
M5
G0 Z70 F12000
G0 X3000 Y3000
G0 Z20
; piece 4: (3000, 3000) to (0, 3000) mm
M3
G1 F9000
G1 X0 Y3000
G1 Z40
G1 X3000 Y3000
M5
G0 Z70 F12000
G0 X0 Y3000
G0 Z20
; piece 5: (0, 3000) to (0, 2250) mm
M3
G1 F9000
G1 X0 Y2250
G1 Z40
G1 X0 Y3000
M5
G0 Z70 F12000
G0 X0 Y750
G0 Z20
; piece 6: (0, 750) to (0, 0) mm
M3
G1 F9000
G1 X0 Y0
G1 Z40
G1 X0 Y750
M5
G0 Z70 F12000
G0 X3000 Y0
G0 Z20
; piece 7: (3000, 0) to (6000, 0) mm
M3
G1 F9000
G1 X6000 Y0
G1 Z40
G1 X3000 Y0
M5
G0 Z70 F12000
G0 X6000 Y0
G0 Z20
; piece 8: (6000, 0) to (6000, 750) mm
M3
G1 F9000
G1 X6000 Y750
G1 Z40
G1 X6000 Y0
M5
G0 Z70 F12000
G0 X6000 Y2250
G0 Z20
; piece 9: (6000, 2250) to (6000, 3000) mm
M3
G1 F9000
G1 X6000 Y3000
G1 Z40
G1 X6000 Y2250
M5
G0 Z70 F12000
G0 X6000 Y3000
G0 Z20
; piece 10: (6000, 3000) to (3000, 3000) mm
M3
G1 F9000
G1 X3000 Y3000
G1 Z40
G1 X6000 Y3000
M5
G0 Z70 F12000
G0 X6000 Y0
G0 Z20
; piece 11: (6000, 0) to (9000, 0) mm
M3
G1 F9000
G1 X9000 Y0
G1 Z40
G1 X6000 Y0
M5
G0 Z70 F12000
G0 X9000 Y0
G0 Z20
; piece 12: (9000, 0) to (9000, 750) mm
M3
G1 F9000
G1 X9000 Y750
G1 Z40
G1 X9000 Y0
M5
G0 Z70 F12000
G0 X9000 Y2250
G0 Z20
; piece 13: (9000, 2250) to (9000, 3000) mm
M3
G1 F9000
G1 X9000 Y3000
G1 Z40
G1 X9000 Y2250
M5
G0 Z70 F12000
G0 X9000 Y3000
G0 Z20
; piece 14: (9000, 3000) to (6000, 3000) mm
M3
G1 F9000
G1 X6000 Y3000
G1 Z40
G1 X9000 Y3000
M5
G0 Z70 F12000
G0 X9000 Y0
G0 Z20
; piece 15: (9000, 0) to (12000, 0) mm
M3
G1 F9000
G1 X12000 Y0
G1 Z40
G1 X9000 Y0
M5
G0 Z70 F12000
G0 X12000 Y0
G0 Z20
; piece 16: (12000, 0) to (12000, 750) mm
M3
G1 F9000
G1 X12000 Y750
G1 Z40
G1 X12000 Y0
M5
G0 Z70 F12000
G0 X12000 Y2250
G0 Z20
; piece 17: (12000, 2250) to (12000, 3000) mm
M3
G1 F9000
G1 X12000 Y3000
G1 Z40
G1 X12000 Y2250
M5
G0 Z70 F12000
G0 X12000 Y3000
G0 Z20
; piece 18: (12000, 3000) to (9000, 3000) mm
M3
G1 F9000
G1 X9000 Y3000
G1 Z40
G1 X12000 Y3000
M5
G0 Z140
M30
