(OmniTurn G33 seed 002: three-start 20 pitch thread, K = 3 x .05, Z start offset by .15/3)
G90G94 F300
T4
X0Z.2
X.247
G33X.212Z-.5I.01K.15P
Z.25
G33X.212Z-.5I.01K.15P
Z.3
G33X.212Z-.5I.01K.15P
