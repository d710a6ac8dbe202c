"""Every function against the command whose data it is (same shape, same values), and against
numbers worked out by hand from the controllers' own rules."""

import io
import json
import math
import warnings

import pytest

import threadcut
from conftest import EXAMPLES, ROOT, apt_examples, gcode_examples, one_line

M30_G76 = (EXAMPLES / "fanuc-m30x2-g76.nc").read_text()


def test_controllers_are_the_commands_list(cli):
    names = [line.split()[0] for line in cli.out("controllers").splitlines()]
    assert threadcut.controllers() == names
    assert "fanuc" in names and "centroid" in names


@pytest.mark.parametrize("path,controller", gcode_examples(), ids=lambda v: getattr(v, "name", v))
def test_passes_are_the_cycles_of_passes_json(cli, path, controller):
    expected = cli.json("passes", str(path), "-c", controller, "--json")["cycles"]
    assert threadcut.passes(path.read_text(), controller) == expected
    assert expected, "every example cuts a thread"


@pytest.mark.parametrize("path", apt_examples(), ids=lambda p: p.name)
def test_passes_of_apt(cli, path):
    expected = cli.json("passes", str(path), "--json")["cycles"]
    # APT is recognised by its first statement; the controller is not used to read it.
    assert threadcut.passes(path.read_text(), "fanuc") == expected


def test_passes_follow_fanuc_g76_rules():
    # G76 P020060 Q100 R0.05 / G76 X27.546 Z-30. P1227 Q400 F2.: the first cut Δd = Q400 = 0.4 mm,
    # the n-th rough pass at Δd·√n, two finishing passes at the full height k = P1227 = 1.227 mm.
    [cycle] = threadcut.passes(M30_G76, "fanuc")
    assert cycle["controller"] == "fanuc"
    assert cycle["line"] == 8
    assert cycle["units"] == "mm"
    assert cycle["source"] == "cycle"
    p = cycle["passes"]
    assert [r["n"] for r in p] == list(range(1, len(p) + 1))
    assert p[0]["depth"] == pytest.approx(0.4, abs=5e-4)
    assert p[1]["depth"] == pytest.approx(0.4 * math.sqrt(2), abs=5e-4)
    assert p[2]["depth"] == pytest.approx(0.4 * math.sqrt(3), abs=5e-4)
    assert [r["kind"] for r in p[-2:]] == ["finish", "finish"]
    assert p[-1]["depth"] == pytest.approx(1.227, abs=5e-4)
    # X on diameter: the crest Ø27.546 + 2·1.227 = Ø30; the first infeed point at Ø30 − 2·0.4.
    assert p[0]["x"] == pytest.approx(29.2, abs=5e-4)
    # The shares of the sharp-V chip areas add up to the whole groove.
    assert sum(r["share"] for r in p) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("path,controller", gcode_examples(), ids=lambda v: getattr(v, "name", v))
def test_motions_are_the_jsonl_objects(cli, path, controller):
    lines = cli.out("expand", str(path), "-c", controller, "--format", "jsonl").splitlines()
    assert threadcut.motions(path.read_text(), controller) == [json.loads(l) for l in lines]


def test_motions_of_apt(cli):
    path = EXAMPLES / "variable-lead.apt"
    lines = cli.out("expand", str(path), "--format", "jsonl").splitlines()
    motions = threadcut.motions(path.read_text(), "fanuc")
    assert motions == [json.loads(l) for l in lines]
    # A variable lead: its thread moves say by how much the lead changes per revolution.
    assert any("dlead" in m for m in motions)


def test_motions_of_the_g76_cycle():
    motions = threadcut.motions(M30_G76, "fanuc")
    threads = [m for m in motions if m["kind"] == "thread"]
    assert {m["lead"] for m in threads} == {2.0}
    # Ten passes (eight rough and two finishing), one thread move each.
    assert [m["pass"] for m in threads] == list(range(1, 11))
    assert all(m["line"] == 8 for m in threads)
    # G76 cuts along one flank (a = 60°): a pass at depth d ends (k − d)·tan 30° short of Z-30,
    # k = 1.227 the full height; the finishing passes end at Z-30.
    depths = [p["depth"] for p in threadcut.passes(M30_G76, "fanuc")[0]["passes"]]
    for m, d in zip(threads, depths):
        assert m["z"] == pytest.approx(-30 + (1.227 - d) * math.tan(math.radians(30)), abs=5e-4)
    assert threads[-1]["z"] == pytest.approx(-30, abs=1e-9)
    # X is a radius: the first thread move at Ø29.2.
    assert threads[0]["x"] == pytest.approx(14.6, abs=5e-4)


@pytest.mark.parametrize("path,controller", gcode_examples(), ids=lambda v: getattr(v, "name", v))
def test_expand_is_the_commands_output(cli, path, controller):
    r = cli.run("expand", "-", "-c", controller, stdin=path.read_text())
    if r.returncode == 0:
        assert threadcut.expand(path.read_text(), controller) == r.stdout
    else:
        # A cycle in a loop that cuts differently each time is not expanded in place: the same
        # error, and `flatten=True` as `--flatten` writes the executed program.
        with pytest.raises(threadcut.InputError) as e:
            threadcut.expand(path.read_text(), controller)
        assert str(e.value) == one_line(r.stderr)
        flat = cli.out("expand", "-", "-c", controller, "--flatten", stdin=path.read_text())
        assert threadcut.expand(path.read_text(), controller, flatten=True) == flat


def test_expand_keeps_other_lines_and_writes_plain_moves():
    out = threadcut.expand(M30_G76, "fanuc")
    assert out.startswith("%\nO0001 (M30x2 external thread, G76)\nG21 G99\n")
    assert out.endswith("G0 X100. Z100.\nM30\n%\n")
    blocks = [l for l in out.splitlines() if not l.startswith("(")]
    assert not any(l.startswith("G76") for l in blocks)
    # Ten passes, each one synchronised move at the lead F2.
    assert sum(1 for l in blocks if l.startswith("G32")) == 10


def test_expand_of_apt_is_the_post(cli):
    apt = (EXAMPLES / "m20-external.apt").read_text()
    assert threadcut.expand(apt, "fanuc") == threadcut.post(apt, "fanuc")


def check_cli(cli, path, *args):
    findings = cli.json("check", str(path), *args, "--format", "json")
    for f in findings:
        assert f.pop("file") == str(path)
    return findings


@pytest.mark.parametrize("path,controller", gcode_examples(), ids=lambda v: getattr(v, "name", v))
def test_check_is_check_format_json(cli, path, controller):
    r = cli.run("check", str(path), "-c", controller, "--format", "json")
    expected = json.loads(r.stdout)
    for f in expected:
        f.pop("file")
    assert threadcut.check(path.read_text(), controller) == expected


def test_check_with_thread_and_stock(cli):
    path = EXAMPLES / "fanuc-m30x2-g76.nc"
    args = ["--thread", "M30x2-6g", "--stock-diameter", "31", "--stock-start", "0.5"]
    r = cli.run("check", str(path), "-c", "fanuc", *args, "--format", "json")
    expected = [{k: v for k, v in f.items() if k != "file"} for f in json.loads(r.stdout)]
    got = threadcut.check(
        M30_G76, "fanuc", thread="M30x2-6g", stock_diameter=31.0, stock_start=0.5
    )
    assert got == expected
    # P1227 reaches 1.227 below the crest; M30x2-6g's minor diameter needs at least 1.246.
    [minor] = [f for f in got if f["code"] == "E016"]
    assert minor["level"] == "error"
    assert minor["line"] == 8
    assert "27.546 > 27.508 max" in minor["message"]


def test_check_with_a_wire_of_ones_own(cli):
    path = EXAMPLES / "fanuc-m30x2-g76.nc"
    args = ["--thread", "M30x2-6g", "--wire", "1.2", "--stock-diameter", "31"]
    r = cli.run("check", str(path), "-c", "fanuc", *args, "--format", "json")
    expected = [{k: v for k, v in f.items() if k != "file"} for f in json.loads(r.stdout)]
    got = threadcut.check(M30_G76, "fanuc", thread="M30x2-6g", wire=1.2, stock_diameter=31.0)
    assert got == expected
    assert any("over 1.2 wires" in f["message"] for f in got if f["level"] == "note")
    with pytest.raises(threadcut.InputError, match="needs --thread"):
        threadcut.check(M30_G76, "fanuc", wire=1.2)
    with pytest.raises(threadcut.InputError, match="positive length"):
        threadcut.check(M30_G76, "fanuc", thread="M30x2-6g", wire=-1.0)


def test_passes_states_what_the_thread_will_measure(cli):
    # As `threadcut passes --json --thread M30x2-6g --wire 1.15`: the pitch diameter the final
    # passes leave with the standard's root form at the tip, 28.7007 (cli/tests/check_thread.rs
    # works it out), over 1.15 wires, and 0.0614 deeper to 6g's middle.
    path = EXAMPLES / "fanuc-m30x2-g76.nc"
    args = ["--thread", "M30x2-6g", "--wire", "1.15"]
    r = cli.run("passes", str(path), "-c", "fanuc", *args, "--json")
    expected = json.loads(r.stdout)["cycles"]
    got = threadcut.passes(M30_G76, "fanuc", thread="M30x2-6g", wire=1.15)
    assert got == expected
    m = got[0]["measure"]
    assert m["class"] == "6g" and m["best_wire"] is False
    assert abs(m["pitch_diameter"] - 28.7007) < 1e-4
    assert abs(m["deeper"] - 0.0614) < 1e-4
    assert "measure" not in threadcut.passes(M30_G76, "fanuc")[0]


def test_check_reports_a_controller_alarm_as_a_finding():
    # GSK's G78: the tail-out K10 is not shorter than the 8 mm thread.
    src = "G00 X80 Z10\nG97 S100\nG78 P010060 Q0.1 R0.05\nG78 X60 Z2 P1.2 Q0.4 F2 J1 K10\n"
    findings = threadcut.check(src, "gsk980")
    errors = [f for f in findings if f["level"] == "error"]
    assert errors and errors[0]["line"] == 4
    assert set(findings[0]) == {"line", "column", "level", "code", "message", "hint"}


def test_check_of_apt(cli):
    path = EXAMPLES / "m20-external.apt"
    expected = check_cli(cli, path, "-c", "fanuc")
    assert threadcut.check(path.read_text(), "fanuc") == expected


@pytest.mark.parametrize(
    "path,controller",
    [(EXAMPLES / "gsk-g78.nc", "gsk980"), (EXAMPLES / "haas-m24x3-two-start.nc", "haas")],
    ids=lambda v: getattr(v, "name", v),
)
def test_plot_svg_is_plots_svg(cli, path, controller):
    svg = threadcut.plot_svg(path.read_text(), controller)
    assert svg == cli.out("plot", str(path), "-c", controller, "-o", "-")
    assert svg.lstrip().startswith("<svg") and svg.rstrip().endswith("</svg>")


def test_plot_svg_of_apt(cli):
    path = EXAMPLES / "two-start-inch.apt"
    assert threadcut.plot_svg(path.read_text(), "fanuc") == cli.out("plot", str(path), "-o", "-")


@pytest.mark.parametrize(
    "name",
    ["M10", "M10x1.25-6g", "M12-6H", "1/2-13 UNC-2A", "#10-32 UNF", "1/2-14 NPT", "R 1/2", "Tr20x4"],
)
def test_thread_is_thread_json(cli, name):
    assert threadcut.thread(name) == cli.json("thread", name, "--json")


def test_thread_values():
    t = threadcut.thread("M10x1.5-6g")
    # ISO 68-1: d2 = d − (3/4)·H with H = (√3/2)·P; ISO 965-1: es(g) = −(15 + 11·P) µm.
    h = math.sqrt(3) / 2 * 1.5
    assert t["basic"]["pitch_diameter"] == pytest.approx(10 - 0.75 * h, abs=1e-9)
    # −31.5 µm, which ISO 965-1's table rounds to −32 µm.
    assert t["external"]["deviation"] == pytest.approx(-0.032, abs=1e-9)
    assert t["internal"] is None
    u = threadcut.thread("1/2-13 UNC-2A")
    assert u["units"] == "inch" and u["tpi"] == 13
    # ASME B1.1: the 2A allowance of 1/2-13 is 0.0015 in below the basic major diameter 0.5.
    assert u["external"]["major"]["max"] == pytest.approx(0.4985, abs=1e-9)


def test_thread_gives_wires_and_gauges(cli):
    # The same object as `threadcut thread NAME --wire D --json`.
    assert threadcut.thread("7/16-14 UNC", wire=0.045) == cli.json(
        "thread", "7/16-14 UNC", "--wire", "0.045", "--json"
    )
    t = threadcut.thread("M10x1.5-6g")
    # Best wire P/(2·cos 30°) = 0.866025; M = d2 + 3w − 0.866025·P at d2 9.025721: 10.324760
    # (the codingace.net table wires::tests cites).
    assert t["wires"]["best"] == pytest.approx(0.866025, abs=1e-6)
    assert t["wires"]["basic"]["simple"] == pytest.approx(10.324760, abs=1e-6)
    # neme-s.org: 7/16-14 over 0.045 in wires, M = 0.4375 + 0.135 − 0.1083 = 0.464 in.
    u = threadcut.thread("7/16-14 UNC", wire=0.045)
    assert u["wires"]["wire"] == pytest.approx(0.045, abs=1e-9)
    assert u["wires"]["basic"]["simple"] == pytest.approx(0.4642, abs=1e-4)
    # The GO ring at 6g's largest pitch diameter 8.994, NOT GO at the smallest 8.862.
    ring = t["gauges"]["external"][0]
    assert (ring["go"], ring["not_go"]) == (pytest.approx(8.994, abs=1e-6), pytest.approx(8.862, abs=1e-6))
    with pytest.raises(threadcut.InputError, match="positive length"):
        threadcut.thread("M10", wire=0.0)


MILLS = [
    ("M10x1.5", dict(internal=True, length=12, tool_diameter=6, feed=300, controller="centroid", d_register=1), []),
    (
        "M16-6H",
        dict(internal=True, length=20, tool_diameter=10, passes=3, feed=250, center=(40, -25),
             start_z=-3, controller="fanuc-mill", d_register=12),
        ["--passes", "3", "--center", "40,-25", "--start-z", "-3"],
    ),
    (
        "M20",
        dict(internal=False, length=15, tool_diameter=12, teeth=6, feed=400, comp="none",
             controller="linuxcnc-mill"),
        ["--teeth", "6", "--comp", "none"],
    ),
    (
        "1/2-13 UNC-2A",
        dict(internal=False, length=0.75, tool_diameter=0.25, feed=10, controller="fanuc-mill",
             left=True, top_down=True, lead="radial", units="inch", clearance=0.1, starts=2,
             d_register=3),
        ["--left", "--top-down", "--lead", "radial", "--units", "inch", "--clearance", "0.1",
         "--starts", "2"],
    ),
]


@pytest.mark.parametrize("thread,kw,flags", MILLS, ids=[m[0] for m in MILLS])
def test_mill_is_the_commands_program(cli, thread, kw, flags):
    args = [
        "mill", "--thread", thread, "--internal" if kw["internal"] else "--external",
        "--length", str(kw["length"]), "--tool-diameter", str(kw["tool_diameter"]),
        "--feed", str(kw["feed"]), "--controller", kw["controller"], *flags,
    ]
    if "d_register" in kw:
        args += ["--d-register", str(kw["d_register"])]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", threadcut.InputWarning)
        assert threadcut.mill(thread, **kw) == cli.out(*args)


def test_mill_warns_of_a_missing_d_register():
    with pytest.warns(threadcut.InputWarning) as record:
        out = threadcut.mill(
            "M10x1.5", internal=True, length=12, tool_diameter=6, feed=300, controller="centroid"
        )
    assert "G41" in out
    messages = [str(w.message) for w in record]
    assert messages[0].startswith("warning: no --d-register: centroid writes G41/G42 without D")
    w = record[0].message
    assert w.code is None and w.line is None and w.message.startswith("no --d-register")
    # Warnings point at the caller's line, not at threadcut's.
    assert record[0].filename == __file__


@pytest.mark.parametrize("path", apt_examples(), ids=lambda p: p.name)
@pytest.mark.parametrize("controller", ["fanuc", "sinumerik", "linuxcnc", "haas"])
def test_post_is_the_commands_output(cli, path, controller):
    apt = path.read_text()
    r = cli.run("post", "-", "-c", controller, stdin=apt)
    if r.returncode == 0:
        assert threadcut.post(apt, controller) == r.stdout
    else:
        # What the controller cannot do: the same error, in the command's one-line form (the
        # command names standard input `-`).
        with pytest.raises(threadcut.InputError) as e:
            threadcut.post(apt, controller)
        assert str(e.value) == one_line(r.stderr)


def test_a_variable_lead_cannot_be_posted_to_fanuc():
    with pytest.raises(threadcut.InputError) as e:
        threadcut.post((EXAMPLES / "variable-lead.apt").read_text(), "fanuc")
    assert e.value.code == "E009"
    assert (e.value.line, e.value.column) == (9, 1)
    assert "G34" in e.value.hint


def test_post_writes_the_native_cycle_or_says_why():
    out = threadcut.post((EXAMPLES / "m20-external.apt").read_text(), "fanuc")
    assert out.startswith("(threadcut post for fanuc, mm, feed per revolution)\nG21 G18 G99 G97\n")
    assert "G76" in out or "plain moves" in out


def test_machine_profile_by_path_and_by_file_object(cli):
    profile = ROOT / "profiles" / "fanuc.toml"
    expected = cli.json("passes", str(EXAMPLES / "fanuc-m30x2-g76.nc"), "--machine", str(profile), "--json")
    assert threadcut.passes(M30_G76, "fanuc", machine=str(profile)) == expected["cycles"]
    assert threadcut.passes(M30_G76, "fanuc", machine=profile) == expected["cycles"]
    text = profile.read_text()
    assert threadcut.passes(M30_G76, "fanuc", machine=io.StringIO(text)) == expected["cycles"]
    # A profile of its own: the control reads 0.0001 mm (ISC), so the table has a finer
    # resolution, but the same cuts.
    isc = text.replace('increment_system = "isb"', 'increment_system = "isc"').replace(
        'name = "fanuc"', 'name = "my-lathe"'
    )
    [cycle] = threadcut.passes(M30_G76.replace("Q400", "Q4000").replace("P1227", "P12270"), "fanuc", machine=io.StringIO(isc))
    assert cycle["passes"][0]["depth"] == pytest.approx(0.4, abs=5e-5)
    assert cycle["passes"][-1]["depth"] == pytest.approx(1.227, abs=5e-5)


def test_check_with_a_machine_profile(cli):
    # Haas settings in a profile of its own: the findings are the command's with --machine.
    profile = ROOT / "profiles" / "haas.toml"
    path = EXAMPLES / "haas-m24x3-two-start.nc"
    expected = check_cli(cli, path, "--machine", str(profile))
    assert threadcut.check(path.read_text(), "haas", machine=profile) == expected


def test_threads_at_once_get_the_same_results():
    # The functions let go of the interpreter while the library runs: two Python threads analyse
    # at once, and both get what one thread alone gets.
    import threading

    # The cycle's lines 200 times (a program ends at its M30: what follows is not run).
    body = "".join(l + "\n" for l in M30_G76.splitlines() if l.startswith(("G0 ", "G76")))
    big = "G21 G99\n" + body * 200
    want = threadcut.passes(big, "fanuc")
    got = [None, None]

    def work(i):
        got[i] = threadcut.passes(big, "fanuc")

    ts = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert got == [want, want]
    assert len(want) == 200


@pytest.mark.parametrize("path,controller", gcode_examples(), ids=lambda v: getattr(v, "name", v))
def test_convert_is_the_commands_output(cli, path, controller):
    # Every example to Fanuc and to LinuxCNC: the command's program, or its error.
    for target in ("fanuc", "linuxcnc"):
        r = cli.run("convert", "-", "--from", controller, "--to", target, stdin=path.read_text())
        if r.returncode == 0:
            assert threadcut.convert(path.read_text(), controller, target) == r.stdout
        else:
            with pytest.raises(threadcut.InputError) as e:
                threadcut.convert(path.read_text(), controller, target)
            assert str(e.value) == one_line(r.stderr)


def test_convert_writes_the_targets_cycle():
    # Fanuc's G76 in G-code system B: the same cycle, feed per revolution as G95 (not G99).
    out = threadcut.convert(M30_G76, "fanuc", "fanuc-b")
    blocks = [l for l in out.splitlines() if not l.startswith("(")]
    assert "G76 X27.546 Z-30. P1227 Q400 F2." in blocks
    assert "G21 G95" in blocks and not any("G99" in l for l in blocks)
    # LinuxCNC's G76 cuts another law: plain G33 passes, X a radius (its profile's G8).
    lcnc = threadcut.convert(M30_G76, "fanuc", "linuxcnc").splitlines()
    assert not any(l.startswith("G76") for l in lcnc)
    assert "G33 X14.6 Z-29.5225 K2." in lcnc
    with pytest.raises(threadcut.InputError) as e:
        threadcut.convert(M30_G76, "fanuc", "centroid")
    assert "milling profile" in e.value.message


def test_convert_states_the_lead_drift_and_takes_a_limit():
    # F1.50004 on Haas is F1.5: 0.00004 mm a turn over 35 mm, 0.0009333 mm; stated (a comment
    # and a warning), within a quarter of M20x1.5-6g's Td2; refused below max_lead_drift.
    lead = "G21 G99\nG0 X22. Z5.\nG92 X20. Z-30. F1.50004\nM30\n"
    with pytest.warns(threadcut.InputWarning, match="drifts 0.0009333 mm"):
        out = threadcut.convert(lead, "fanuc", "haas")
    assert "drifts 0.0009333 mm" in out
    with pytest.raises(threadcut.InputError) as e:
        threadcut.convert(lead, "fanuc", "haas", max_lead_drift=0.0005)
    assert "the limit given" in e.value.message


def test_convert_takes_named_tools():
    # Sinumerik's T="THREAD_EXT_60" D1 is Fanuc's T0101 when named; unnamed, refused with the flag.
    named = 'G0 X40 Z5\nT="THREAD_EXT_60" D1\n'
    out = threadcut.convert(named, "sinumerik", "fanuc", tools={"THREAD_EXT_60": "T0101"})
    assert "T0101" in out.splitlines()
    with pytest.raises(threadcut.InputError) as e:
        threadcut.convert(named, "sinumerik", "fanuc")
    assert "--tool THREAD_EXT_60=T0101" in (e.value.hint or "")
    back = threadcut.convert("T0303\n", "fanuc", "sinumerik", tools={"THREAD_EXT_60": "T0303"})
    assert 'T="THREAD_EXT_60" D1' in back.splitlines()


def test_plot_svg_draws_one_cycle_on_request():
    two = "G21 G99\n" + "".join(
        l + "\n" for l in M30_G76.splitlines() if l.startswith(("G0 ", "G76"))
    ) * 2
    both = threadcut.plot_svg(two, "fanuc")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        second = threadcut.plot_svg(two, "fanuc", cycle=2)
    assert second.startswith("<svg") and len(second) < len(both)
    with pytest.raises(threadcut.InputError, match="cycle=3: the program has 2 threads"):
        threadcut.plot_svg(two, "fanuc", cycle=3)


# Turns Ø19.8 (G71/G70), cuts M20x2.5 with G76 at line 18, then a rapid at line 19 from X24 Z5 to
# X15 Z-10 runs through the thread's teeth (cli/tests/part.rs has the same program).
TURNED_HIT = (
    "G21 G99\nT0101\nG97 S800 M03\nG00 X27. Z2.\nG71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\n"
    "N10 G00 X16.\nG01 Z0. F0.12\nX19.8 Z-1.9\nZ-30.\nX24.\nN20 X27.\nG70 P10 Q20\nG00 X100. Z100.\n"
    "T0303\nG00 X24. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.85 Z-27. P1575 Q400 F2.5\n"
    "G00 X15. Z-10.\nG00 X100. Z100.\nM30\n"
)


def test_check_gives_the_blanks_and_the_hits(cli, tmp_path):
    path = tmp_path / "hit.nc"
    path.write_text(TURNED_HIT)
    stock = ["--stock-diameter", "25", "--stock-start", "0", "--stock-length", "60"]
    # An error: exit status 2, the findings on standard output as ever.
    r = cli.run("check", str(path), "-c", "fanuc", *stock, "--format", "json")
    assert r.returncode == 2
    expected = [{k: v for k, v in f.items() if k != "file"} for f in json.loads(r.stdout)]
    got = threadcut.check(
        TURNED_HIT, "fanuc", stock_diameter=25.0, stock_start=0.0, stock_length=60.0
    )
    # Still the list of findings, compared as before.
    assert got == expected
    assert isinstance(got, list) and isinstance(got, threadcut.CheckResult)
    [blank] = got.blanks
    assert blank == {
        "line": 18, "crest": 19.8, "crest_from": "measured", "face": 0.0, "face_from": "given"
    }
    [hit] = got.hits
    assert hit["line"] == 19 and hit["level"] == "error"
    # From X24 Z5 (radius 12) to X15 Z-10 (radius 7.5), mm; it enters at the crest, radius 9.9.
    assert hit["from"] == pytest.approx((12.0, 5.0))
    assert hit["to"] == pytest.approx((7.5, -10.0))
    assert hit["at"][0] == pytest.approx(9.9, abs=0.01)
    # The rapid is the E011 finding at the same line.
    assert [f["line"] for f in got if f["code"] == "E011"] == [19]
    # The bore keyword is taken (an external thread's blank does not use it: its crest stays assumed).
    assert threadcut.check(M30_G76, "fanuc", stock_bore=10.0).blanks[0]["crest_from"] == "assumed"


def test_passes_gives_each_threads_blank_as_the_command(cli, tmp_path):
    path = tmp_path / "hit.nc"
    path.write_text(TURNED_HIT)
    expected = cli.json("passes", str(path), "-c", "fanuc", "--json")["cycles"]
    got = threadcut.passes(TURNED_HIT, "fanuc")
    assert got == expected
    assert got[0]["blank"] == {
        "crest": 19.8, "crest_from": "measured", "face": 0.0, "face_from": "assumed"
    }
    # Nothing turned: the stock given is the blank.
    stock = ["--stock-diameter", "31", "--stock-start", "0.5"]
    path = EXAMPLES / "fanuc-m30x2-g76.nc"
    expected = cli.json("passes", str(path), "-c", "fanuc", "--json", *stock)["cycles"]
    got = threadcut.passes(M30_G76, "fanuc", stock_diameter=31.0, stock_start=0.5)
    assert got == expected
    assert got[0]["blank"] == {"crest": 31.0, "crest_from": "given", "face": 0.5, "face_from": "given"}


def test_plot_svg_draws_the_part_as_plot(cli, tmp_path):
    path = tmp_path / "hit.nc"
    path.write_text(TURNED_HIT)
    stock = ["--stock-diameter", "25", "--stock-bore", "4"]
    svg = threadcut.plot_svg(TURNED_HIT, "fanuc", stock_diameter=25.0, stock_bore=4.0)
    assert svg == cli.out("plot", str(path), "-c", "fanuc", *stock, "-o", "-")
    assert "The part as the program makes it" in svg and 'class="rapid-hit"' in svg
    alone = threadcut.plot_svg(TURNED_HIT, "fanuc", part=True)
    assert alone == cli.out("plot", str(path), "-c", "fanuc", "--part", "-o", "-")
    assert "Pass diagram" not in alone
    with pytest.raises(threadcut.InputError):
        threadcut.plot_svg(TURNED_HIT, "fanuc", part=True, cycle=1)


def test_include_finds_called_programs_as_the_command_does(cli):
    # O9010 from tests/data/multifile/fanuc/lib (`--include DIR`): three thread passes.
    data = ROOT / "tests" / "data" / "multifile"
    main = data / "fanuc" / "main-m98.nc"
    lib = data / "fanuc" / "lib"
    lines = cli.out(
        "expand", str(main), "-c", "fanuc", "--format", "jsonl", "--include", str(lib)
    ).splitlines()
    motions = threadcut.motions(main.read_text(), "fanuc", include=[lib])
    assert motions == [json.loads(l) for l in lines]
    assert [m["x"] for m in motions if m["kind"] == "thread"] == [9.7, 9.5, 9.35]
    # Without it, the call is not found.
    with pytest.raises(threadcut.InputError):
        threadcut.motions(main.read_text(), "fanuc")
# A cycle on its own (no line before it places the tool): FS15's one-block G76, mm. FS15's
# profile: the least cut 0.1, the finishing allowance 0.05. Rough passes at D·√n, D = 0.485:
# 0.485, 0.68589, 0.84004, 0.97, 1.08449, 1.188; 0.485·√7 = 1.28319 < 1.188 + 0.1 → 1.288, 1.388;
# then K − 0.05 = 1.484; the finishing pass at K = 1.534. X (diameter) = 16.93 + 2·(K − d).
G76_ALONE = "M3 S500\nG76 X16.93 Z-25. K1.534 D.485 F2.5\nM30\n"


def test_passes_of_a_cycle_on_its_own(cli, tmp_path):
    [cycle] = threadcut.passes(G76_ALONE, "fanuc15")
    p = cycle["passes"]
    depths = [0.485, 0.68589, 0.84004, 0.97, 1.08449, 1.188, 1.288, 1.388, 1.484, 1.534]
    assert [r["depth"] for r in p] == pytest.approx(depths, abs=1e-5)
    assert [r["x"] for r in p] == pytest.approx([16.93 + 2 * (1.534 - d) for d in depths], abs=1e-5)
    assert all(r["z"] is None for r in p)
    assert cycle["start_unknown"]["axes"] == ["X", "Z"]
    assert "the Z where each pass starts" in cycle["start_unknown"]["note"]
    # The command's table, the same.
    path = tmp_path / "alone.nc"
    path.write_text(G76_ALONE)
    assert cli.json("passes", str(path), "-c", "fanuc15", "--json")["cycles"] == [cycle]


def test_start_places_the_tool(cli, tmp_path):
    with pytest.raises(threadcut.InputError, match="the tool's X and Z are not known here") as e:
        threadcut.expand(G76_ALONE, "fanuc15")
    assert "--start X,Z" in e.value.hint
    # Given the start, the table is the same, with Z: pass 1 at Z5 plus its flank shift
    # (1.534 − 0.485)·tan 30° = 0.60564.
    [cycle] = threadcut.passes(G76_ALONE, "fanuc15", start=(22.0, 5.0))
    assert "start_unknown" not in cycle
    assert cycle["passes"][0]["z"] == pytest.approx(5.60564, abs=1e-5)
    # A start below the crest (16.93 + 2·1.534 = 19.998): the return between passes would cut
    # through the thread.
    found = threadcut.check(G76_ALONE, "fanuc15", start=(18.0, 5.0))
    assert [f["code"] for f in found if f["level"] == "error"] == ["E007"]
    assert not [f for f in threadcut.check(G76_ALONE, "fanuc15", start=(22.0, 5.0)) if f["level"] == "error"]
    path = tmp_path / "alone.nc"
    path.write_text(G76_ALONE)
    assert threadcut.expand(G76_ALONE, "fanuc15", start=(22.0, 5.0)) == cli.out(
        "expand", str(path), "-c", "fanuc15", "--start", "22,5"
    )


MILL = ROOT / "tests" / "data" / "mill"


def test_a_milling_program_is_checked_as_the_command_checks_it(cli):
    # The bolt's tool-centre path with an 8 mm cutter in tool 2: the minor diameter 2·9.9 − 8 =
    # 11.8, above M12x1.75-6g's d3 maximum (E016 at the first helix, line 8).
    path = MILL / "linuxcnc-m12-helix.ngc"
    args = ["--thread", "M12x1.75-6g", "--tool", "T2=8"]
    r = cli.run("check", str(path), "-c", "linuxcnc-mill", "--format", "json", *args)
    assert r.returncode == 2, r.stderr
    expected = json.loads(r.stdout)
    got = threadcut.check(path.read_text(), "linuxcnc-mill", thread="M12x1.75-6g", tools={"T2": 8})
    assert [(f["line"], f["code"], f["message"]) for f in got] == [
        (f["line"], f["code"], f["message"]) for f in expected
    ]
    assert any(f["code"] == "E016" and f["line"] == 8 for f in got)


def test_milled_passes_and_plot(cli):
    path = MILL / "fanuc-m20-internal-g41.nc"
    expected = cli.json("passes", str(path), "-c", "fanuc-mill", "--json")
    got = threadcut.passes(path.read_text(), "fanuc-mill")
    assert got == expected
    [t] = got["milled"]
    assert t["lead"] == pytest.approx(2.5) and t["side"] == "internal" and t["hand"] == "right"
    assert t["passes"][0]["diameter"] == pytest.approx(20.0)
    svg = threadcut.plot_svg(path.read_text(), "fanuc-mill")
    assert svg == cli.out("plot", str(path), "-c", "fanuc-mill")


def test_milling_keywords_need_a_milling_controller():
    with pytest.raises(threadcut.InputError, match="name a milling controller"):
        threadcut.check(M30_G76, "fanuc", tool_diameter=10)
    with pytest.raises(threadcut.InputError, match="tools="):
        threadcut.check("G0 X0\n", "fanuc-mill", tools={"X2": 8})
