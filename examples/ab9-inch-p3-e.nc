(Allen-Bradley 9/Series G78: 1/2-13 UNC external, E13 threads per inch, P3 constant depth)
G20
G90 G00 X.6 Z.2
G78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3
