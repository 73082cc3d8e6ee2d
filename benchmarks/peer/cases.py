"""Peer cases: one description per case, from which both programs are built.

A case names its buildings (storeys, fundamental period, floor mass, Rayleigh
ratio), the gap between neighbours, the contact law and its parameters, and a
record.  :meth:`PeerCase.model` gives the seispound Model;
:func:`benchmarks.peer.opensees.run_opensees` writes the OpenSees model from
that same Model.

Ground motion: the record (m/s^2, at its own dt) is preceded by one zero sample
and interpolated linearly at the analysis step for both programs.  OpenSees
starts Newmark from zero acceleration, seispound from equilibrium
(a0 = -a_g(0)); starting from rest with a_g(0) = 0 makes the two the same
state (with El Centro's a_g(0) = 0.0098 m/s^2 the linear responses differ by
1e-5, with the zero sample by 4e-12: see ``docs/peer.md``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from seispound.contact import make_law
from seispound.integrate import Newmark
from seispound.model.spec import Analysis, Model
from seispound.motion import read_record
from seispound.motion.catalogue import bundled_path
from seispound.structure import Building, Gap, RayleighDamping

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared" / "ground_motions"

# contact stiffness per law: linear laws [N/m], Hertz-type [N/m^1.5]
STIFFNESS = {"LVe": 5e8, "MLVe": 5e8, "NIVe": 2.75e9}
RESTITUTION = 0.65


def uniform_storey_stiffness(mass: float, n: int, period: float) -> float:
    """Storey stiffness [N/m] of a uniform n-storey shear building with fundamental period ``period`` [s].

    The fixed-free chain of equal masses and springs has
    omega_1 = 2 sqrt(k/m) sin(pi / (2 (2n + 1))).
    """
    w1 = 2.0 * math.pi / period
    return mass * (w1 / (2.0 * math.sin(math.pi / (2.0 * (2 * n + 1))))) ** 2


@dataclass(frozen=True)
class BuildingSpec:
    name: str
    storeys: int
    period: float  # s
    mass: float = 1e5  # kg per floor
    ratio: float = 0.05  # Rayleigh ratio at modes 1 and 2
    height: float = 3.0  # m per storey

    def building(self) -> Building:
        k = uniform_storey_stiffness(self.mass, self.storeys, self.period)
        modes = (1, min(2, self.storeys))
        return Building(self.name, [self.mass] * self.storeys, [k] * self.storeys, [self.height] * self.storeys,
                        RayleighDamping(ratio=self.ratio, modes=modes))


@dataclass(frozen=True)
class PeerCase:
    """One row of buildings under one record with one law (or none)."""

    name: str
    buildings: tuple
    gap: float  # m, at every common level of every pair of neighbours
    law: str | None  # "LVe", "NIVe", "MLVe" or None (gaps that never close)
    record: str  # bundled catalogue name, or a path
    duration: float  # s of the record used
    scale: float = 1.0

    def model(self, dt: float = 0.005, newmark: Newmark | None = None) -> Model:
        bs = [b.building() for b in self.buildings]
        law = self.law or "LVe"
        gaps = [Gap((a.name, b.name), self.gap if self.law else 10.0)  # no law: gaps too wide to close
                for a, b in zip(self.buildings, self.buildings[1:])]
        return Model(self.name, bs, gaps, make_law(law, stiffness=STIFFNESS[law], restitution=RESTITUTION),
                     Analysis(dt, self.duration, newmark or Newmark()))

    def record_path(self) -> Path:
        p = Path(self.record)
        if p.suffix:
            return p if p.is_absolute() else REPO / p
        return bundled_path(self.record)

    def ground(self, dt: float) -> tuple[np.ndarray, int]:
        """(a_g at k dt, k = 0..nsteps [m/s^2], nsteps): the record after one zero sample, linear in between."""
        rec = read_record(self.record_path(), scale=self.scale)
        acc = np.concatenate([[0.0], np.asarray(rec.acceleration)])
        nsteps = int(round(self.duration / dt))
        t = np.arange(nsteps + 1) * dt
        return np.interp(t, np.arange(acc.size) * rec.dt, acc, right=0.0), nsteps

    def with_(self, **changes) -> "PeerCase":
        return replace(self, **changes)


PAIR = (BuildingSpec("A", 3, 0.4), BuildingSpec("B", 5, 0.7))
ROW4 = tuple(BuildingSpec(n, 10, T) for n, T in zip("ABCD", (1.0, 0.8, 1.25, 0.9)))
PEER_LAWS = ("LVe", "NIVe", "MLVe", None)


def kobe_nis090() -> str:
    """Kobe 1995 Nishi-Akashi 090 from the shared test records (falls back to the copy in tests/data)."""
    shared = SHARED / "pypi_pystrata-0.5.4" / "NIS090.AT2"
    return str(shared if shared.exists() else REPO / "tests" / "data" / "NIS090.AT2")


def benchmark_cases(duration: float = 20.0) -> list[PeerCase]:
    """The large cases: both rows, every peer law and no contact, El Centro 180 and Kobe NIS090."""
    out = []
    for row_name, row, gap in (("pair 3+5", PAIR, 0.01), ("row of four 10-storey", ROW4, 0.02)):
        for rec_name, rec in (("El Centro 180", "elcentro_180"), ("Kobe NIS090", kobe_nis090())):
            for law in PEER_LAWS:
                out.append(PeerCase(f"{row_name}, {rec_name}, {law or 'no contact'}", row, gap, law, rec, duration))
    return out
