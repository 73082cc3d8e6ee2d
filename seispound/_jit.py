"""The package's ``njit``: numba's, with one specialisation per argument type, not per value.

When a compiled function calls another, numba types the call with the arguments as they stand
at the call site, and a constant (``m_act = 0`` before the first impact, ``transposed=True``)
is typed as its literal value: the callee is compiled once for ``Literal[int](0)`` and again
for ``int64``.  On a fresh install that doubled the compile of a dozen of the integrator's
functions (about 5 s of the first run's 45 s, ``python -m benchmarks.startup``).  This
dispatcher types every call with the arguments' plain types (``numba.types.unliteral``), so
each function compiles once per argument type; LLVM still folds the constants where it
inlines the callee.  Nothing in the package dispatches on a literal value.

It is numba's CPU dispatcher (``numba.core.registry.CPUDispatcher``, the class
``numba.njit`` builds) with one method overridden; the options are numba's.

Its on-disk cache is keyed by every source the compiled code depends on, not only its own
file: numba checks only the file that defines a function (``numba.core.caching``), while the
integrator's kernels inline laws from other modules and freeze constants imported from others,
so that an edit of ``_material.py`` alone would leave ``_general.py``'s cached kernel running the
old law.  Each cached
function's stamp therefore carries the hash of the sources of every module in the package that a
compiled module imports, transitively (``package_stamp``).
"""

from __future__ import annotations

import functools
import hashlib
import re
import threading
from importlib import import_module
from pathlib import Path

from numba.core import config, types
from numba.core.registry import CPUDispatcher

# imported by name so that the cache's stamp (``package_stamp``) does not follow it: it runs around
# compiled code, never inside it
_first_use = import_module(__package__ + "._first_use")

_ROOT = Path(__file__).resolve().parent


class _Dispatcher(CPUDispatcher):
    """``CPUDispatcher`` whose calls from compiled code are typed without literal values, and whose first call
    from Python may run its Python source while it compiles in the background (:mod:`seispound._first_use`)."""

    def __call__(self, *args, **kws):
        if _first_use.depth and _first_use.thread == threading.get_ident():  # below a Python run: Python throughout
            return self.py_func(*args, **kws)
        if self.overloads:  # machine code in this process
            return super().__call__(*args, **kws)
        return _first_use.first_call(self, args, kws, super().__call__)

    def get_call_template(self, args, kws):
        args = tuple(types.unliteral(a) for a in args)
        kws = {k: types.unliteral(v) for k, v in kws.items()}
        return super().get_call_template(args, kws)


_IMPORT = re.compile(r"^[ \t]*(?:from[ \t]+(\.*)([\w.]*)[ \t]+import[ \t]+([\w, \t]*)|import[ \t]+([\w.]+))", re.M)


def _imports(path: Path) -> set[Path]:
    """The package's modules that the module at ``path`` imports (``from .a import b``, ``from .. import a as c``,
    ``from seispound.a import b``, ``import seispound.a``), as source paths (a package's ``__init__.py``).

    A regular expression over the lines, not ``ast``: parsing the kernels' sources cost 0.2 s at import."""
    out = set()
    for dots, module, names, plain in _IMPORT.findall(path.read_text(encoding="utf-8")):
        if plain:
            base, module = None, plain
        elif dots:
            base = path.parent
            for _ in range(len(dots) - 1):
                base = base.parent
        else:
            base = None
        if base is None:
            if module.split(".")[0] != _ROOT.name:
                continue
            base, module = _ROOT.parent, module
        target = base.joinpath(*module.split(".")) if module else base
        cands = [target] + ([target / n.split()[0] for n in names.split(",") if n.strip()] if not module else [])
        for n in cands:
            for cand in (n.with_suffix(".py"), n / "__init__.py"):
                if cand.is_file():
                    out.add(cand.resolve())
    return out


@functools.lru_cache(maxsize=1)
def package_stamp() -> str:
    """sha256 [hex] of the sources of every module a compiled module depends on, within the package.

    The compiled modules are those that import this one; their imports are followed transitively
    (``_imports``).  Any edit of one of them, or of a constant module they read (``contact.codes``),
    invalidates every cached function of the package.
    """
    todo = [p.resolve() for p in sorted(_ROOT.rglob("*.py")) if b"_jit import njit" in p.read_bytes()]
    seen = set()
    while todo:
        p = todo.pop()
        if p not in seen:
            seen.add(p)
            todo.extend(_imports(p) - seen)
    h = hashlib.sha256()
    for p in sorted(seen):
        h.update(str(p.relative_to(_ROOT)).encode())
        h.update(p.read_bytes())
    return h.hexdigest()


def _stamp_with_package(disp) -> None:
    """Make ``disp``'s cache index carry ``package_stamp`` beside numba's stamp of its own file (numba
    rejects an index whose stamp differs: the function is then compiled again)."""
    cache_file = getattr(getattr(disp, "_cache", None), "_cache_file", None)
    if cache_file is None or not hasattr(cache_file, "_source_stamp"):
        raise RuntimeError("numba's cache has changed shape: seispound cannot key its cache by its sources")
    cache_file._source_stamp = (cache_file._source_stamp, package_stamp())


def njit(*, cache: bool = True, **options):
    """Decorator: compile ``nopython`` like ``numba.njit(cache=cache, **options)``.

    Parameters
    ----------
    cache : bool
        Keep the compiled code on disk (numba's cache, ``NUMBA_CACHE_DIR``).
    **options
        numba target options (``inline``, ``fastmath``, ...).
    """

    def wrap(func):
        if config.DISABLE_JIT:  # NUMBA_DISABLE_JIT=1, as numba.njit honours it
            return func
        disp = _Dispatcher(py_func=func, locals={}, targetoptions=dict(options, nopython=True))
        if cache:
            disp.enable_caching()
            _stamp_with_package(disp)
        return disp

    return wrap
