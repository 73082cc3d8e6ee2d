"""Floor-acceleration accuracy of the two schemes against the reference twin (shared by the test and docs).

A stiff low-rise pair (4 storeys, T1 = 0.25 s; 6 storeys, T1 = 0.4 s; floor
mass 1e5 kg, Rayleigh 5 % on modes 1 and 2), gap 5 mm at the four common
levels, Hd (k = 5e9 N/m^1.5, e = 0.65), the first 8 s of El Centro 1940 (180)
on the analysis grid (the record's 10 ms samples interpolated linearly, which
is how both solvers see it).  The reference is the twin of
tests/reference_twin.py (solve_ivp LSODA, rtol 1e-9, contacts event-located).
The error measure is the seed's normalised error (Eq. 10) per channel,
NE = ||a_sim - a_ref||_2 / ||a_ref||_2 over the analysis instants, for the
absolute acceleration of every floor; reported is the worst channel.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import scipy.linalg as sl

from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.structure import Gap, assemble
from tests.reference_twin import RefGap, RefLaw, shear_matrices, simulate_reference

from ._helpers import el_centro, shear_building

T_END = 8.0
GAP = 0.005
K_HD, E_HD = 5e9, 0.65


def pair():
    return shear_building("A", 4, 0.25), shear_building("B", 6, 0.4)


def _matrices():
    a, b = pair()
    mats = [shear_matrices(x.floor_masses, x.storey_stiffness, *x.rayleigh_coefficients()) for x in (a, b)]
    return (np.concatenate([x[0] for x in mats]), sl.block_diag(*[x[1] for x in mats]),
            sl.block_diag(*[x[2] for x in mats]))


@lru_cache(maxsize=None)
def reference(pounding: bool, dt: float):
    """Absolute floor accelerations (nt, n) of the twin on the grid k dt."""
    m, K, C = _matrices()
    ag, nsteps = el_centro(T_END, dt)
    t = np.arange(nsteps + 1) * dt
    gaps = [RefGap(f, 4 + f, GAP, RefLaw("Hd", K_HD, E_HD)) for f in range(4)] if pounding else []
    res = simulate_reference(m, K, C, gaps, lambda tt: np.interp(tt, t, ag), T_END, np.zeros(m.size),
                             t_eval=t, rtol=1e-9, breakpoints=t)
    f = -(res.displacement @ K.T) - (res.velocity @ C.T)
    for q, gp in enumerate(gaps):
        f[:, gp.i] -= res.force[:, q]
        f[:, gp.j] += res.force[:, q]
    return f / m


@lru_cache(maxsize=None)
def kernel(pounding: bool, dt: float, scheme: str):
    a, b = pair()
    law = make_law("Hd", stiffness=K_HD, restitution=E_HD)
    system = assemble([a, b], [Gap(("A", "B"), GAP)] if pounding else [], law)
    ag, nsteps = el_centro(T_END, dt)
    raw = integrate(system, ag, dt, nsteps, scheme=scheme)
    return raw.acceleration, raw.impacts["gap"].size


def worst_ne(pounding: bool, dt: float, scheme: str) -> float:
    acc, _ = kernel(pounding, dt, scheme)
    ref = reference(pounding, dt)
    ne = np.linalg.norm(acc - ref, axis=0) / np.linalg.norm(ref, axis=0)
    return float(ne.max())


def table(dts=(0.005, 0.0025, 0.00125)):
    """Worst-channel NE of both schemes with and without pounding, one row per dt."""
    rows = []
    for dt in dts:
        rows.append((dt, *(worst_ne(p, dt, s) for p in (False, True) for s in ("newmark", "exact"))))
    return rows


if __name__ == "__main__":
    print("| dt [ms] | no pounding, Newmark | no pounding, exact | pounding, Newmark | pounding, exact |")
    print("|---|---|---|---|---|")
    for dt, *ne in table():
        print(f"| {1e3 * dt:g} | " + " | ".join(f"{100 * x:.3f} %" for x in ne) + " |")
