(OmniTurn G33 seed 002: 15/16-20 internal thread, radius mode G73)
T8 (Internal threading tool)
X.4375Z.2
X.4425
G33X.46875Z-.75I.01K.05C
