"""Build a seispound model in OpenSeesPy, run it, and return comparable results.

One description: the seispound :class:`~seispound.model.spec.Model` (buildings,
gaps, contact law, Newmark settings) is assembled once with
:func:`seispound.structure.assemble`, and the OpenSees model is written from the
same flat arrays, element by element:

* one node per floor (1 DOF, ``model basic -ndm 1 -ndf 1``) with its lumped
  mass, one fixed ground node per building;
* each storey spring a ``zeroLength`` element with an ``Elastic`` material and
  ``-doRayleigh 1`` (without it zeroLength ignores beta_K: the response of a
  5 % damped building then comes out 11 % too large);
* Rayleigh damping per building: ``region -nodeOnly`` (floors) with
  alpha_M = a0 and ``region -eleOnly`` (storey springs) with beta_K = a1;
  the gap elements are in no region and keep zeroLength's default (no
  Rayleigh damping);
* each gap element a ``zeroLength`` from the left floor to the right floor
  (deformation u_right - u_left; contact when it falls below -size) with
  - LVe  -> ``ViscoelasticGap``  K = k, C = 2 xi sqrt(k m_eff)  (seed Eqs. 1-3),
  - NIVe -> ``JankowskiImpact``  Kh = k, xi = xi-bar(e), m_eff, n = 1.5 (seed Eq. 6),
  - MLVe -> ``JankowskiImpact``  Kh = k, xi = xi(e) of seed Eq. 5, m_eff, n = 1
    (its approach-only dashpot 2 xi sqrt(Kh m_eff) is the seed's MLVe, Eq. 4);
* ``UniformExcitation`` with a ``Path`` time series (linear between samples,
  as in seispound), ``Newmark`` gamma, beta, ``Newton`` with a displacement
  increment test, ``BandGeneral``.

OpenSees steps at a fixed dt and has no event location: an impact starts at
the first step whose trial deformation crosses the gap, so its onset and its
approach velocity converge with dt only.  Both programs allow LVe's tensile
force at the end of contact (``ViscoelasticGap`` keeps K delta + C rate while
the gap is closed; seispound's LVe default ``tension = true``).
"""

from __future__ import annotations

import ctypes
import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from seispound.contact import _scalar as S
from seispound.structure import assemble

# law name -> (OpenSees material, displacement exponent)
PEER_LAWS = {"LVe": ("ViscoelasticGap", 1.0), "NIVe": ("JankowskiImpact", 1.5), "MLVe": ("JankowskiImpact", 1.0)}


def import_opensees():
    """``openseespy.opensees``, with the wheel's bundled BLAS loaded first.

    The Linux wheel ships libblas.so.3 next to liblapack.so.3 but liblapack has
    no run path to find it; loading it globally beforehand resolves the symbol
    (no LD_LIBRARY_PATH, no files changed).
    """
    try:
        import openseespylinux  # noqa: F401  (raises if the extension fails to load)
    except RuntimeError:
        import importlib.util

        spec = importlib.util.find_spec("openseespylinux")
        if spec is None or not spec.submodule_search_locations:
            raise
        lib = Path(list(spec.submodule_search_locations)[0]) / "lib"
        for name in ("libquadmath.so.0", "libgfortran.so.4", "libblas.so.3", "liblapack.so.3"):
            if (lib / name).exists():
                ctypes.CDLL(str(lib / name), mode=ctypes.RTLD_GLOBAL)
        import sys

        sys.modules.pop("openseespylinux", None)
    except ImportError:
        pass
    import openseespy.opensees as ops

    return ops


@dataclass
class PeerResult:
    """Results of one program on one case (SI units)."""

    time: np.ndarray  # (nt,) s
    displacement: np.ndarray  # (nt, n) m, relative to the ground, DOF order of seispound's assembly
    force: np.ndarray  # (nt, ng) N, compression positive
    peak_displacement: np.ndarray  # (n,) m
    peak_force: np.ndarray  # (ng,) N
    impacts: np.ndarray  # (ng,) int: contacts that started (open -> closed transitions)
    seconds: float  # wall time of the analysis (model building excluded)
    unconverged_steps: int = 0  # OpenSees steps accepted after max_iter (see run_opensees)


def count_impacts(force: np.ndarray) -> np.ndarray:
    """Impacts per gap from a force history: open -> closed transitions of F != 0."""
    closed = force != 0.0
    starts = closed[1:] & ~closed[:-1]
    return starts.sum(axis=0) + closed[0]


def _read_binary(path, ncol, nrow):
    """Rows of an OpenSees ``-binary`` recorder: ncol float64 values and a newline byte each."""
    rows = np.fromfile(path, dtype=np.dtype([("v", "<f8", (ncol,)), ("eol", "u1")]))
    if rows.size != nrow:
        raise RuntimeError(f"{path.name}: {rows.size} rows recorded, expected {nrow}")
    return np.ascontiguousarray(rows["v"])


def build_opensees(model, ag: np.ndarray, dt: float, nsteps: int, tol: float = 1e-9,
                   algorithm: str = "KrylovNewton", log: str = os.devnull, system=None):
    """Build ``model`` in OpenSeesPy under ground acceleration ag sampled at k dt (m/s^2), k = 0..nsteps, up to
    ``analysis("Transient")``, with no recorders; returns the ``openseespy.opensees`` module, ready for
    ``analyze(nsteps, dt)``.  ``log``: where OpenSees' messages go.  Node numbering: floor DOF i is node i + 1;
    storey springs are elements 1..n_el, gaps n_el + 1.. (see ``run_opensees``).  ``system``: the model's
    assembly, if already made (the flat arrays the OpenSees commands are written from).
    """
    ops = import_opensees()
    system = system or assemble(model.buildings, model.gaps, model.contact)
    for g in range(system.n_gap):
        name = system.links[g].law.name
        if name not in PEER_LAWS:
            raise ValueError(f"law {name} has no OpenSees counterpart (peer laws: {', '.join(PEER_LAWS)})")
        if system.gap_size[g] <= 0.0:
            raise ValueError("OpenSees' gap materials need a gap > 0")
    n, ng = system.n_dof, system.n_gap
    ops.wipe()
    ops.logFile(log, "-noEcho")  # (the gap materials print every impact)
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    floor_node = np.arange(n) + 1
    ground_node = {}
    for i in range(n):
        ops.node(int(floor_node[i]), 0.0)
        ops.mass(int(floor_node[i]), float(system.mass[i]))
    for b in range(len(model.buildings)):
        tag = n + 1 + b
        ground_node[b] = tag
        ops.node(tag, 0.0)
        ops.fix(tag, 1)
    mat = 0
    storey_eles = {b: [] for b in range(len(model.buildings))}
    for e in range(system.el_i.size):
        mat += 1
        ops.uniaxialMaterial("Elastic", mat, float(system.el_k[e]))
        i, j = int(system.el_i[e]), int(system.el_j[e])
        b = int(system.dof_building[i])
        below = ground_node[b] if j < 0 else int(floor_node[j])
        # zeroLength adds Rayleigh damping only when asked (-doRayleigh 1)
        ops.element("zeroLength", e + 1, below, int(floor_node[i]), "-mat", mat, "-dir", 1, "-doRayleigh", 1)
        storey_eles[b].append(e + 1)
    gap_ele0 = system.el_i.size + 1
    for g in range(ng):
        mat += 1
        name = system.links[g].law.name
        kind, expo = PEER_LAWS[name]
        par = system.gap_par[g]
        k, xi, meff, size = float(par[S.P_K]), float(par[S.P_XI]), float(par[S.P_MEFF]), float(system.gap_size[g])
        if kind == "ViscoelasticGap":
            ops.uniaxialMaterial("ViscoelasticGap", mat, k, 2.0 * xi * np.sqrt(k * meff), -size)
        else:
            ops.uniaxialMaterial("JankowskiImpact", mat, k, xi, meff, -size, expo)
        ops.element("zeroLength", gap_ele0 + g, int(floor_node[system.gap_i[g]]), int(floor_node[system.gap_j[g]]),
                    "-mat", mat, "-dir", 1)
    reg = 0
    for b, bld in enumerate(model.buildings):
        a0, a1 = bld.rayleigh_coefficients()
        nodes = [int(x) for x in floor_node[system.dof_building == b]]
        reg += 1
        ops.region(reg, "-nodeOnly", *nodes, "-rayleigh", float(a0), 0.0, 0.0, 0.0)
        reg += 1
        ops.region(reg, "-eleOnly", *storey_eles[b], "-rayleigh", 0.0, float(a1), 0.0, 0.0)
    ops.timeSeries("Path", 1, "-dt", float(dt), "-values", *[float(x) for x in ag[: nsteps + 1]])
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    nm = model.analysis.newmark
    ops.constraints("Plain")
    ops.numberer("Plain")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", tol, 50, 5)
    # the gap materials' tangent leaves out their dashpot (C gamma / (beta dt)),
    # so plain Newton is a fixed-point iteration that can diverge at small dt;
    # Krylov-accelerated Newton converges throughout
    ops.algorithm(algorithm)
    ops.integrator("Newmark", float(nm.gamma), float(nm.beta))
    ops.analysis("Transient")
    return ops


def run_opensees(model, ag: np.ndarray, dt: float, nsteps: int, tol: float = 1e-9,
                 algorithm: str = "KrylovNewton") -> PeerResult:
    """Run ``model`` in OpenSeesPy under ground acceleration ag sampled at k dt (m/s^2), k = 0..nsteps.

    Returns floor displacements and gap forces at every step (read back from
    binary recorders), their peaks, impact counts and the analysis wall time.
    ``tol`` [m] is the displacement-increment norm of the Newton test.  With no
    event location, a step that ends where a gap sits at delta ~ 0 can make the
    iteration cycle between open and closed (LVe's dashpot force jumps by C
    times the rate there), and no tolerance is met; such a step is accepted
    after 50 iterations (OpenSees ``test`` print flag 5) and counted in
    ``unconverged_steps``.
    """
    system = assemble(model.buildings, model.gaps, model.contact)
    n, ng = system.n_dof, system.n_gap
    floor_node = np.arange(n) + 1
    gap_ele0 = system.el_i.size + 1
    log = tempfile.NamedTemporaryFile(prefix="opensees", suffix=".log", delete=False)
    log.close()
    ops = build_opensees(model, ag, dt, nsteps, tol, algorithm, log=log.name, system=system)
    with tempfile.TemporaryDirectory() as tmp:
        fd, ff = Path(tmp) / "disp.bin", Path(tmp) / "force.bin"
        ops.recorder("Node", "-binary", str(fd), "-node", *[int(x) for x in floor_node], "-dof", 1, "disp")
        ops.recorder("Element", "-binary", str(ff), "-ele", *range(gap_ele0, gap_ele0 + ng), "force")
        t0 = time.perf_counter()
        ok = ops.analyze(int(nsteps), float(dt))
        seconds = time.perf_counter() - t0
        ops.wipe()  # closes the recorders
        text = Path(log.name).read_text(errors="replace")
        os.unlink(log.name)
        if ok != 0:
            tail = [ln for ln in text.splitlines() if "impact detected" not in ln][-3:]
            raise RuntimeError(f"OpenSees analysis failed (code {ok}): {' | '.join(tail)}")
        unconverged = text.count("failed to converge")
        disp = _read_binary(fd, n, nsteps)
        frc = _read_binary(ff, 2 * ng, nsteps) if ng else np.zeros((nsteps, 0))
    # zeroLength force output [on node 1, on node 2] = [-f, f] with f the material force,
    # negative in compression: compression positive is -f = minus the node-2 entry
    force = -frc[:, 1::2]
    time_ = np.arange(1, nsteps + 1) * dt
    disp = np.vstack([np.zeros((1, n)), disp])
    force = np.vstack([np.zeros((1, ng)), force])
    return PeerResult(time=np.concatenate([[0.0], time_]), displacement=disp, force=force,
                      peak_displacement=np.max(np.abs(disp), axis=0), peak_force=np.max(force, axis=0, initial=0.0),
                      impacts=count_impacts(force), seconds=seconds, unconverged_steps=unconverged)
