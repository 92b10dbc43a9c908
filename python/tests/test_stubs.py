"""The package's stubs (deepsea/_deepsea.pyi): they parse, name every public name of the
extension with the same kind (class or function) and the same keyword arguments, and mypy's
stubtest agrees where mypy is installed."""

import ast
import inspect
import os
import re
import subprocess
import sys

import pytest

import deepsea
import deepsea._deepsea as ext

STUB = os.path.join(os.path.dirname(deepsea.__file__), "_deepsea.pyi")


def stub_tree():
    return ast.parse(open(STUB).read(), STUB)


def public(obj):
    return sorted(n for n in dir(obj) if not n.startswith("_"))


def test_stub_names_every_public_name():
    tree = stub_tree()
    top = {n.name: n for n in tree.body if isinstance(n, (ast.ClassDef, ast.FunctionDef))}
    for name in public(ext):
        assert name in top, f"{name} is not in {STUB}"
        assert isinstance(top[name], ast.ClassDef) == inspect.isclass(getattr(ext, name)), name
    assert set(public(ext)) == set(top), set(top) - set(public(ext))
    assert set(deepsea.__all__) == set(public(ext))
    for cls in ("Asset", "Renderer", "Camera"):
        members = {n.name for n in top[cls].body if isinstance(n, ast.FunctionDef)}
        assert set(public(getattr(ext, cls))) <= members, (cls, members)


def signature_names(doc_first_line):
    """Argument names of a pybind11 signature line "f(a: T, *, b: T = x) -> R"."""
    inside = doc_first_line[doc_first_line.index("(") + 1: doc_first_line.rindex(") ->")]
    return [m.group(1) for m in re.finditer(r"(?:^|, )(\w+)(?::|$|,)", inside)
            if m.group(1) not in ("self",)]


def test_stub_arguments_match():
    tree = stub_tree()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef):
            a = node.args
            names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
            doc = getattr(ext, node.name).__doc__.splitlines()[0]
            assert signature_names(doc) == names, (node.name, doc)


def test_package_is_typed():
    assert os.path.exists(os.path.join(os.path.dirname(deepsea.__file__), "py.typed"))


def test_stubtest():
    pytest.importorskip("mypy.stubtest")
    r = subprocess.run([sys.executable, "-m", "mypy.stubtest", "deepsea._deepsea",
                        "--allowlist", os.path.join(os.path.dirname(__file__),
                                                    "stubtest_allowlist.txt")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
