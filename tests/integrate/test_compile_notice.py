"""The first use of a kernel with nothing cached says that it compiles (issue: a silent 30 s start)."""

import io
from types import SimpleNamespace

from seispound.integrate import _driver as D
from seispound.integrate import newmark


def _kernel(signatures, index_path):
    # numba's dispatcher keeps its compiled overloads in a dict keyed by signature
    return SimpleNamespace(overloads={s: None for s in signatures},
                           _cache=SimpleNamespace(_cache_file=SimpleNamespace(_index_path=str(index_path))))


def test_says_it_compiles_once_when_nothing_is_cached(tmp_path, monkeypatch):
    monkeypatch.setattr(newmark, "_ANNOUNCED", set())
    out = io.StringIO()
    fresh = _kernel([], tmp_path / "missing.nbi")
    assert newmark.announce_compile(fresh, "general", stream=out)
    assert not newmark.announce_compile(fresh, "general", stream=out)  # once per process
    line = out.getvalue().strip()
    assert line.count("\n") == 0 and "compiling the general integrator" in line and "cached afterwards" in line


def test_silent_when_compiled_or_cached(tmp_path, monkeypatch):
    monkeypatch.setattr(newmark, "_ANNOUNCED", set())
    out = io.StringIO()
    index = tmp_path / "kernel.nbi"
    index.write_bytes(b"")
    assert not newmark.announce_compile(_kernel([], index), "fast", stream=out)  # on disk
    assert not newmark.announce_compile(_kernel(["sig"], tmp_path / "missing.nbi"), "fast", stream=out)  # in memory
    assert out.getvalue() == ""


def test_the_real_kernel_has_the_cache_layout_the_notice_reads():
    # numba's FunctionCache keeps its index path here; if a numba release moves it, the notice goes quiet
    assert D.general_kernel._cache._cache_file._index_path.endswith(".nbi")
    assert isinstance(D.general_kernel.overloads, dict)
