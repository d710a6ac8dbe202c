#!/usr/bin/env bash
# scripts/outputs.sh BIN OUTDIR: everything the threadcut command BIN writes for every bundled
# example and test program — expand (G-code, JSON lines), passes (text, JSON), check (JSON; text
# with a stock), plot, convert to every lathe controller — under each lathe controller, plus thread
# and mill: standard output, standard error and exit status, one file each. Run it with the
# command before and after a change, then `diff -r` the two folders: a refactor leaves them equal.
set -u
BIN=$(realpath "$1"); mkdir -p "$2"; OUT=$(realpath "$2")
cd "$(dirname "$0")/.."
CS="gsk980 omniturn ab9 fanuc fanuc15 fanuc-b haas linuxcnc sinumerik"
for f in examples/*.nc examples/*.ngc examples/*.mpf examples/*.apt tests/data/real/* tests/data/linuxcnc-ref/*.ngc; do
  b=$(echo "$f" | tr / _)
  for c in $CS; do
    r(){ local name=$1; shift; "$BIN" "$@" >"$OUT/$b.$c.$name.out" 2>"$OUT/$b.$c.$name.err"; echo $? >"$OUT/$b.$c.$name.rc"; }
    r expand expand "$f" --controller $c
    r jsonl expand "$f" --controller $c --format jsonl
    r passes passes "$f" --controller $c --format json
    r passest passes "$f" --controller $c
    r check check "$f" --controller $c --format json
    r checkt check "$f" --controller $c --stock-diameter 40 --stock-start 0
    r plot plot "$f" --controller $c
    for t in $CS; do r conv-$t convert "$f" --from $c --to $t; done
  done
done
for t in M20x2.5-6g 1/2-13UNC-2A "Tr40x7" "1/2 NPT" M10; do b=$(echo "$t"|tr '/ ' '__'); "$BIN" thread "$t" --format json >"$OUT/thread.$b.out" 2>&1; done
for c in centroid fanuc-mill linuxcnc-mill; do for i in --internal --external; do "$BIN" mill --thread M20x2.5 $i --length 20 --tool-diameter 12 --feed 300 --controller $c >"$OUT/mill.$c$i.out" 2>&1; done; done
