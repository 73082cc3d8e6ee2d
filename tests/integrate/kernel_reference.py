"""Reference outputs of the integrator on several rows and laws, pinned before a kernel change.

``python -m tests.integrate.kernel_reference`` writes ``tests/data/kernel_reference.npz``;
``test_kernel_reference.py`` reruns every case and compares.  Regenerate only on purpose,
when a change of results is intended and explained (the file's git history says when).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from seispound.contact import make_law
from seispound.integrate import Newmark, integrate
from seispound.structure import Gap, assemble
from tests.verification._helpers import el_centro, shear_building

FILE = Path(__file__).resolve().parents[1] / "data" / "kernel_reference.npz"
FIELDS = ("displacement", "velocity", "acceleration", "force", "energy", "peak_displacement", "peak_force")
HISTORIES = ("displacement", "velocity", "acceleration", "force", "energy")
EVERY = 16
IMPACT_FIELDS = ("gap", "t0", "v0", "vout", "fmax", "dur", "zeta")

_LAWS = {
    "Hd": dict(stiffness=2.75e9, restitution=0.65),
    "LVe": dict(stiffness=9.3e8, restitution=0.65),
    "LVe-clamped": dict(stiffness=9.3e8, restitution=0.65, tension=False),
    "MLVe": dict(stiffness=9.3e8, restitution=0.65),
    "NIVe": dict(stiffness=2.75e9, restitution=0.65),
    "LHC": dict(stiffness=9.3e8, restitution=0.65),
    "Hertzdamp": dict(stiffness=2.75e9, restitution=0.65),
}


def _law(name):
    params = dict(_LAWS[name])
    return make_law(name.split("-")[0], **params)


def _pair(law, size=0.01):
    a = shear_building("A", 4, 0.5)
    b = shear_building("B", 8, 1.0)
    return assemble([a, b], [Gap(("A", "B"), size=size, law=_law(law))])


def _row(law="Hd", size=0.01):
    bs = [shear_building("W", 8, 0.8, modes=(1, 3)), shear_building("M", 12, 1.2, modes=(1, 3)),
          shear_building("E", 6, 0.6, modes=(1, 3))]
    return assemble(bs, [Gap(("W", "M"), size=size, law=_law(law)), Gap(("M", "E"), size=size, law=_law(law))])


def _pairs(n_pairs=4):
    bs, gaps = [], []
    for p in range(n_pairs):
        bs += [shear_building(f"L{p}", 3 + p, 0.3 + 0.1 * p), shear_building(f"R{p}", 6 + p, 0.7 + 0.1 * p)]
        gaps.append(Gap((f"L{p}", f"R{p}"), size=0.004 + 0.002 * p, law=_law("Hd")))
    return assemble(bs, gaps)


def cases():
    """name -> (system, ground acceleration (nt,), dt, nsteps, integrate keyword arguments)."""
    dt = 0.005
    ag8, n8 = el_centro(6.0, dt)
    out = {}
    for law in _LAWS:
        out[f"pair-{law}"] = (_pair(law), ag8, dt, n8, {})
    out["pair-Hd-physical"] = (_pair("Hd"), ag8, dt, n8, dict(free_flight=False))
    ag2, n2 = el_centro(6.0, 0.002)
    out["pair-Hd-linear-acceleration"] = (_pair("Hd"), ag2, 0.002, n2, dict(newmark=Newmark(beta=1 / 6, gamma=0.5)))
    out["row3-Hd"] = (_row("Hd"), ag8, dt, n8, {})
    out["row3-Hd-single-rate"] = (_row("Hd"), ag8, dt, n8, dict(multirate=False))
    out["row3-NIVe"] = (_row("NIVe"), ag8, dt, n8, {})
    out["pairs4-Hd"] = (_pairs(), ag8, dt, n8, dict(wait_share=0.0))
    out["pair-Hd-twin"] = (_pair("Hd").without_contact(), ag8, dt, n8, {})
    return out


def run(case):
    system, ag, dt, nsteps, kw = case
    raw = integrate(system, ag, dt, nsteps, **{"scheme": "newmark", **kw})  # pinned: Newmark throughout
    res = {f: np.asarray(getattr(raw, f)) for f in FIELDS}
    for f in HISTORIES:  # every EVERY-th instant: the file stays small, the comparison as strict
        res[f] = res[f][::EVERY]
    for f in IMPACT_FIELDS:
        res[f"impacts.{f}"] = np.asarray(raw.impacts[f])
    return res


def main():
    data = {}
    for name, case in cases().items():
        for key, value in run(case).items():
            data[f"{name}/{key}"] = value
        print(name, "impacts:", data[f"{name}/impacts.gap"].size)
    np.savez_compressed(FILE, **data)
    print("wrote", FILE, FILE.stat().st_size, "bytes")


if __name__ == "__main__":
    main()
