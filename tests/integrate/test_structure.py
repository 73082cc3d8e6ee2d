"""The compiled code's shape: every numba-compiled function of the package short enough to read on one screen
and with few arguments (issue 29: "no compiled function longer than about 150 lines or with more than about a
dozen arguments: work arrays travel in a few named structures").

A regression guard on the source, not a verification: it reads the package's files with ``ast`` and lists
each function decorated with the package's ``njit`` (or numba's) whose body, docstring excluded, runs over
MAX_LINES lines or that takes more than MAX_ARGS arguments.
"""

from __future__ import annotations

import ast
from pathlib import Path

import seispound

MAX_LINES = 150
MAX_ARGS = 12
_PACKAGE = Path(seispound.__file__).resolve().parent


def _compiled_functions():
    """(file, name, body lines without the docstring, arguments) of every jit-compiled function."""
    for path in sorted(_PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if not isinstance(node, ast.FunctionDef):
                continue
            if not any("jit" in ast.unparse(d) for d in node.decorator_list):
                continue
            body = node.body
            doc = isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str)
            first = body[1].lineno if doc and len(body) > 1 else body[0].lineno
            yield path.relative_to(_PACKAGE.parent), node.name, node.end_lineno - first + 1, len(node.args.args)


def test_the_scan_sees_the_drivers():
    names = {name for _, name, _, _ in _compiled_functions()}
    assert {"integrate_kernel", "general_kernel", "material_trial"} <= names
    assert len(names) > 100


def test_no_compiled_function_is_longer_than_a_screen():
    long = [f"{f}:{name} ({n} lines)" for f, name, n, _ in _compiled_functions() if n > MAX_LINES]
    assert long == []


def test_no_compiled_function_takes_more_than_a_dozen_arguments():
    many = [f"{f}:{name} ({k} arguments)" for f, name, _, k in _compiled_functions() if k > MAX_ARGS]
    assert many == []
