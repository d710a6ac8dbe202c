(OmniTurn G33 seed 002: tapered thread in diameter mode G72; the seed prints I.00 5, read as I.005)
G90G94F300G72
T5
X0Z.2
X.415
G33 X.365 Z-.5 I.005K.0769 A.035
