#!/usr/bin/env python3
"""scripts/pastes.py DIR: the 30,000-line pastes issue 28 times the page with (docs/performance.md),
one file per kind, named NAME.CONTROLLER: threading cycles of every controller run 10,000 or
15,000 times, one thread of 7,500 hand-written G32/G33 passes, one G92 thread of 29,990 passes,
plain feed moves, comments, a line the controller refuses 30,000 times, and a loop of 30,000
runs. Time one with `cargo build --release --example analyse -p threadcut-web`, then
`target/release/examples/analyse DIR/NAME.CONTROLLER CONTROLLER 3` (or paste it into the page)."""
import os
import sys


def write(directory, name, head, body, count):
    with open(os.path.join(directory, name), "w") as f:
        f.write(head)
        for i in range(count):
            f.write(body(i))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    os.makedirs(d, exist_ok=True)
    fanuc = "G21 G99\nG97 S500 M3\n"
    write(d, "fanuc-g76.fanuc", fanuc,
          lambda i: "G0 X22. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.933 Z-30. P1534 Q400 F2.5\n", 10000)
    write(d, "haas-g76.haas", "G21\nG97 S500 M3\n",
          lambda i: "G0 X22. Z5.\nG76 X16.933 Z-30. K1.534 D0.4 F2.5 A60\n", 15000)
    # One pass each (D as deep as the thread).
    write(d, "haas-once.haas", "G21\nG97 S500 M3\n",
          lambda i: "G0 X22. Z5.\nG76 X16.933 Z-30. K1.534 D2. F2.5 A60\n", 15000)
    write(d, "ab9.ab9", "G21\nG97 S500 M3\n",
          lambda i: "G0 X22. Z5.\nG78 X16.933 Z-30. F2.5 D0.4\nG0 X22.\n", 10000)
    write(d, "gsk-g78.gsk980", "",
          lambda i: "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n", 10000)
    write(d, "cycle97.sinumerik", "G18 G90 DIAMON\nS500 M3\n",
          lambda i: "G0 X22 Z5\nCYCLE97(2.5,,0,-30,20,20,3,3,1.534,0.05,30,0,5,2,3,1)\n", 15000)
    write(d, "lcnc-g76.linuxcnc", "G7 G21 G18\nS500 M3\n",
          lambda i: "G0 X22 Z5\nG76 P2.5 Z-30 I-1 J0.2 K1.534 Q29.5 L2 E1\n", 15000)
    write(d, "omniturn.omniturn", "G71\nM3 S500\n",
          lambda i: "G0 X.9 Z.2\nG33 X.66 Z-1.2 K.0984 D.01\nG0 X.9\n", 10000)
    # One thread of 7,500 passes, 0.002 mm apart, deepening 900 times over.
    write(d, "g32.fanuc", fanuc + "G0 X22. Z5.\n",
          lambda i: f"G0 X{19.9 - 0.002 * (i % 900):.3f}\nG32 Z-30. F2.5\nG0 X22.\nZ5.\n", 7500)
    write(d, "g33-radial.linuxcnc", "G7 G21 G18\nS500 M3\nG0 X22 Z5\n",
          lambda i: f"G0 X{19.9 - 0.002 * (i % 900):.3f}\nG33 Z-30 K2.5\nG0 X22\nZ5\n", 7500)
    # One G92 thread: 29,990 passes, X only.
    write(d, "g92.fanuc", fanuc + "G0 X22. Z5.\nG92 X19.9 Z-30. F2.5\n",
          lambda i: f"X{19.9 - 0.0005 * ((i + 1) % 3000):.3f}\n", 29990)
    write(d, "turn.gsk980", "G0 X80 Z10\n",
          lambda i: f"G1 X{20 + i % 50}.5 Z-{i % 40}.25 F0.2\n", 30000)
    write(d, "comments.gsk980", "", lambda i: "(JUST A COMMENT LINE ABOUT NOTHING)\n", 30000)
    write(d, "garbage.gsk980", "", lambda i: "G1 X10 Z5 Q? #\n", 30000)
    write(d, "whileloop.fanuc",
          fanuc + "#1=0\nWHILE[#1LT30000]DO1\nG0 X22. Z5.\n#1=#1+1\nEND1\nM30\n", lambda i: "", 0)


if __name__ == "__main__":
    main()
