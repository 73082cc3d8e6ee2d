"""The compiled code's disk cache is keyed by every source it depends on (``seispound._jit``).

numba checks only the file that defines a cached function; the kernels inline the storey and
contact laws of ``_material.py`` and ``contact/_scalar.py`` and freeze the columns of
``storey/codes.py``, so without this an edit there left the cached kernels running the old code.
(Regression guards of the cache, not of the physics.)
"""

from pathlib import Path

from seispound import _jit
from seispound.integrate import _driver, _material

ROOT = Path(_jit.__file__).resolve().parent


def _closure():
    todo = [p.resolve() for p in ROOT.rglob("*.py") if b"_jit import njit" in p.read_bytes()]
    seen = set()
    while todo:
        p = todo.pop()
        if p not in seen:
            seen.add(p)
            todo.extend(_jit._imports(p) - seen)
    return {str(p.relative_to(ROOT)) for p in seen}


def test_the_stamp_covers_the_laws_and_constants_the_kernels_inline():
    files = _closure()
    for needed in ("integrate/_material.py", "integrate/_general.py", "integrate/_kernel.py", "integrate/_driver.py", "contact/_scalar.py",
                   "contact/codes.py", "storey/codes.py", "integrate/_outputs.py"):
        assert needed in files
    # what no compiled code reads stays out, so that editing it does not recompile the integrator
    for other in ("diagnose/api.py", "storey/laws.py", "integrate/newmark.py", "cli.py"):
        assert other not in files


def test_relative_imports_of_a_package_and_of_names_resolve(tmp_path, monkeypatch):
    pkg = tmp_path / "seispound"
    (pkg / "a").mkdir(parents=True)
    for f in ("__init__.py", "a/__init__.py", "a/b.py", "a/c.py", "d.py"):
        (pkg / f).write_text("")
    (pkg / "a" / "k.py").write_text("from .b import x\nfrom . import c as C\nfrom ..d import (\n    y,\n)\nimport numpy\n")
    monkeypatch.setattr(_jit, "_ROOT", pkg)
    got = {str(p.relative_to(pkg.resolve())) for p in _jit._imports(pkg / "a" / "k.py")}
    assert got == {"a/b.py", "a/c.py", "a/__init__.py", "d.py"}


def test_every_cached_kernel_carries_the_package_stamp():
    for disp in (_driver.integrate_kernel, _driver.general_kernel, _driver.drive_two_node, _driver.drive_coupled,
                 _material.material_energy):
        own, package = disp._cache._cache_file._source_stamp
        assert package == _jit.package_stamp() and own  # numba's stamp of its own file stays beside it
