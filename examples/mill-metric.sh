#!/bin/sh
# Metric thread milling on Fanuc and LinuxCNC: an M16 nut with a 3-pass constant-area plan and a
# 10 mm single-point mill, and an M20 bolt with a 6-tooth mill as the tool-centre path, as JSON lines.
set -eu
TC=${TC:-cargo run -q --}

$TC mill --thread M16-6H --internal --length 20 --tool-diameter 10 --passes 3 --feed 250 \
    --center 40,-25 --start-z -3 --controller fanuc-mill --d-register 12

$TC mill --thread M20 --external --length 15 --tool-diameter 12 --teeth 6 --feed 400 \
    --comp none --controller linuxcnc-mill --format jsonl
