"""threadcut: exact pass-by-pass motion for CNC thread-cutting cycles.

Each function is one `threadcut` command, computed by the same library function the command line
calls, so that its data is the command's JSON. A program is G-code for `controller` or APT/CL
(recognised by its first statement: PARTNO, UNITS/, MACHIN/, FROM/, GOTO/, PITCH/, CLPRNT).

`machine`, where a function takes it, is a machine profile in TOML (see the repository's
`profiles/`): a path (`str` or `os.PathLike`), or an object with `read()` that gives its text, such
as an open file or `io.StringIO(toml_text)`. A `str` is always a path, never TOML text. The profile
must be the controller's: its `name` or its `dialect` is `controller`.

`include`, where a function takes it, is a list of directories where calls find the programs the
program does not hold (`--include DIR`, in order): Fanuc/Haas/GSK `O9010`, `O9010.nc`, `9010.nc`
(any case), LinuxCNC `name.ngc` for `o<name> call`, Sinumerik `NAME.SPF` (any case).

Bad input raises `InputError`; findings that do not stop a function are issued as `InputWarning`
through Python's `warnings` module.
"""

import os
from typing import Any, Protocol

__version__: str

class _Readable(Protocol):
    def read(self) -> str: ...

_Machine = str | os.PathLike[str] | _Readable

class InputError(ValueError):
    """Bad input: a program the controller refuses, an unknown controller or thread, a bad option.

    `str(error)` is the command line's one-line form: `<string>:2:8: error[E004]: message` for a
    place in the program (the program is named `<string>`), `error[E004]: message` for a thread
    name or a milling option, `profile.toml:3:1: error: message` for a machine profile, and
    `error: message` for an error with no code (an unknown controller, a bad keyword value).
    """

    file: str | None
    """`"<string>"` for the program, the profile's path for a machine profile, else None."""
    line: int | None
    """1-based line of the offending word, or None when the error has no place."""
    column: int | None
    """1-based column (bytes) of the offending word, or None when the error has no place."""
    code: str | None
    """The stable diagnostic code (`"E004"`), or None for an error without one."""
    message: str
    """What is wrong, in the controller's own words where it has an alarm for it."""
    hint: str | None
    """What to do about it, or None."""

class InputWarning(UserWarning):
    """A finding worth a word that does not stop the function (the command line's warnings).

    It has the attributes of `InputError` (`file`, `line`, `column`, `code`, `message`, `hint`),
    and `str(warning)` is the same one-line form with `warning` for `error`.
    """

    file: str | None
    line: int | None
    column: int | None
    code: str | None
    message: str
    hint: str | None

def controllers() -> list[str]:
    """The built-in controller profiles, as `threadcut controllers` lists them: the lathe
    controllers, then the milling ones (`centroid`, `fanuc-mill`, `linuxcnc-mill`, for `mill`)."""

def passes(
    program: str,
    controller: str,
    *,
    machine: _Machine | None = None,
    thread: str | None = None,
    wire: float | None = None,
    stock_diameter: float | None = None,
    stock_start: float | None = None,
    stock_length: float | None = None,
    stock_bore: float | None = None,
    include: list[str | os.PathLike[str]] | None = None,
    start: tuple[float, float] | None = None,
    internal: bool | None = None,
    tool_diameter: float | None = None,
    teeth: int | None = None,
    tools: dict[str, float] | None = None,
) -> list[dict[str, Any]] | dict[str, Any]:
    """Each thread's pass table: the `cycles` of `threadcut passes --json`.

    One dict per thread (a cycle, or passes written as plain synchronised moves): `line`,
    `controller`, `units` (`"mm"` or `"inch"`), `source` (`"cycle"` or `"moves"`), `depth_from`
    (`"crest"` or `"first_pass"`) and `passes`, one dict per pass: `n`, `kind` (`"rough"` or
    `"finish"`), `depth` (radius, from the crest), `increment`, `x` (as the program writes it)
    and `z` of the infeed point, `area` and `share` of a sharp V of the tool angle, and the
    simulated `sim_area`, `sim_share`, `cutting_flank` and `chip_thickness` (None where the section
    cannot be simulated), and for G-code `blank`: the thread's blank as `check` takes it, `{crest, crest_from,
    face, face_from}` (the crest a diameter; `*_from` `"measured"` on the part the program turned,
    `"given"`, `"assumed"` or `"unknown"`). Program units. The stock keywords are `check`'s; each
    not given is the machine profile's `[stock]` value, if any. With `thread` (a standard thread's
    name, as `check` takes it) each dict has `measure`: what the thread will measure (`pitch_diameter`
    as cut, `wire`, `m` over it, the class's `pitch_diameter_min`/`_max`, `m_min`/`m_max`, the
    `deeper` change of the final depth to the window's middle, and `assumed`), or `{not_stated}`
    with the reason; `wire` the measuring wire one owns (the thread's units).

    `start=(x, z)` places the tool before the program's first line, as the program writes it at
    power-on (the profile's units, X on diameter where the control's X is; `--start X,Z`).
    Without it, a cycle whose start point is not known (a cycle shown on its own) still gives its
    pass table where the table does not depend on the start (Fanuc-family G76 and G92, the
    one-block G76, GSK's G78): its `z` is None and `start_unknown` (`{axes, note}`) says what is
    not known; LinuxCNC's G76, whose passes are placed from the drive line, raises `InputError`.

    A milling controller (`fanuc-mill`, `haas-mill`, `linuxcnc-mill`, `centroid`) gives a dict
    instead, `threadcut passes --format json`'s: `milled`, one dict per milled thread (its axis,
    `lead`, `starts`, `pitch`, `hand`, `direction`, `side` and `side_from`, `climb`,
    `root_diameter`, and `passes`, one dict per helix), and `taps`, one per tapping cycle; with
    `check`'s milling keywords.

    A program with no thread gives `[]` and an `InputWarning`. Raises `InputError` for a program
    the controller refuses (at its line and column) or an unknown controller.
    """

def motions(
    program: str,
    controller: str,
    *,
    machine: _Machine | None = None,
    include: list[str | os.PathLike[str]] | None = None,
    start: tuple[float, float] | None = None,
) -> list[dict[str, Any]]:
    """Every motion of the program: the objects of `threadcut expand --format jsonl`.

    One dict per motion: `kind` (`"rapid"`, `"feed"` or `"thread"`), `x` (a radius) and `z` of
    its end, program units, `pass` and `line`; a thread move adds `lead`, `dlead` where the lead
    varies, and `phase`, the spindle start angle in degrees, where it is not 0.

    Raises `InputError` for a program the controller refuses or an unknown controller.
    """

def expand(
    program: str,
    controller: str,
    *,
    machine: _Machine | None = None,
    flatten: bool = False,
    include: list[str | os.PathLike[str]] | None = None,
    start: tuple[float, float] | None = None,
) -> str:
    """The program with each threading cycle replaced by plain moves in the controller's own
    format (`threadcut expand`); every other line is kept as written. An APT/CL program is posted
    for the controller, as `post` does.

    A program with control flow (subroutines, loops, parameters) keeps its own text where every
    run of a cycle in it makes the same moves; `flatten=True` writes the executed program as
    straight-line code instead (`--flatten`).

    Raises `InputError` for a program the controller refuses or an unknown controller.
    """

class CheckResult(list[dict[str, Any]]):
    """`check`'s findings, a list, with each thread's blank and the rapids into material."""

    blanks: list[dict[str, Any]]
    hits: list[dict[str, Any]]

def check(
    program: str,
    controller: str,
    *,
    machine: _Machine | None = None,
    thread: str | None = None,
    wire: float | None = None,
    stock_diameter: float | None = None,
    stock_start: float | None = None,
    stock_length: float | None = None,
    stock_bore: float | None = None,
    include: list[str | os.PathLike[str]] | None = None,
    start: tuple[float, float] | None = None,
    internal: bool | None = None,
    tool_diameter: float | None = None,
    teeth: int | None = None,
    tools: dict[str, float] | None = None,
) -> CheckResult:
    """What the program will do wrong before the spindle turns: `threadcut check --format json`.

    One dict per finding: `line`, `column`, `level` (`"error"`, `"warning"` or `"note"`, an
    assumption), `code` (`"E013"`, None for a note), `message` and `hint` (or None); errors and
    warnings first, then the notes. A controller alarm is an error finding, not an exception.
    `thread` judges the thread cut against a standard thread's class (`"M30x2-6g"`), and its note
    states the measurement over `wire` (the thread's units, `--wire`; default the best wire);
    `stock_diameter` is the bar's diameter, `stock_start` the Z of its face, `stock_length` its
    length toward the chuck and `stock_bore` a bore through it, in program units (`--stock-*`;
    each not given is the machine profile's `[stock]` value, else not known: the crest and Z0
    are assumed, and said in a note).

    The list is a `CheckResult` with two more attributes: `blanks`, each thread's blank (`line`,
    `crest`, `crest_from`, `face`, `face_from`, as `passes` gives it) and `hits`, the rapid moves
    that run into material (`line`, `level` `"error"` or `"warning"`, and `from`, `to`, `at` —
    where it enters the material — each `(x, z)` in mm, X a radius).

    A milling controller (`fanuc-mill`, `haas-mill`, `linuxcnc-mill`, `centroid`) reads a
    machining centre's program: its milled threads (helices about one axis) and its tapping cycles
    are judged (docs/milling-check.md); `internal` (True, False: external), `tool_diameter`,
    `teeth` and `tools` (`{"D16": 17.0, "T5": 12}`: a cutter's diameter by its offset register or
    tool number), in program units, tell what the program does not show.

    A program with no thread gives `[]` and an `InputWarning`. Raises `InputError` for an unknown
    controller or thread.
    """

def plot_svg(
    program: str,
    controller: str,
    *,
    machine: _Machine | None = None,
    cycle: int | None = None,
    part: bool = False,
    stock_diameter: float | None = None,
    stock_start: float | None = None,
    stock_length: float | None = None,
    stock_bore: float | None = None,
    include: list[str | os.PathLike[str]] | None = None,
    start: tuple[float, float] | None = None,
    internal: bool | None = None,
    tool_diameter: float | None = None,
    teeth: int | None = None,
    tools: dict[str, float] | None = None,
) -> str:
    """One SVG of the threads' pass diagrams and XZ toolpaths (`threadcut plot`): at most the first
    50 threads, the picture saying what it left out, or only the `cycle`th thread (1-based).

    Above them, the part the program makes (where it cuts anything, a stock is given or a rapid
    runs into material): the stock, the part, each thread's teeth, the rapids into material in red
    at their line; `part=True` draws it alone (`--part`). The stock keywords are `check`'s.

    A milling controller draws each milled thread along its axis and from the side, with `check`'s
    milling keywords.

    A program with no thread gives an empty drawing and an `InputWarning`; threads left out without
    `cycle` are an `InputWarning` too. Raises `InputError` for a program the controller refuses, an
    unknown controller, or a `cycle` the program does not have.
    """

def thread(name: str, *, wire: float | None = None) -> dict[str, Any]:
    """A standard thread: the object of `threadcut thread NAME --json`.

    `name` is `M10`, `M10x1.25-6g`, `1/2-13 UNC-2A`, `#10-32 UNF`, `1/2-14 NPT`, `Tr20x4`, ... .
    Keys: `name`, `family`, `series`, `units` (the standard's own), `pitch`, `pitch_mm`, `tpi`,
    `basic` (`major`, `pitch_diameter`, `minor`, `fundamental_height`), `thread_height` and
    `turning_infeed` (`external`, `internal`), and `external` / `internal`: the class limits
    (`class`, `deviation`, `major`, `pitch`, `minor`, each `{min, max}`) of the side the name asks
    for, both without a class; other forms than ISO metric and Unified add `profile` and `taper`.
    `wires`: the three-wire measurement (`wire`, `best`, `min`, `max`, `fits`, `formula`, `basic`,
    `class`, `limits`: M over the wire at the basic and the external class's pitch diameters, by the
    simple formula and with the lead angle), over `wire` (the thread's units, as `--wire`) when
    given, else over the best wire; `gauges` (metric and Unified): the GO / NOT GO gauge sizes of
    each side's class, as `threadcut thread NAME --wire D --json` prints them.

    Raises `InputError` for a name threadcut does not know (its hint names the nearest ones) or a
    wire that is not a positive length.
    """

def mill(
    thread: str,
    *,
    internal: bool,
    length: float,
    tool_diameter: float,
    feed: float,
    controller: str,
    left: bool = False,
    teeth: int = 1,
    top_down: bool = False,
    bottom_up: bool = False,
    passes: int = 1,
    starts: int = 1,
    comp: str = "g41",
    center: tuple[float, float] = (0.0, 0.0),
    start_z: float = 0.0,
    lead: str = "arc",
    clearance: float | None = None,
    units: str | None = None,
    d_register: int | None = None,
) -> str:
    """A thread-milling program (`threadcut mill`): helical G2/G3 full circles, cutter
    compensation, lead-in and lead-out, for a milling controller (`centroid`, `fanuc-mill`,
    `linuxcnc-mill`).

    The options are the command's flags as keywords: `left` (a left-hand thread), `teeth` (on
    the tool, one pitch apart), `top_down` or `bottom_up` (default: climb milling), `passes`
    (radial, of equal chip area), `starts`, `comp` (`"g41"`: the controller's compensation, or
    `"none"`: the tool-centre path), `center` (the thread's axis, X and Y), `start_z` (the top of
    the thread), `lead` (`"arc"` or `"radial"`), `clearance` (above `start_z` for rapid moves,
    default 5 mm), `units` (`"mm"` or `"inch"`, default the thread's own) and `d_register` (the
    D word of G41/G42). Lengths and the feed are in program units.

    Warnings about the plan are `InputWarning`s. Raises `InputError` for an unknown thread or
    milling controller, a class for the other side, or a plan that cannot be milled; its message
    names the command line's flag (`--length`).
    """

def convert(
    program: str,
    source: str,
    target: str,
    *,
    source_machine: _Machine | None = None,
    target_machine: _Machine | None = None,
    flatten: bool = False,
    max_lead_drift: float | None = None,
    tools: dict[str, str] | None = None,
) -> str:
    """The program, written for controller `source`, as a program for controller `target`
    (`threadcut convert`): each cycle as the target's native cycle where reading it back gives the
    same toolpath, else as plain moves with a comment saying why; every other block through the
    two controllers' codes. A program with control flow is copied as it is for the same
    controller; for another one it is converted as executed only with `flatten=True`.
    `max_lead_drift`: the largest drift of a lead the target cannot write exactly, over its thread,
    in the converted program's units (default: a quarter of the thread's medium-class
    pitch-diameter tolerance; the drift is always stated in a comment and an `InputWarning`).
    `tools`: named tools and the numbers that call them (`{"THREAD_EXT_60": "T0101"}`: tool 1,
    offset 1; `"T4"`: tool 4 with its own offset), as `--tool NAME=T0101`: a Sinumerik
    `T="THREAD_EXT_60" D1` written `T0101`, and `T0101` written `T="THREAD_EXT_60" D1` for
    Sinumerik; each replaces the target profile's `[tools]` entry of the same name.
    `source_machine` and `target_machine` are machine profiles, as `machine` elsewhere.

    Raises `InputError` at the first block the target cannot express (its line, column and word),
    for an unknown controller, or for a program the source controller refuses.
    """

def post(apt: str, controller: str, *, machine: _Machine | None = None) -> str:
    """An APT/CL program posted for a controller (`threadcut post`): each THREAD as the
    controller's native cycle where reading it back gives the same toolpath, else as plain moves
    with a comment saying why.

    Raises `InputError` for a statement the post cannot read or an unknown controller.
    """
