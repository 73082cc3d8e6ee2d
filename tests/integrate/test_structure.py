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
            bound = path.name == "_driver.py" and node.name == "drive"  # compiled per linear part by ``_bind``
            if not bound and not any("jit" in ast.unparse(d) for d in node.decorator_list):
                continue
            body = node.body
            doc = isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
                and isinstance(body[0].value.value, str)
            first = body[1].lineno if doc and len(body) > 1 else body[0].lineno
            yield path.relative_to(_PACKAGE.parent), node.name, node.end_lineno - first + 1, len(node.args.args)


def test_the_scan_sees_the_drivers():
    names = {name for _, name, _, _ in _compiled_functions()}
    assert {"drive", "integrate_kernel", "general_kernel", "material_trial"} <= names
    assert len(names) > 100


def test_no_compiled_function_is_longer_than_a_screen():
    long = [f"{f}:{name} ({n} lines)" for f, name, n, _ in _compiled_functions() if n > MAX_LINES]
    assert long == []


def test_no_compiled_function_takes_more_than_a_dozen_arguments():
    many = [f"{f}:{name} ({k} arguments)" for f, name, _, k in _compiled_functions() if k > MAX_ARGS]
    assert many == []


# An inlined function, with everything inlined into it, at most this many source lines.  numba copies an
# ``inline="always"`` function at its call site with everything already inlined into it, each block with the
# whole variable scope, so a phase inlined under phases is copied again at every level above it: the loops
# written that way (the fast driver's physical step 995 lines inlined, the general driver's 1038) compiled
# about twice as long as with the loops in the kernels (docs/performance.md, start-up).  Largest now: the
# general driver's trial step, 765.
MAX_INLINED_LINES = 800


def _jit_functions():
    """{(module, name): (inlined?, node)} of every jit-compiled function, and each module's relative imports."""
    funcs, imports = {}, {}
    for path in sorted(_PACKAGE.rglob("*.py")):
        mod = ".".join(path.relative_to(_PACKAGE.parent).with_suffix("").parts)
        tree = ast.parse(path.read_text(encoding="utf-8"))
        imports[mod] = {}
        for node in tree.body:
            if isinstance(node, ast.ImportFrom) and node.level:
                where = ".".join(mod.split(".")[:-node.level] + (node.module.split(".") if node.module else []))
                imports[mod].update({a.asname or a.name: where for a in node.names})
            if isinstance(node, ast.FunctionDef) and any("jit" in ast.unparse(d) for d in node.decorator_list):
                inline = any('inline="always"' in ast.unparse(d).replace("'", '"') for d in node.decorator_list)
                funcs[(mod, node.name)] = (inline, node)
    return funcs, imports


def _inlined_lines():
    """{(module, name): source lines of each inlined function with its inlined callees' (each counted once)}."""
    funcs, imports = _jit_functions()

    def inlined_callees(mod, node):
        for c in ast.walk(node):
            if isinstance(c, ast.Call) and isinstance(c.func, ast.Name):
                key = (mod, c.func.id) if (mod, c.func.id) in funcs else (imports[mod].get(c.func.id), c.func.id)
                if key in funcs and funcs[key][0]:
                    yield key

    memo = {}

    def size(key):
        if key not in memo:
            node = funcs[key][1]
            memo[key] = node.end_lineno - node.lineno + 1 + sum(size(k) for k in set(inlined_callees(key[0], node)))
        return memo[key]

    return {key: size(key) for key, (inline, _) in funcs.items() if inline}


def test_the_inline_scan_sees_the_phases():
    sizes = _inlined_lines()
    assert sizes[("seispound.integrate._kernel", "_trial")] > sizes[("seispound.integrate._kernel", "_accept")]
    assert len(sizes) > 50


def test_no_inlined_function_carries_a_large_tree():
    large = [f"{mod}.{name} ({n} lines inlined)" for (mod, name), n in _inlined_lines().items()
             if n > MAX_INLINED_LINES]
    assert large == []
