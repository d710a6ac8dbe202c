"""The example script `examples/python/passes_csv.py`, run as a user would run it."""

import csv
import io
import subprocess
import sys

import pytest

import threadcut
from conftest import EXAMPLES, ROOT

SCRIPT = ROOT / "examples" / "python" / "passes_csv.py"


def run(*args):
    return subprocess.run(
        [sys.executable, str(SCRIPT), *args], cwd=ROOT, capture_output=True, text=True
    )


@pytest.mark.parametrize(
    "name,controller",
    [("fanuc-m30x2-g76.nc", "fanuc"), ("haas-m24x3-two-start.nc", "haas"), ("two-start-inch.apt", "fanuc")],
)
def test_every_pass_of_every_thread_is_a_row(name, controller):
    path = EXAMPLES / name
    r = run(str(path), "-c", controller)
    assert r.returncode == 0, r.stderr
    table = list(csv.DictReader(io.StringIO(r.stdout)))
    cycles = threadcut.passes(path.read_text(), controller)
    passes = [(c, p) for c in cycles for p in c["passes"]]
    assert len(table) == len(passes) > 0
    for row, (c, p) in zip(table, passes):
        assert int(row["line"]) == c["line"]
        assert int(row["pass"]) == p["n"]
        assert row["kind"] == p["kind"]
        assert float(row["depth"]) == p["depth"]
        assert float(row["x"]) == p["x"]


def test_the_g76_table_in_numbers(tmp_path):
    out = tmp_path / "passes.csv"
    r = run(str(EXAMPLES / "fanuc-m30x2-g76.nc"), "-c", "fanuc", "-o", str(out))
    assert r.returncode == 0 and r.stdout == ""
    table = list(csv.DictReader(out.open()))
    # Q400: the first cut 0.4 mm deep, at Ø30 − 0.8; P1227: the last at 1.227.
    assert (table[0]["pass"], table[0]["kind"]) == ("1", "rough")
    assert float(table[0]["depth"]) == pytest.approx(0.4, abs=5e-4)
    assert float(table[0]["x"]) == pytest.approx(29.2, abs=5e-4)
    assert float(table[-1]["depth"]) == pytest.approx(1.227, abs=5e-4)
    assert {row["units"] for row in table} == {"mm"}


def test_a_refused_program_says_where(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text("G00 X80 Z10\nG78 P020545 Q0.15 R0.5\nG78 X60 Z-30 P1.2 Q0.4 F2\n")
    r = run(str(bad), "-c", "gsk980")
    assert r.returncode == 2
    assert r.stderr.startswith(f"{bad}:2:8: error[E004]: P(r)=05")
