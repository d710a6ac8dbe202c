#!/bin/sh
# TB029's two examples (seed 004): a one-inch internal thread (major 1.0000") and a 1"-8 external
# thread (minor 0.8492", start radius 0.4246"), on the Centroid profile. Run from the repository root.
set -eu
TC=${TC:-cargo run -q --}

echo "== 1-8 UNC-2B internal, 0.75\" deep, 0.5\" single-point thread mill, bottom-up (climb), G41"
$TC mill --thread "1-8 UNC-2B" --internal --length 0.75 --tool-diameter 0.5 --feed 12 \
    --controller centroid --d-register 1

echo "== 1-8 UNC-2A external, 1\" long, TB029's radial start at 0.4246\""
$TC mill --thread "1-8 UNC-2A" --external --length 1 --tool-diameter 0.75 --feed 15 \
    --controller centroid --d-register 2 --lead radial
