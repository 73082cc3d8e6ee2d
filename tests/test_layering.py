"""Layering: the model package imports nothing of the integrator but its plain settings
(``integrate.settings``: Newmark's parameters), and reading a model or asking for help compiles
nothing (numba is not even imported)."""

import ast
import subprocess
import sys
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "seispound"


def _imports(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            yield ("." * node.level) + (node.module or "")
        elif isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)


def test_model_package_does_not_import_the_integrator():
    offenders = [(p.name, m) for p in (PKG / "model").glob("*.py") for m in _imports(p)
                 if ("integrate" in m and m != "..integrate.settings") or m.startswith("numba")]
    assert offenders == []


def _modules_after(code):
    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(sorted(sys.modules))"],
                         capture_output=True, text=True, check=True, cwd=PKG.parent)
    return set(eval(out.stdout.strip().splitlines()[-1]))


def test_reading_a_model_loads_no_numba():
    mods = _modules_after("import seispound.model as m\nm.load_model('models/two_buildings.toml').validate()")
    assert "numba" not in mods
    assert {m for m in mods if m.startswith("seispound.integrate")} <= {"seispound.integrate",
                                                                         "seispound.integrate.settings"}


def test_help_loads_no_numba():
    mods = _modules_after("from seispound.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass")
    assert "numba" not in mods
