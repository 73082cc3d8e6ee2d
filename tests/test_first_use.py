"""A first use runs the Python source while numba compiles in the background (``seispound._first_use``).

Each check runs in a child process with an empty numba cache (``NUMBA_CACHE_DIR``), as a fresh
install has.  The function compiled there is ``integrate._exact.exact_coefficients`` (a few
seconds to compile; its Python form is a loop over the modes), except in the last check, which
runs README command 1 (``seispound run models/two_buildings.toml``) whole.  The suite itself
compiles as numba does (``conftest.py`` sets ``SEISPOUND_INTERPRET_SECONDS=0``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]

SETUP = """
import sys, time, numpy as np
from seispound import _first_use as F
from seispound.integrate._exact import exact_coefficients as f
F.label(f, "the exact coefficients", "a few s")
n = int(sys.argv[1])
w2 = np.linspace(1.0, 400.0, n); c = 0.05 * np.sqrt(w2); out = np.full((8, n), np.nan)
m = min(n, 2000); ref = np.empty((8, m)); f.py_func(w2[:m], c[:m], 0.005, ref)  # the Python form, first columns
"""


def _child(code, tmp_path, *args, **env):
    environ = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"), PYTHONPATH=str(ROOT), **env)
    return subprocess.run([sys.executable, "-c", textwrap.dedent(SETUP) + textwrap.dedent(code), *map(str, args)],
                          cwd=tmp_path, env=environ, capture_output=True, text=True, timeout=600)


def _lines(stderr):
    return [ln for ln in stderr.splitlines() if ln.startswith("seispound:")]


def test_a_first_use_runs_as_python_and_the_next_process_finds_it_compiled(tmp_path):
    first = _child("""
        with F.interpret_first_use():
            f(w2, c, 0.005, out)
            assert F.interpreted_calls == 1 and not f.overloads, "ran as Python, compiled nothing here"
        job, = set(F._compiled_by.values())  # started as the block ended
        assert job.wait(timeout=300) == 0
        assert np.array_equal(out[:, :m], ref)
        np.save("out.npy", out)
        """, tmp_path, 40, SEISPOUND_INTERPRET_SECONDS="30")
    assert first.returncode == 0, first.stderr
    said = _lines(first.stderr)
    assert len(said) == 1 and "the exact coefficients is not compiled yet" in said[0], said
    second = _child("""
        f(w2, c, 0.005, out)
        hits, misses = sum(f.stats.cache_hits.values()), sum(f.stats.cache_misses.values())
        assert (hits, misses) == (1, 0), (hits, misses)
        print(np.abs(out - np.load("out.npy")).max() / np.abs(ref).max())  # n <= 2000: every column
        """, tmp_path, 40)
    assert second.returncode == 0, second.stderr
    assert _lines(second.stderr) == []  # loaded, not compiled: nothing to say
    # machine code and Python form of one source (a regression guard): measured 0
    assert float(second.stdout) <= 1e-15


@pytest.mark.parametrize("n, budget, then", [
    (400_000, "0.2", "waiting for the exact coefficients to compile"),  # 1.5 s of Python, a budget of 0.2 s
    (5_000_000, "300", "the exact coefficients has compiled in the background"),  # 8 s of Python, 2.5 s to compile
])
def test_a_python_run_is_stopped_by_its_timer_and_goes_on_as_machine_code(tmp_path, n, budget, then):
    run = _child("""
        with F.interpret_first_use():
            f(w2, c, 0.005, out)
        assert F.interpreted_calls == 0 and sum(f.stats.cache_hits.values()) == 1, "stopped, loaded from the cache"
        print(np.abs(out[:, :m] - ref).max() / np.abs(ref).max())
        """, tmp_path, n, SEISPOUND_INTERPRET_SECONDS=budget)
    assert run.returncode == 0, run.stderr
    said = _lines(run.stderr)
    assert len(said) == 2 and then in said[1], said
    # the output array was put back and written by the compiled call: equal to the Python form's (measured 0)
    assert float(run.stdout) <= 1e-15


def test_a_python_run_that_raises_gives_way_to_the_machine_code(tmp_path):
    run = _child("""
        from tests._first_use_functions import root
        F.label(root, "the root", "a few s")
        with F.interpret_first_use():
            r = root(-1.0)
        assert F.interpreted_calls == 0 and len(root.overloads) == 1 and np.isnan(r), r
        """, tmp_path, 40, SEISPOUND_INTERPRET_SECONDS="30")
    assert run.returncode == 0, run.stderr
    said = _lines(run.stderr)
    assert len(said) == 2 and "its Python run stopped (ValueError: math domain error)" in said[1], said


DEAD_BEFORE_ITS_WORK = """
    import subprocess

    class Dead(subprocess.Popen):  # it has ended before its work is written to it: the write finds a broken pipe
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            self.wait()

    subprocess.Popen = Dead
"""


@pytest.mark.parametrize("when", ["as it happens", "ended before its work is written"])
def test_a_failed_background_compile_is_reported_and_the_run_compiles_here(tmp_path, when):
    run = _child(textwrap.dedent(DEAD_BEFORE_ITS_WORK if when.startswith("ended") else "") + textwrap.dedent("""
        sys.executable = "/bin/false"  # the background process exits at once with status 1
        with F.interpret_first_use():
            f(w2, c, 0.005, out)
        assert F.interpreted_calls == 0 and len(f.overloads) == 1
        """), tmp_path, 400_000, SEISPOUND_INTERPRET_SECONDS="0.2")
    assert run.returncode == 0, run.stderr
    said = _lines(run.stderr)
    assert len(said) == 2 and said[1].startswith("seispound: the compile in the background failed (exit 1; its "
                                                 "messages: "), said
    assert said[1].endswith("seispound-compile.log): compiling the exact coefficients here (a few s)"), said


def test_other_threads_keep_their_machine_code_during_a_python_run(tmp_path):
    # root(-1) is NaN as machine code and raises as Python: a thread calling it while the main thread runs Python
    run = _child("""
        import threading
        from tests._first_use_functions import root
        root(4.0)  # compiled, outside the block
        seen, stop = [], threading.Event()

        def other():
            while not stop.is_set():
                try:
                    seen.append(np.isnan(root(-1.0)))
                except ValueError:
                    seen.append("python")

        worker = threading.Thread(target=other)
        worker.start()
        with F.interpret_first_use():
            f(w2, c, 0.005, out)  # about 0.4 s of Python
        stop.set()
        worker.join()
        assert F.interpreted_calls == 1 and len(seen) > 10 and all(x is np.True_ for x in seen), seen[:5]
        """, tmp_path, 100_000, SEISPOUND_INTERPRET_SECONDS="30", SEISPOUND_COMPILE_AHEAD="0")
    assert run.returncode == 0, run.stderr


def test_outside_the_block_a_first_use_compiles_and_says_so_once(tmp_path):
    run = _child("""
        f(w2, c, 0.005, out)
        f(w2, c, 0.005, out)
        assert F.interpreted_calls == 0 and len(f.overloads) == 1
        """, tmp_path, 40, SEISPOUND_INTERPRET_SECONDS="30")
    assert run.returncode == 0, run.stderr
    said = _lines(run.stderr)
    assert said == ["seispound: compiling the exact coefficients (first use since installing; a few s, cached "
                    "afterwards)"], said


def test_no_python_run_when_switched_off(tmp_path):
    run = _child("""
        with F.interpret_first_use():
            f(w2, c, 0.005, out)
        assert F.interpreted_calls == 0 and len(f.overloads) == 1 and not F._compiled_by
        """, tmp_path, 40, SEISPOUND_INTERPRET_SECONDS="0")
    assert run.returncode == 0, run.stderr
    assert "compiling the exact coefficients" in run.stderr


def test_readme_command_1_on_a_fresh_install_runs_as_python_and_matches_the_compiled_run(tmp_path):
    import seispound as sp

    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"), SEISPOUND_COMPILE_AHEAD="0",
               SEISPOUND_INTERPRET_SECONDS="300")  # generous: a loaded machine must not fall back to compiling
    out = tmp_path / "two_buildings.h5"
    run = subprocess.run([sys.executable, "-m", "seispound", "run", str(ROOT / "models" / "two_buildings.toml"),
                          "-o", str(out), "-q"], env=env, capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    assert "the fast integrator is not compiled yet" in run.stderr
    compiled = sp.simulate(sp.load_model(ROOT / "models" / "two_buildings.toml"))
    with xr.open_dataset(out) as python:
        assert python.attrs["integrator_run_as"].startswith("Python")
        assert compiled.attrs["integrator_run_as"] == "numba machine code"
        worst = 0.0
        for name, var in compiled.data_vars.items():
            if var.dtype.kind == "f" and np.isfinite(var.values).any():
                scale = np.nanmax(np.abs(var.values))
                if scale > 0:
                    worst = max(worst, float(np.nanmax(np.abs(python[name].values - var.values))) / scale)
    # the same source as machine code and as Python (a regression guard): measured 7.0e-16 of each
    # variable's largest value, 46 impacts in both
    assert worst <= 2e-15


@pytest.mark.parametrize("kernel, model", [("integrate_kernel", "two_buildings.toml"),
                                           ("general_kernel", "yielding_pair.toml")])
def test_the_cache_check_reads_numbas_index(kernel, model, tmp_path):
    # numba keeps the index of its cache in this layout; if a release moves it, a first use compiles (the check
    # answers "cached"), it never runs a compiled function as Python by mistake
    import seispound as sp
    from seispound import _first_use as F
    from seispound.integrate import _driver as D
    from tests._models import short_copy

    sp.simulate(sp.load_model(short_copy(tmp_path, 0.5, model)), twin=False)
    function = getattr(D, kernel)
    sig, = function.overloads
    assert F._cached(function, sig) is True
    assert F._cached(function, sig[:-1]) is False
