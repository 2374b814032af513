; bad number
G21 G90
G0 X0 Y0 Z0
G1 X10 Yabc F600
