#!/usr/bin/env python3
"""The pass table of every thread of a G-code or APT/CL program, as one CSV file.

    python examples/python/passes_csv.py examples/fanuc-m30x2-g76.nc --controller fanuc
    python examples/python/passes_csv.py part.nc -c haas -o part-passes.csv

One row per pass: the thread's line, where its passes come from (`cycle` or `moves`), the units,
then the columns of `threadcut passes` (depth from the crest as a radius, the infeed point X as
the program writes it and Z, the sharp-V chip area and its share, the simulated area, share,
cutting flank and chip thickness). Needs the `threadcut` package (`pip install ./python`).
"""

import argparse
import csv
import sys

import threadcut

COLUMNS = [
    "line", "source", "units", "pass", "kind", "depth", "increment", "x", "z",
    "area", "share", "sim_area", "sim_share", "cutting_flank", "chip_thickness",
]


def rows(program, controller, machine=None):
    """One dict per pass of every thread, in program order."""
    for cycle in threadcut.passes(program, controller, machine=machine):
        for p in cycle["passes"]:
            yield {
                "line": cycle["line"],
                "source": cycle["source"],
                "units": cycle["units"],
                "pass": p["n"],
                **{k: p[k] for k in COLUMNS[4:]},
            }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("program", help="the program (G-code or APT/CL)")
    ap.add_argument("-c", "--controller", required=True, choices=threadcut.controllers())
    ap.add_argument("--machine", help="a machine profile (TOML) for the controller")
    ap.add_argument("-o", "--output", help="the CSV file (default: standard output)")
    args = ap.parse_args(argv)
    with open(args.program, encoding="utf-8") as f:
        program = f.read()
    try:
        table = list(rows(program, args.controller, args.machine))
    except threadcut.InputError as e:
        # The program's place in the message is the file's.
        print(str(e).replace("<string>", args.program, 1), file=sys.stderr)
        if e.hint:
            print(f"  = help: {e.hint}", file=sys.stderr)
        return 2
    out = open(args.output, "w", newline="", encoding="utf-8") if args.output else sys.stdout
    try:
        writer = csv.DictWriter(out, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(table)
    finally:
        if args.output:
            out.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
