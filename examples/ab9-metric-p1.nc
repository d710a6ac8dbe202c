(Allen-Bradley 9/Series G78: M10x1.5 external, P1 constant amount on one edge, 60 degree tool)
(K = 0.6134 x 1.5 = 0.92 thread height, D = 0.35 first pass: threading-notes a.4)
G21
G90 G00 X12. Z5.
G78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1
G00 X50. Z50.
