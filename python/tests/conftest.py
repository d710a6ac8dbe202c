"""Shared fixtures: the repository's examples, each with its controller, and the `threadcut`
command to compare with (THREADCUT_CLI, else the workspace's debug build, built if missing)."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

# Each example's controller, by the start of its name (the longest profile name first).
PREFIXES = [
    ("fanuc-b", "fanuc-b"),
    ("fanuc15", "fanuc15"),
    ("fanuc", "fanuc"),
    ("gsk", "gsk980"),
    ("haas", "haas"),
    ("linuxcnc", "linuxcnc"),
    ("omniturn", "omniturn"),
    ("sinumerik", "sinumerik"),
    ("ab9", "ab9"),
]


def controller_of(path):
    for prefix, controller in PREFIXES:
        if path.name.startswith(prefix):
            return controller
    raise AssertionError(f"no controller for {path.name}")


def gcode_examples():
    """(path, controller) of every G-code example."""
    out = []
    for p in sorted(EXAMPLES.iterdir()):
        if p.suffix in (".nc", ".ngc", ".mpf"):
            out.append((p, controller_of(p)))
    return out


def apt_examples():
    return sorted(EXAMPLES.glob("*.apt"))


def _cli_path():
    given = os.environ.get("THREADCUT_CLI")
    if given:
        return pathlib.Path(given)
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    path = target / "debug" / "threadcut"
    if not path.exists():
        subprocess.run(["cargo", "build", "-q", "-p", "threadcut-cli"], cwd=ROOT, check=True)
    return path


class Cli:
    """The `threadcut` command, run in the repository's root."""

    def __init__(self, path):
        self.path = path

    def run(self, *args, stdin=None):
        return subprocess.run(
            [str(self.path), *args],
            cwd=ROOT,
            input=stdin,
            capture_output=True,
            text=True,
        )

    def out(self, *args, stdin=None):
        """Standard output of a run that must succeed."""
        r = self.run(*args, stdin=stdin)
        assert r.returncode == 0, r.stderr
        return r.stdout

    def json(self, *args, stdin=None):
        return json.loads(self.out(*args, stdin=stdin))


def one_line(stderr, name="<string>"):
    """The command's first message on standard error (`error[E004]: message`, then ` --> -:2:8`
    where it has a place) in the one-line form of `str(InputError)`, the program named `name`."""
    lines = stderr.splitlines()
    head = lines[0]
    if len(lines) > 1 and lines[1].lstrip().startswith("--> "):
        place = lines[1].lstrip()[4:]
        file, line, column = place.rsplit(":", 2)
        return f"{name}:{line}:{column}: {head}"
    return head


def help_lines(stderr):
    """The `= help:` texts of the command's messages."""
    return [l.split("= help: ", 1)[1] for l in stderr.splitlines() if "= help: " in l]


@pytest.fixture(scope="session")
def cli():
    return Cli(_cli_path())
