(OmniTurn G33 seed 002: straight external thread, 20 pitch, major .494, radius mode G73)
T4F200
X0Z.2
X.237
G33X.212Z-.5I.012K.05PC
