(Allen-Bradley 9/Series G78: tapered external thread, I = radius change start to end, P4 alternating edges)
G20
G90 G00 X1.2 Z.25
G78 X.9 Z-1. K.05 D.015 F.0833 A60 P4 I-.03
