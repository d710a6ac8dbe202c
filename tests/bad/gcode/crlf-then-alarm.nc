G0 X80 Z10
(CRLF line ends)
  G78 X60 Z-30 Q0.5 F2
