(OmniTurn G33 seed 002: clean-up single pass O on the first external example)
T4F300
X0Z.2
X.237
G33X.212Z-.5I.008K.05PCO
