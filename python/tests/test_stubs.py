"""The type stubs (`python/threadcut.pyi`) describe the module as it is: the same public names,
the same parameters with the same defaults, the same docstrings (`help()` shows what an IDE
shows)."""

import ast
import inspect
import pathlib

import threadcut

STUB = pathlib.Path(__file__).resolve().parents[1] / "threadcut.pyi"
TREE = ast.parse(STUB.read_text())


def stub_functions():
    return {n.name: n for n in TREE.body if isinstance(n, ast.FunctionDef)}


def stub_classes():
    return {
        n.name: n for n in TREE.body if isinstance(n, ast.ClassDef) and not n.name.startswith("_")
    }


def test_the_stub_and_the_module_have_the_same_names():
    public = set(stub_functions()) | set(stub_classes()) | {"__version__"}
    assert set(threadcut.__all__) == public
    for name in public:
        assert hasattr(threadcut, name), name
    assert threadcut.__version__ == "0.1.0"


def test_the_package_ships_the_stub():
    package = pathlib.Path(threadcut.__file__).parent
    assert (package / "__init__.pyi").read_text() == STUB.read_text()
    assert (package / "py.typed").exists()


def stub_parameters(node):
    a = node.args
    out = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + a.defaults
    for arg, d in zip(positional, defaults):
        out.append((arg.arg, inspect.Parameter.POSITIONAL_OR_KEYWORD, d))
    for arg, d in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, inspect.Parameter.KEYWORD_ONLY, d))
    return [
        (name, kind, inspect.Parameter.empty if d is None else ast.literal_eval(d))
        for name, kind, d in out
    ]


def test_every_function_has_the_stubs_signature():
    for name, node in stub_functions().items():
        runtime = inspect.signature(getattr(threadcut, name))
        got = [(p.name, p.kind, p.default) for p in runtime.parameters.values()]
        assert got == stub_parameters(node), name


def test_every_docstring_is_the_stubs():
    assert inspect.cleandoc(threadcut.__doc__) == inspect.cleandoc(ast.get_docstring(TREE))
    for name, node in {**stub_functions(), **stub_classes()}.items():
        doc = ast.get_docstring(node)
        assert doc, f"{name} has no docstring in the stub"
        assert inspect.cleandoc(getattr(threadcut, name).__doc__) == doc, name
