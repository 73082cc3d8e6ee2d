"""The one time loop (``integrate/_driver.py``): its phases, chosen by the linear part, and the compiled
loop against the same loop run by Python.

Regression guards, not verifications (the physics is verified in ``tests/verification``): the compiled
loop is compared with the same source run by the Python interpreter (``NUMBA_DISABLE_JIT``, in a
subprocess, ``_python_loop.py``), on both linear parts, through free flight and impacts.  numba inlines each phase into the loop; phases inlined through ``numba.extending.overload``
(a way of choosing them that was tried) lost their stores into the energy history while every other
history was right, which only a comparison of every history finds.
"""

import inspect
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from seispound.integrate import _driver as D
from tests.integrate import _python_loop as P

ROOT = Path(__file__).resolve().parents[2]
# (case, steps, driver): the first impacts of a pair and of a row of three, after free flight, on each
# linear part (the first impacts at 1.83 s and 2.01 s: steps 367, 403)
SPECS = ("pair-LVe:420:fast", "row3-Hd:440:fast", "pair-LVe:420:general")


@pytest.fixture(scope="module")
def python_runs(tmp_path_factory):
    out = tmp_path_factory.mktemp("loop") / "python.npz"
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=str(ROOT))
    subprocess.run([sys.executable, "-m", "tests.integrate._python_loop", str(out), *SPECS], cwd=ROOT, env=env,
                   check=True, timeout=900)
    return np.load(out)


@pytest.mark.parametrize("spec", SPECS)
def test_the_compiled_loop_equals_the_loop_run_by_python(spec, python_runs):
    name, nsteps, driver = spec.split(":")
    raw = P.run(name, int(nsteps), driver)
    assert raw.impacts["t0"].size >= 2  # the comparison passes through impacts
    np.testing.assert_array_equal(raw.impacts["t0"].size, python_runs[f"{spec}/t0"].size)
    worst = {}
    for f in P.FIELDS:
        ref = python_runs[f"{spec}/{f}"]
        got = np.asarray(getattr(raw, f))
        worst[f] = float(np.abs(got - ref).max() / max(np.abs(ref).max(), 1e-300))
    print(f"MEASURED {spec}: compiled vs Python", {k: f"{v:.1e}" for k, v in worst.items()})
    assert max(worst.values()) <= 1e-13, worst  # measured: at most 2.8e-14 (the coefficient-vector part)


def test_every_phase_has_one_signature_on_both_linear_parts(monkeypatch):
    from seispound.integrate import _general as G
    from seispound.integrate import _kernel as K

    for two_node, coupled in D.PHASES.values():
        assert str(inspect.signature(two_node.py_func)) == str(inspect.signature(coupled.py_func))
    monkeypatch.setitem(D.PHASES, "_trial", (K._trial, G._screen))
    with pytest.raises(TypeError, match="one phase, two signatures"):
        D._bind(D.drive, "drive_mismatched", 0)


def test_the_loop_is_one_source_bound_per_linear_part():
    for bound, part in ((D.drive_two_node, 0), (D.drive_coupled, 1)):
        assert bound.py_func.__code__ is D.drive.__code__
        for name, impls in D.PHASES.items():
            assert bound.py_func.__globals__[name] is impls[part]
