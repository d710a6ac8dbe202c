"""Every error path: what raises `InputError` (a `ValueError`) with which attributes and which
`str()`, what is an `InputWarning`, and what stays Python's own exception."""

import io
import warnings

import pytest

import threadcut
from conftest import EXAMPLES, ROOT, help_lines, one_line

M30_G76 = (EXAMPLES / "fanuc-m30x2-g76.nc").read_text()
# GSK G78: P(r)=05 is not an infeed mode (0 to 4).
BAD_GSK = "G00 X80 Z10\nG78 P020545 Q0.15 R0.5\nG78 X60 Z-30 P1.2 Q0.4 F2\n"
# GSK G78 over 1.5 mm with a 2 mm lead: the dialect warns (W001) and plans it.
SHORT_GSK = "G00 X80 Z10\nG97 S100\nG78 P010060 Q0.1 R0.05\nG78 X60 Z8.5 P1.2 Q0.4 F2\n"

PROGRAM_FUNCTIONS = [threadcut.passes, threadcut.motions, threadcut.expand, threadcut.plot_svg]


def test_input_error_is_a_value_error():
    assert issubclass(threadcut.InputError, ValueError)
    assert issubclass(threadcut.InputWarning, UserWarning)


@pytest.mark.parametrize("f", PROGRAM_FUNCTIONS, ids=lambda f: f.__name__)
def test_a_refused_program_raises_at_its_place(cli, f):
    with pytest.raises(threadcut.InputError) as e:
        f(BAD_GSK, "gsk980")
    err = e.value
    assert (err.file, err.line, err.column, err.code) == ("<string>", 2, 8, "E004")
    assert err.message.startswith("P(r)=05: the infeed mode must be 0 to 4")
    assert "P020545" in err.hint
    # The command's one-line form: the command names standard input `-`.
    r = cli.run("passes", "-", "-c", "gsk980", stdin=BAD_GSK)
    assert r.returncode == 2
    assert str(err) == one_line(r.stderr)
    assert str(err) == f"<string>:2:8: error[E004]: {err.message}"
    assert help_lines(r.stderr) == [err.hint]


def test_check_gives_the_alarm_as_a_finding_not_an_exception():
    [alarm, *_] = [f for f in threadcut.check(BAD_GSK, "gsk980") if f["level"] == "error"]
    assert (alarm["line"], alarm["column"], alarm["code"]) == (2, 8, "E004")


@pytest.mark.parametrize(
    "f",
    PROGRAM_FUNCTIONS + [threadcut.check, threadcut.post],
    ids=lambda f: f.__name__,
)
def test_an_unknown_controller(cli, f):
    with pytest.raises(threadcut.InputError) as e:
        f(M30_G76, "GSK980x")
    err = e.value
    assert err.code is None and err.line is None and err.column is None and err.file is None
    r = cli.run("passes", str(EXAMPLES / "fanuc-m30x2-g76.nc"), "-c", "GSK980x")
    assert str(err) == one_line(r.stderr)
    assert help_lines(r.stderr) == [err.hint]
    assert str(err) == "error: unknown controller `GSK980x`"
    assert err.hint.startswith("did you mean `gsk980`? (built in: gsk980, ")


def test_controller_names_are_case_insensitive():
    assert threadcut.passes(M30_G76, "FANUC") == threadcut.passes(M30_G76, "fanuc")


def test_a_milling_profile_is_not_a_lathe_controller():
    with pytest.raises(threadcut.InputError) as e:
        threadcut.passes(M30_G76, "centroid")
    assert e.value.message == "`centroid` is a milling profile, and this function reads lathe programs"
    assert 'threadcut.mill(..., controller="centroid")' in e.value.hint


def test_an_unknown_thread(cli):
    with pytest.raises(threadcut.InputError) as e:
        threadcut.thread("M99")
    err = e.value
    assert err.code == "E004" and err.line is None and err.file is None
    assert str(err) == f"error[E004]: {err.message}"
    assert err.hint.startswith("nearest known threads:")
    r = cli.run("thread", "M99")
    assert r.stderr.splitlines()[0] == f"error: {err.message}"
    # The command adds how to list every thread.
    [help] = help_lines(r.stderr)
    assert help.startswith(err.hint)


def test_check_with_an_unknown_thread():
    with pytest.raises(threadcut.InputError) as e:
        threadcut.check(M30_G76, "fanuc", thread="M30x7")
    assert e.value.code == "E004"


def test_dialect_warnings_are_input_warnings(cli):
    with pytest.warns(threadcut.InputWarning) as record:
        cycles = threadcut.passes(SHORT_GSK, "gsk980")
    assert len(cycles) == 1
    [w] = [w.message for w in record]
    assert (w.file, w.line, w.code) == ("<string>", 4, "W001")
    r = cli.run("passes", "-", "-c", "gsk980", stdin=SHORT_GSK)
    assert str(w) == one_line(r.stderr)
    assert record[0].filename == __file__


def test_warnings_can_be_errors():
    with warnings.catch_warnings():
        warnings.simplefilter("error", threadcut.InputWarning)
        with pytest.raises(threadcut.InputWarning):
            threadcut.expand(SHORT_GSK, "gsk980")


@pytest.mark.parametrize(
    "f", [threadcut.passes, threadcut.check, threadcut.plot_svg], ids=lambda f: f.__name__
)
def test_a_program_without_a_thread_warns(cli, f):
    with pytest.warns(threadcut.InputWarning) as record:
        result = f("G0 X10. Z5.\nG1 Z-10. F0.2\n", "fanuc")
    if f is not threadcut.plot_svg:
        assert result == []
    [w] = [w.message for w in record]
    r = cli.run("passes", "-", "-c", "fanuc", stdin="G0 X10. Z5.\nG1 Z-10. F0.2\n")
    assert r.stderr.splitlines()[0] == "warning: no thread found in standard input: no threading cycle and no synchronised move"
    assert w.message.startswith("no thread found: no threading cycle and no synchronised move")
    assert "this controller threads with G32, G76, G92" in w.message


def test_machine_profile_errors():
    # A TOML error: at its line and column in the profile.
    with pytest.raises(threadcut.InputError) as e:
        threadcut.passes(M30_G76, "fanuc", machine=io.StringIO('name = "x"\ncolour = 1\n'))
    err = e.value
    assert (err.file, err.line, err.column, err.code) == ("<machine>", 2, 1, None)
    assert "unknown field `colour`" in err.message
    assert str(err) == f"<machine>:2:1: error: {err.message}"
    # A profile for another controller.
    with pytest.raises(threadcut.InputError, match="not the controller `haas`"):
        threadcut.passes(M30_G76, "haas", machine=ROOT / "profiles" / "fanuc.toml")
    # A file that is not there is Python's own error, with its name.
    with pytest.raises(FileNotFoundError) as missing:
        threadcut.passes(M30_G76, "fanuc", machine="no-such-profile.toml")
    assert missing.value.filename == "no-such-profile.toml"
    # TOML text is not a path: a str is always a path.
    with pytest.raises(OSError):
        threadcut.passes(M30_G76, "fanuc", machine='name = "fanuc"\n')


def test_a_profile_whose_dialect_threadcut_does_not_have(tmp_path):
    text = (ROOT / "profiles" / "fanuc.toml").read_text().replace(
        'dialect = "fanuc"', 'dialect = "mazak"'
    )
    with pytest.raises(threadcut.InputError) as e:
        threadcut.passes(M30_G76, "fanuc", machine=io.StringIO(text))
    assert e.value.code is None and e.value.line is None
    assert "mazak" in str(e.value) and str(e.value).startswith("error: ")


def test_a_named_profile_file_names_itself(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text('name = "x"\n\ndialect = 3\n')
    with pytest.raises(threadcut.InputError) as e:
        threadcut.expand(M30_G76, "fanuc", machine=p)
    assert e.value.file == str(p)
    assert e.value.line == 3
    with open(p) as f, pytest.raises(threadcut.InputError) as e:
        threadcut.expand(M30_G76, "fanuc", machine=f)
    assert e.value.file == str(p)


def test_post_of_g_code_is_refused():
    with pytest.raises(threadcut.InputError) as e:
        threadcut.post(M30_G76, "fanuc")
    assert e.value.file == "<string>" and e.value.line is not None


def mill(**kw):
    args = dict(internal=True, length=12, tool_diameter=6, feed=300, controller="centroid", d_register=1)
    args.update(kw)
    return threadcut.mill("M10x1.5", **args)


def test_mill_errors(cli):
    with pytest.raises(threadcut.InputError) as e:
        mill(controller="fanuc")
    assert e.value.code is None
    assert str(e.value) == (
        "error: `fanuc` is a lathe controller, and `threadcut.mill` writes thread-milling programs"
    )
    assert e.value.hint.endswith("milling profiles: centroid, fanuc-mill, haas-mill, linuxcnc-mill")
    assert mill(controller="Centroid") == mill(controller="centroid")
    with pytest.raises(threadcut.InputError) as e:
        threadcut.mill(
            "M10x1.5-6g", internal=True, length=12, tool_diameter=6, feed=300, controller="centroid"
        )
    assert e.value.code == "E005"
    assert "which is for external threads, but --internal was given" in e.value.message
    with pytest.raises(threadcut.InputError) as e:
        mill(length=-1)
    assert e.value.code == "E004" and e.value.message.startswith("--length:")
    r = cli.run(
        "mill", "--thread", "M10x1.5", "--internal", "--length", "-1", "--tool-diameter", "6",
        "--feed", "300", "-c", "centroid",
    )
    assert f"error: {e.value.message}" in r.stderr.splitlines()
    with pytest.raises(threadcut.InputError, match="`M99`"):
        threadcut.mill("M99", internal=True, length=12, tool_diameter=6, feed=300, controller="centroid")


@pytest.mark.parametrize(
    "kw,words",
    [
        (dict(comp="g42"), 'comp="g42": expected "g41" or "none"'),
        (dict(lead="helix"), 'lead="helix": expected "arc" or "radial"'),
        (dict(units="cm"), 'units="cm": expected "mm" or "inch"'),
        (dict(top_down=True, bottom_up=True), "give one direction"),
    ],
)
def test_mill_option_values(kw, words):
    with pytest.raises(threadcut.InputError) as e:
        mill(**kw)
    assert words in str(e.value)
    assert e.value.code is None


def test_mill_keyword_mistakes_are_type_errors():
    with pytest.raises(TypeError):
        mill(colour="red")
    with pytest.raises(TypeError):
        threadcut.mill("M10x1.5", length=12, tool_diameter=6, feed=300, controller="centroid")
    with pytest.raises(OverflowError):
        mill(teeth=-1)


def test_wrong_types_are_type_errors():
    with pytest.raises(TypeError):
        threadcut.passes(b"G0 X1\n", "fanuc")
    with pytest.raises(TypeError):
        threadcut.passes(M30_G76, "fanuc", "profiles/fanuc.toml")
