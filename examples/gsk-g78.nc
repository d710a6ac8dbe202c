%
O0078 (M30x2 EXTERNAL THREAD, GSK G78)
(Seed 001's example with infeed mode r = 0 and a 3 mm lead; see docs/dialects/gsk-g78.md)
G00 X80 Z10
T0101 M03 S300
G78 P020045 Q0.15 R0.5
G78 X60 Z-60 P3 Q1.8 F3 J1.5 K2
G00 X80 Z10
(M30x2: k = 0.6134 x 2 = 1.227, left-flank infeed, 60 deg tool)
G00 X32 Z5
G78 P020160 Q0.1 R0.05
G78 X27.546 Z-30 P1.227 Q0.4 F2
G00 X100 Z100
M30
%
