G0 X80 Z10 (no end
