G0 X80 Z10
(café ÿþ comment)
G78 X60 Z-30 P2 F2
