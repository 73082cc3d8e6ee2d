"""The counting copy of the kernel (``benchmarks.attempts``) counts without changing what it counts."""

import numpy as np
import pytest

from benchmarks.attempts import counting, counting_kernel, count, P_ATTEMPTS, N_PROBE
from seispound import load_model
from benchmarks.canonical import CANONICAL
from seispound.integrate import Newmark, integrate
from seispound.simulation import prepare_ground_motion
from seispound.structure import assemble


@pytest.fixture(scope="module")
def canonical():
    m = load_model(CANONICAL)
    ag, _ = prepare_ground_motion(m)
    return assemble(m.buildings, m.gaps, m.contact), ag, m.analysis.dt, 2000  # first 10 s


@pytest.fixture(scope="module")
def module():
    return counting_kernel()


def test_counting_copy_computes_the_same_run_bit_for_bit(module, canonical):
    system, ag, dt, nsteps = canonical
    ag = ag[: nsteps + 1]
    plain = integrate(system, ag, dt, nsteps, Newmark(contact_substeps=16), free_flight=False, multirate=False)
    probe = np.zeros(N_PROBE)
    with counting(module, probe):
        counted = integrate(system, ag, dt, nsteps, Newmark(contact_substeps=16), free_flight=False, multirate=False)
    assert counted.impacts["gap"].size == plain.impacts["gap"].size > 10
    np.testing.assert_array_equal(counted.displacement, plain.displacement)
    np.testing.assert_array_equal(counted.force, plain.force)
    # every attempt is either accepted (a step) or redone (rejected)
    assert probe[P_ATTEMPTS] == plain.stats["steps"] + plain.stats["rejected"]
    from seispound.integrate import newmark
    assert newmark.D.__name__.endswith("_driver")  # the real driver is back


def test_multirate_bound_lies_between_one_step_and_the_attempts_taken(module, canonical):
    system, ag, dt, nsteps = canonical
    c, raw = count(module, system, ag[: nsteps + 1], dt, nsteps, 32)
    taken = raw.stats["steps"] + raw.stats["rejected"]
    assert c["attempts"] == taken
    assert c["attempts_per_step"] == pytest.approx(taken / nsteps, rel=1e-12)
    # every building steps at least once per analysis step; multi-rate never costs more than now
    assert 1.0 < c["multirate_per_step"] <= c["attempts_per_step"]
    # the kernel as built does no more work than single-rate, and at least a step per analysis step
    assert 1.0 < c["built_per_step"] <= c["attempts_per_step"]
    assert c["mean_closed"] >= 1.0
