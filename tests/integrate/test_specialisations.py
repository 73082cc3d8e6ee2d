"""One compiled specialisation per kernel: a fresh install compiles each kernel once, not per call path.

numba compiles a function once per tuple of argument types, and its types tell read-only arrays
from writable ones and literal constants from plain integers.  A run and its no-pounding twin
passed the model's frozen arrays in one and fresh arrays in the other, which compiled the fast
integrator twice on a fresh install (80 s instead of 45 s for README command 1).  These tests fail
when a call path brings a second specialisation back.  (Regression guards of the compile, not of
the physics.)
"""

import numpy as np

import seispound as sp
from seispound._jit import njit
from seispound.integrate import _driver as D
from seispound.integrate import newmark



def yielding_and_foundation():
    """Two rows on the general driver: bilinear storeys; a foundation on a soil cone."""
    from seispound.foundation import Footing, Foundation, Soil
    from seispound.storey import StoreyLaw

    yielding = sp.load_model("models/two_buildings.toml")
    for b in yielding.buildings:
        b.storey_law = StoreyLaw(kind="bilinear", yield_drift=0.01, post_yield_ratio=0.05)
    foundation = sp.load_model("models/two_buildings.toml")
    foundation.buildings[1].foundation = Foundation(
        mass=4e5, rotary_inertia=2e7, floor_rotary_inertia=3e6, soil=Soil(200.0, 1900.0, 0.3),
        footing=Footing(width=15.0, length=15.0))
    return yielding, foundation


def test_a_run_and_its_twin_share_one_fast_kernel():
    sp.simulate(sp.load_model("models/two_buildings.toml"))  # the pounding run and its twin
    assert len(D.integrate_kernel.signatures) == 1
    assert len(D.drive_two_node.signatures) <= 1  # (none when the entry point comes from the cache)


def test_yielding_storeys_and_a_foundation_share_one_general_kernel():
    for model in yielding_and_foundation():
        sp.simulate(model, twin=False)
    assert len(D.general_kernel.signatures) == 1
    # one time loop, compiled once per linear part (two-node, coefficient vectors) and no more
    assert len(D.drive_coupled.signatures) <= 1


def test_kernel_inputs_are_writable_copies_only_when_frozen():
    a = np.arange(3.0)
    b = np.arange(3.0)
    b.setflags(write=False)
    wa, wb = newmark._writable(a, b)
    assert wa is a  # nothing copied when already writable
    assert wb.flags.writeable and wb is not b and np.array_equal(wb, b)


def test_a_literal_argument_does_not_compile_a_second_specialisation():
    @njit(cache=False)
    def callee(x, k):
        return x[k] + 1.0

    @njit(cache=False)
    def caller(x):
        k = 0  # a literal at the call site: numba.njit would compile callee for Literal[int](0) too
        s = callee(x, k)
        for j in range(x.size):
            s += callee(x, j)
        return s

    assert caller(np.ones(4)) == 10.0
    assert len(callee.signatures) == 1
