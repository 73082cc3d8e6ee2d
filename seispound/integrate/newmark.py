"""Validating front end of the Newmark-beta kernel."""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field, replace

import numpy as np

from .. import _first_use
from ..errors import InputError
from .settings import Newmark
from ..motion.spatial import ground_motion_integrals
from . import _driver as D
from . import _outputs as O
from ..structure.band import bandwidth, envelope, profile_order
from ._multirate import WAIT_SHARE
from .modal import dof_blocks, modal_basis

# longest free-flight block [analysis steps]; blocks start at 16 after an impact
FREE_FLIGHT_BLOCK = 256

__all__ = ["Newmark", "RawResult", "integrate", "IntegrationError"]


class IntegrationError(RuntimeError):
    """The integration could not proceed (Newton did not converge, capacity exceeded)."""


@dataclass
class RawResult:
    """Kernel outputs (SI units). Shapes: nt = nsteps + 1, n DOFs, ng gaps, ni impacts."""

    time: np.ndarray  # (nt,) s
    displacement: np.ndarray  # (nt, n) m, relative to the ground
    velocity: np.ndarray  # (nt, n) m/s, relative
    acceleration: np.ndarray  # (nt, n) m/s^2, absolute
    force: np.ndarray  # (nt, ng) N
    energy: np.ndarray  # (nt, 6) J: input, kinetic, strain, damping, contact, hysteretic
    peak_displacement: np.ndarray  # (n,) m, over every substep
    peak_force: np.ndarray  # (ng,) N
    impacts: dict = field(default_factory=dict)  # arrays of length ni
    stats: dict = field(default_factory=dict)
    # hysteretic storeys (general driver): their element indices (nh,) and forces (nt, nh) [N]
    storey_elements: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    storey_force: np.ndarray | None = None
    storey_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))  # the DOF above each
    driver: str = "fast"
    # the scheme that ran between impacts: "exact" or "newmark" (the Newmark scheme asked; the general driver
    # without free flight; the fast driver without a modal basis)
    scheme: str = "exact"
    drift: np.ndarray | None = None  # (nt, n) m: set by results.floors.floor_view (storey deformations)


def gap_blocks(system, gap_i, gap_j) -> tuple[np.ndarray, np.ndarray]:
    """DOF range [gap_lo, gap_hi) of the blocks (buildings) each gap links, and any between them.

    A gap's Woodbury column K_hat^-1 b_g is nonzero only there, and gaps whose
    ranges do not overlap are uncoupled (the kernel's contact groups).
    Shapes: gap_i, gap_j (ng,) DOF indices; returns two (ng,) int64 arrays.
    """
    starts = dof_blocks(system.n_dof, system.el_i, system.el_j)
    blk_of = np.searchsorted(starts, np.arange(system.n_dof), side="right") - 1
    gap_lo = np.minimum(starts[blk_of[gap_i]], starts[blk_of[gap_j]]).astype(np.int64)
    gap_hi = np.maximum(starts[blk_of[gap_i] + 1], starts[blk_of[gap_j] + 1]).astype(np.int64)
    return gap_lo, gap_hi


def _element_blocks(system) -> tuple[np.ndarray | None, np.ndarray | None]:
    """First DOF and first element of each block (building), two (nb + 1,) int64 arrays.

    None, None when the elements of a block are not contiguous (the kernel
    needs each block's elements as one range to step it alone).
    """
    starts = dof_blocks(system.n_dof, system.el_i, system.el_j)
    blk = np.searchsorted(starts, system.el_i, side="right") - 1
    if np.any(np.diff(blk) < 0):
        return None, None
    el_start = np.searchsorted(blk, np.arange(starts.size), side="left").astype(np.int64)
    return starts.astype(np.int64), el_start


def gap_ground_motion(row_i, row_j, ag, dt):
    """Differential ground acceleration, velocity and displacement of each gap, shape (3, ng, nt).

    ``row_i``, ``row_j`` (ng,): the motion row under each gap's left and right
    floor.  When every gap has the same row on both sides, zeros of shape
    (3, ng, 1) (the kernel then skips the ground terms: ``moving`` False).
    """
    ng = row_i.size
    if np.array_equal(row_i, row_j):
        return np.zeros((3, ng, 1))
    vg, ug = ground_motion_integrals(ag, dt)
    return np.ascontiguousarray(np.stack([ag[row_i] - ag[row_j], vg[row_i] - vg[row_j], ug[row_i] - ug[row_j]]))


_BASES: dict = {}
_BLOCKS: dict = {}


def _memo(cache: dict, arrays, make):
    """make(), kept in ``cache`` under the bytes of ``arrays`` (at most 64 entries, oldest dropped)."""
    key = b"".join(np.ascontiguousarray(x).tobytes() for x in arrays)
    if key not in cache:
        if len(cache) >= 64:
            cache.pop(next(iter(cache)))
        cache[key] = make()
    return cache[key]


def _cached_blocks(system, gap_i, gap_j):
    """gap_blocks and _element_blocks of a row, reused across runs of the same row (a study, the twin).

    Both cost tens of microseconds in Python: 5 % of a twin's run on the canonical row.
    """
    return _memo(_BLOCKS, (np.array([system.n_dof]), system.el_i, system.el_j, gap_i, gap_j),
                 lambda: (*gap_blocks(system, gap_i, gap_j), *_element_blocks(system)))


def _cached_basis(system):
    """modal_basis(system), reused for systems with the same linear part (a run and its twin)."""
    return _memo(_BASES, (system.mass, system.dof_a0, system.el_i, system.el_j, system.el_k, system.el_a1),
                 lambda: modal_basis(system))


_EXACT: dict = {}


def _cached_exact(basis, dt):
    """Exact step coefficients (8, n) of every mode of ``basis`` for the step dt (``_exact.py``)."""
    return _memo(_EXACT, (basis.omega2, basis.c, np.array([dt])), lambda: _exact_coefficients(basis, dt))


def _exact_coefficients(basis, dt):
    from ._exact import exact_coefficients

    out = np.empty((8, basis.omega2.size))
    exact_coefficients(basis.omega2, basis.c, float(dt), out)
    return out


# rough compile time of each driver on a first use (``python -m benchmarks.startup``), said before it starts;
# the cold first runs vary with the machine's load
COMPILE_SECONDS = {"fast": "1-3 min", "general": "2-4 min"}


def _labelled(kernel, driver: str):
    """``kernel``, named for the notices of its first use (:mod:`seispound._first_use`: it says when it compiles,
    or runs as Python while it compiles in the background)."""
    _first_use.label(kernel, f"the {driver} integrator", COMPILE_SECONDS[driver])
    return kernel


def integrate(system, ground_acceleration, dt: float, nsteps: int, newmark: Newmark | None = None,
              impact_capacity: int | None = None, store_history: bool = True,
              free_flight: bool = True, multirate: bool = True, wait_share: float = WAIT_SHARE,
              scheme: str = "exact", driver: str = "auto", tangent: bool = True,
              substeps: int | None = None, contact_step: float = math.inf,
              elastic_predictor: bool = True, hysteretic_flight: bool = True) -> RawResult:
    """Integrate a row of buildings under one (or one per DOF group) ground motion.

    Parameters
    ----------
    system : SystemArrays
        From :func:`seispound.structure.assemble`.
    ground_acceleration : ndarray, shape (nt,) or (nm, nt)
        Ground acceleration [m/s^2] sampled at t = k dt, k = 0..nsteps; rows
        selected per DOF by ``system.dof_motion``.  Zeros for free vibration.
    dt : float
        Analysis (output) step [s].
    nsteps : int
        Number of analysis steps.
    newmark : Newmark, optional
    impact_capacity : int, optional
        Initial size of the impact catalogue (grown automatically).
    store_history : bool
        Keep the time histories (default).  False keeps only the peaks, the
        impact catalogue and the initial state (what the no-pounding twin needs).
    free_flight : bool
        March the steps in which every gap stays open in blocks, in modal
        coordinates (exact Newmark, see :mod:`seispound.integrate.modal`), when
        the buildings are linear and classically damped (default).  False
        steps physically throughout; both give the same result to round-off.
    multirate : bool
        While some gap is closed, let only the buildings linked to it (its
        contact group) take contact substeps; the others take the analysis
        step in one Newmark step and join at the substep in which one of their
        gaps may close (default).  False: every building takes every substep.
        The two differ by the time-discretisation error of the waiting
        buildings' steps, the same as in free flight.
    scheme : {"exact", "newmark"}
        "exact" (default): every step in which all gaps are open is exact for
        the piecewise-linear ground acceleration, mode by mode (Nigam &
        Jennings 1969; ``_exact.py``), wherever the free-flight blocks apply
        (linear, classically damped buildings of at most MAX_MODAL_BLOCK
        storeys); contacts and everything else take Newmark steps.
        "newmark": Newmark-beta throughout (as OpenSees does), to compare with
        other programs.
    wait_share : float
        Buildings wait only when together they hold at least this share of
        the row's DOFs (default ``WAIT_SHARE`` = 0.5: below it, the
        bookkeeping costs more than the substeps it saves); 0 lets any
        building wait.
    driver : {"auto", "fast", "general"}
        The one time loop (``_driver.drive``) runs over one of two linear
        parts.  "auto" (default): the two-node part, the fast driver
        (``_kernel.py``: lumped masses, linear two-node storeys,
        floor-to-floor gaps; modal free flight, multi-rate and the exact
        scheme where valid), or the coefficient-vector part, the general
        driver (``_general.py``: any element with state, coupled masses,
        elements on three DOFs, gaps against storeys; free flight by each
        building's map where valid) when the row needs it
        (``SystemArrays.needs_general_driver``).  "general" forces the
        general driver on any row: the off switch the tests compare against.
    substeps : int, optional
        General driver: no step longer than dt / substeps (a power of two;
        ``simulation.newmark_substeps`` decides it from the model).
    contact_step : float
        Longest contact substep [s] (default inf: 1 / ``contact_substeps`` of
        the impact duration alone); ``simulation.contact_step`` sets it from
        the row's fastest mode, which rod floors make kHz.
    elastic_predictor : bool
        General driver, every storey bilinear, peak-oriented, Iwan or flag: each physical step first tries the storeys
        at their elastic stiffness inside the linear part, with Newton on the closed gaps alone, and keeps
        it when every storey ends the step on that line (default); False: the storeys always in the Newton
        iteration.  The two agree to the Newton tolerance ``rtol`` (amplified by pounding's
        sensitivity to where an impact lands), the off switch the tests compare against.
    hysteretic_flight : bool
        General driver, exact scheme, Bouc-Wen or peak-oriented storeys (with or without bilinear ones):
        while every gap is open an analysis step is one exact map with each such storey's offset force
        iterated within it (a peak-oriented storey whose tangent changes inside the step sends that step
        to the physical path) (``_general_flight._hysteretic_flight``; default).  False: those rows take their
        physical path (Newmark substeps) throughout, the reference the tests compare against (the
        two differ by the physical path's time-discretisation error).
    tangent : bool
        General driver: the Newton iteration of a group that holds storeys
        with history runs on the banded tangent stiffness (default;
        ``_general_solve._newton_tangent``).  False: on the dense condensed system
        of the group's forces, the off switch the tests compare against (the
        two agree to the Newton tolerance ``rtol``).

    Returns
    -------
    RawResult
    """
    nm = newmark or Newmark()
    nm.validate()
    if driver not in ("auto", "fast", "general"):
        raise ValueError(f'driver must be "auto", "fast" or "general", got {driver!r}')
    if driver == "fast" and system.needs_general_driver:
        raise ValueError("this row needs the general driver (storeys with history, coupled masses, "
                         "three-DOF elements or gaps against storeys)")
    if driver == "general" or (driver == "auto" and general_driver_needed(system, scheme)):
        _check_scheme(scheme)
        return _integrate_general(system, ground_acceleration, dt, nsteps, nm, impact_capacity, store_history,
                                  tangent, substeps, contact_step, free_flight, scheme, elastic_predictor,
                                  hysteretic_flight)
    _check_scheme(scheme)
    if not 0.0 <= wait_share <= 1.0:
        raise ValueError(f"wait_share must lie in [0, 1], got {wait_share!r}")
    ag = np.atleast_2d(np.asarray(ground_acceleration, dtype=float))
    system = system.kernel_arrays()  # extra dashpots folded into a0 m and a1 k
    if ag.shape[1] == nsteps + 1 and system.dof_influence is not None:
        ag, dof_motion = system.motion_rows(ag)
        system = replace(system, dof_motion=dof_motion, dof_influence=None)
    _check_input(system, ag, dt, nsteps)
    n, ng_all = system.n_dof, system.n_gap
    # gaps whose law is NONE (the no-pounding twin) are left out of the kernel
    live = np.flatnonzero(system.gap_law != 0)
    gap_i, gap_j = system.gap_i[live], system.gap_j[live]
    gap_size, gap_law, gap_par = system.gap_size[live], system.gap_law[live], system.gap_par[live]
    ng = live.size
    gap_lo, gap_hi, blk_dof, blk_el = _cached_blocks(system, gap_i, gap_j)
    if blk_dof is None or not multirate:  # one block: every building steps together
        blk_dof = np.array([0, n], np.int64)
        blk_el = np.array([0, system.el_i.size], np.int64)
    # room for every impact up front: a catalogue overflow reruns the whole integration
    cap = impact_capacity or max(256, nsteps // 4 + 16 * ng)
    ground = gap_ground_motion(system.dof_motion[gap_i], system.dof_motion[gap_j], ag, dt)
    moving = ground.shape[2] > 1
    nt = nsteps + 1 if store_history else 1
    basis = _cached_basis(system) if free_flight or scheme == "exact" else None
    exact = scheme == "exact" and basis is not None  # else Newmark between impacts, and the result says so
    ex_co = _cached_exact(basis, dt) if exact else np.zeros((8, 0))
    if basis is not None:
        md = (bool(free_flight), basis.start, basis.blocks_t, basis.block_offset, basis.phi_t, basis.phi_tm,
              basis.omega2, basis.c, basis.participation(system.mass, system.dof_motion, ag.shape[0]),
              FREE_FLIGHT_BLOCK)
    else:
        e2 = np.zeros((0, 0))
        e1 = np.zeros(1, np.int64)
        md = (False, e1, np.zeros(0), e1, e2, e2, np.zeros(0), np.zeros(0), e2, 1)
    def run(cap):
        # one buffer for every history: numpy backs allocations >= 4 MiB with
        # transparent huge pages, which saves ~1e3 page faults per run
        hist = np.empty(nt * (3 * n + ng + 6))
        out = dict(
            out_u=hist[:nt * n].reshape(nt, n), out_v=hist[nt * n:2 * nt * n].reshape(nt, n),
            out_a=hist[2 * nt * n:3 * nt * n].reshape(nt, n),
            out_f=hist[3 * nt * n:nt * (3 * n + ng)].reshape(nt, ng), out_e=hist[nt * (3 * n + ng):].reshape(nt, 6),
            umax=np.empty(n), fmax=np.empty(ng), **_catalogue(cap))
        f = _writable
        return (*_labelled(D.integrate_kernel, "fast")(
            tuple(f(system.mass, system.dof_a0, system.dof_motion, system.el_i, system.el_j, system.el_k,
                    system.el_a1)), int(system.bandwidth), tuple(f(system.u0, system.v0)),
            tuple(f(gap_i, gap_j, gap_lo, gap_hi, gap_size, gap_law, gap_par)), (*f(ag), moving, *f(ground)),
            (float(dt), int(nsteps), float(nm.beta), float(nm.gamma), (_substeps(nm), float(contact_step)),
             float(nm.rtol), int(nm.max_iter), bool(store_history)),
            (md[0], *f(*md[1:-1]), md[-1], exact, *f(ex_co)), (bool(multirate), float(wait_share), *f(blk_dof, blk_el)),
            tuple(out[k] for k in _OUTPUTS), tuple(out[k] for k in _CATALOGUE), out["stats"]), out)

    n_imp, out = _run_growing(run, cap)
    out["out_e"][:, O.E_HYSTERETIC] = 0.0  # no storey with history on this path
    imp = {k[4:]: out[k][:n_imp].copy() for k in out if k.startswith("imp_")}
    imp["gap"] = live[imp["gap"]]  # back to the system's gap numbering
    if live.size == ng_all:  # every gap in the kernel: its force history as it stands
        force = out["out_f"]
    else:  # (a column scatter costs 0.35 ms on the canonical row: only when some gap is left out)
        force = np.zeros((nt, ng_all))
        force[:, live] = out["out_f"]
    peak_force = np.zeros(ng_all)
    peak_force[live] = out["fmax"]
    st = out["stats"]
    stats = dict(steps=int(st[O.S_STEPS]), iterations=int(st[O.S_ITERATIONS]),
                 rejected=int(st[O.S_REJECTED]), factorizations=int(st[O.S_FACTORIZATIONS]),
                 max_iterations=int(st[O.S_MAX_ITER]), free_flight_steps=int(st[O.S_FREE_FLIGHT]),
                 free_flight_blocks=int(st[O.S_BLOCKS]), waiting_steps=int(st[O.S_WAITING]),
                 joins=int(st[O.S_JOINS]), dof_steps=int(st[O.S_DOF_STEPS]), interpreted=out["interpreted"])
    return RawResult(time=np.arange(nt) * dt, displacement=out["out_u"], velocity=out["out_v"],
                     acceleration=out["out_a"], force=force, energy=out["out_e"],
                     peak_displacement=out["umax"], peak_force=peak_force, impacts=imp, stats=stats,
                     scheme="exact" if exact else "newmark")


def general_driver_needed(system, scheme: str = "exact") -> bool:
    """Whether ``integrate(driver="auto")`` runs ``system`` (SystemArrays) on the general driver.

    Rows with physics the fast driver does not hold (``system.needs_general_driver``: storeys with
    history, coupled masses, three-DOF elements, gaps against storeys); and, for the exact scheme,
    rows whose linear part has no real modal basis (``modal.modal_basis`` is None: non-classical
    damping, such as a rod's bolted element on a damped joint, a singular building, or a building
    of more than ``modal.MAX_MODAL_BLOCK`` DOFs) while every building fits the general driver's
    state-transition maps (``transition.MAX_BLOCK_DOFS``).  The fast driver would step those rows
    by Newmark between impacts, where its kHz modes lose their phase within a few steps (a rod
    slab's ringing after the impact, ``tests/verification/test_hung_slabs.py``); the general
    driver flies them free exactly.
    """
    if system.needs_general_driver:
        return True
    if scheme != "exact" or system.n_dof == 0:
        return False
    arrays = system.kernel_arrays()
    if _cached_basis(arrays) is not None:
        return False
    from .modal import dof_blocks
    from .transition import MAX_BLOCK_DOFS

    return int(np.max(np.diff(dof_blocks(arrays.n_dof, arrays.el_i, arrays.el_j)))) <= MAX_BLOCK_DOFS


def _writable(*arrays):
    """The kernel's inputs as writable C-contiguous arrays (a copy only of a read-only one).

    A compiled kernel is specialised on each argument's type, and numba's types tell read-only
    arrays from writable ones: the model's arrays are frozen, those made per run are not, and
    arrays computed inside the kernel are writable.  One flavour for every input keeps one
    specialisation of the kernel and of the functions it calls, which halves the compile on a
    fresh install (``python -m benchmarks.startup``).
    """
    return [np.require(a, requirements=("C", "W")) for a in arrays]


def _check_scheme(scheme):
    if scheme not in ("exact", "newmark"):
        raise InputError(f'scheme must be "exact" or "newmark", got {scheme!r}', key="analysis.scheme")


# the fast driver's output and catalogue arrays, in the order of its named tuples ``outs`` and ``cat``
_OUTPUTS = ("out_u", "out_v", "out_a", "out_f", "out_e", "umax", "fmax")
_CATALOGUE = ("imp_gap", "imp_t0", "imp_v0", "imp_vout", "imp_fmax", "imp_dur", "imp_zeta", "imp_e")


def _catalogue(cap) -> dict:
    """Empty impact catalogue arrays of ``cap`` rows and the counters, as both drivers take them."""
    return dict(imp_gap=np.empty(cap, np.int64), imp_t0=np.empty(cap), imp_v0=np.empty(cap), imp_vout=np.empty(cap),
                imp_fmax=np.empty(cap), imp_dur=np.empty(cap), imp_zeta=np.empty(cap), imp_e=np.empty(cap),
                stats=np.zeros(O.N_STATS, np.int64))


def _substeps(nm) -> int:
    """The contact substeps of ``nm``; unset (a model's are chosen by ``simulation.run_row``): the default."""
    from .settings import DEFAULT_CONTACT_SUBSTEPS

    return DEFAULT_CONTACT_SUBSTEPS if nm.contact_substeps is None else int(nm.contact_substeps)


def _run_growing(run, cap):
    """run(cap) -> (status, n_impacts, t_reached, outputs), rerun with 4x the catalogue while it overflows;
    returns (n_impacts, outputs)."""
    calls = _first_use.interpreted_calls
    while True:
        status, n_imp, t_reached, out = run(cap)
        if status == O.IMPACT_CAPACITY:
            cap *= 4
            continue
        if status != O.OK:
            raise IntegrationError(f"Newton-Raphson did not converge at t = {t_reached:.6g} s "
                                   f"(try a smaller analysis.dt or more contact_substeps)")
        out["interpreted"] = _first_use.interpreted_calls > calls  # run as Python on a first use
        return n_imp, out


def _check_input(system, ag, dt, nsteps):
    """The checks both drivers need: samples on the step grid, finite, dt > 0, every motion row present."""
    if ag.shape[1] != nsteps + 1:
        raise ValueError(f"ground acceleration has {ag.shape[1]} samples, expected nsteps + 1 = {nsteps + 1}")
    if not np.all(np.isfinite(ag)):
        raise InputError("ground acceleration contains NaN or inf", key="ground_motion")
    if not (dt > 0 and math.isfinite(dt)):
        raise InputError(f"dt must be > 0, got {dt!r}", key="analysis.dt")
    if int(system.dof_motion.max(initial=0)) >= ag.shape[0]:
        raise ValueError("dof_motion refers to a missing ground-motion row")


def _element_ranges(tab, n):
    """DOF range [lo, hi) of the blocks (buildings) each element with state links, two (nn,) int64 arrays.

    Blocks are the connected components of the DOFs under the masses and linear elements
    (and the storeys with history); they are contiguous in the assembly's numbering.
    """
    from .transition import components

    root = components(tab, n)
    lo_of = np.full(n, n)
    hi_of = np.zeros(n, np.int64)
    np.minimum.at(lo_of, root, np.arange(n))
    np.maximum.at(hi_of, root, np.arange(n) + 1)
    nn = tab["ne_dof"].shape[0]
    ne_lo, ne_hi = np.zeros(nn, np.int64), np.zeros(nn, np.int64)
    for q in range(nn):
        used = [int(d) for d in tab["ne_dof"][q] if d >= 0]
        ne_lo[q] = min(lo_of[root[d]] for d in used)
        ne_hi[q] = max(hi_of[root[d]] for d in used)
    return ne_lo, ne_hi


def _integrate_general(system, ground_acceleration, dt, nsteps, nm, impact_capacity, store_history,
                       tangent=True, substeps=None, contact_step=math.inf, free_flight=True,
                       scheme="exact", elastic_predictor=True, hysteretic_flight=True) -> RawResult:
    """``integrate`` on the general driver (``_general.py``): every law through the material protocol, Newmark
    steps, and the analysis steps with no element active in free flight (``transition.py``) where valid."""
    from ._material import N_STATE

    ag = np.ascontiguousarray(np.atleast_2d(np.asarray(ground_acceleration, dtype=float)))
    _check_input(system, ag, dt, nsteps)
    row = _general_row(system)
    tab, order, dof_motion, u0, v0, side = row["tab"], row["order"], row["dof_motion"], row["u0"], row["v0"], row["side"]
    n, ne_gap, live, hyst = system.n_dof, tab["ne_gap"], row["live"], row["hyst"]
    nn, ng_all = ne_gap.size, system.n_gap
    ground = gap_ground_motion(side[0], side[1], ag, dt)
    moving = ground.shape[2] > 1
    cap = impact_capacity or max(256, nsteps // 4 + 16 * max(len(live), 1))
    nt = nsteps + 1 if store_history else 1
    p_tangent = row["p_tangent"]
    lev_free = int(round(math.log2(substeps))) if substeps else 0
    from ..storey.codes import BILINEAR, BOUC_WEN, FLAG, IWAN, PEAK_ORIENTED

    storeys = ~ne_gap
    codes = tab["ne_code"][storeys]
    # every storey bilinear, Iwan or flag (or none): piecewise linear, free flight while every storey is elastic
    windowed = (codes == IWAN) | (codes == FLAG)
    bilinear = bool(np.all((codes == BILINEAR) | windowed))
    # hysteretic storeys fly free with their terms iterated within the step, Bouc-Wen and peak-oriented
    # storeys always and bilinear ones while they yield (exact scheme only: the Newmark scheme's free flight
    # must equal its physical path to round-off, the off switch's comparison); Iwan and flag storeys while elastic
    with_history = (codes == BILINEAR) | (codes == BOUC_WEN) | (codes == PEAK_ORIENTED) | windowed
    hysteretic = bool(storeys.any() and np.all(with_history) and scheme == "exact" and hysteretic_flight)
    ff = (_free_flight_maps(lambda: _renumbered_matrices(system, order), dof_motion, tab, ag.shape[0], dt, nm,
                            scheme, 2 ** lev_free, hysteretic)
          if free_flight and (bilinear or hysteretic) else None)
    # storeys tried at their elastic stiffness first: the piecewise-linear laws (bilinear, peak-oriented, Iwan, flag)
    el_pred = bool(elastic_predictor and storeys.any()
                   and np.all((codes == BILINEAR) | (codes == PEAK_ORIENTED) | windowed))
    i0 = np.zeros(1, np.int64)
    ff_args = ((True, ff.start, ff.off_x, ff.off_g, ff.off_e, ff.phi, ff.g0, ff.g1, ff.egx, ff.egg, ff.st_elem,
                ff.st_start, ff.gc, ff.egc, ff.gq, ff.egq, hysteretic) if ff is not None
               else (False, i0, i0, i0, i0, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 0)),
                     np.zeros(0, np.int64), i0, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), False))

    def run(cap):
        out = dict(out_u=np.zeros((nt, n)), out_v=np.zeros((nt, n)), out_a=np.zeros((nt, n)),
                   out_f=np.zeros((nt, nn)), out_e=np.zeros((nt, 6)), umax=np.zeros(n), fmax=np.zeros(nn),
                   **_catalogue(cap))
        f = _writable
        return (*_labelled(D.general_kernel, "general")(
            tuple(row["linear"]), int(tab["p"]), row["numbering"], tuple(row["elements"]),
            np.zeros((nn, N_STATE)), (*f(ag), moving, *f(ground)), (u0, v0),
            (float(dt), int(nsteps), float(nm.beta), float(nm.gamma), (_substeps(nm), float(contact_step)),
             float(nm.rtol), int(nm.max_iter), bool(store_history)),
            (bool(tangent), int(p_tangent), lev_free, ff_args, el_pred), tuple(out[k] for k in _OUTPUTS),
            tuple(out[k] for k in _CATALOGUE), out["stats"]),
            out)

    n_imp, out = _run_growing(run, cap)
    if order is not None:  # the histories are written in the row's own DOF order (``out_col``), the peaks not
        out["umax"] = out["umax"][row["numbering"][1].argsort()]
    gap_cols = np.flatnonzero(ne_gap)
    force = np.zeros((nt, ng_all))
    force[:, live] = out["out_f"][:, gap_cols]
    peak_force = np.zeros(ng_all)
    peak_force[live] = out["fmax"][gap_cols]
    imp = {k[4:]: out[k][:n_imp].copy() for k in out if k.startswith("imp_")}
    gap_of_element = np.full(nn, -1)
    gap_of_element[gap_cols] = live
    imp["gap"] = gap_of_element[imp["gap"]]
    st = out["stats"]
    stats = dict(steps=int(st[O.S_STEPS]), iterations=int(st[O.S_ITERATIONS]),
                 rejected=int(st[O.S_REJECTED]), factorizations=int(st[O.S_FACTORIZATIONS]),
                 max_iterations=int(st[O.S_MAX_ITER]), free_flight_steps=int(st[O.S_FREE_FLIGHT]), free_flight_blocks=0,
                 waiting_steps=0, joins=0, dof_steps=int(st[O.S_DOF_STEPS]), interpreted=out["interpreted"])
    return RawResult(time=np.arange(nt) * dt, displacement=out["out_u"], velocity=out["out_v"],
                     acceleration=out["out_a"], force=force, energy=out["out_e"],
                     peak_displacement=out["umax"], peak_force=peak_force, impacts=imp, stats=stats,
                     storey_elements=hyst, storey_force=out["out_f"][:, np.flatnonzero(~ne_gap)],
                     storey_dofs=system.el_i[hyst].astype(np.int64), driver="general",
                     scheme=scheme if ff is not None else "newmark")


def _general_row(system) -> dict:
    """What the general driver takes of ``system`` apart from the record and the settings, prepared once.

    The element tables without the disabled gaps (a no-pounding twin's), numbered for a small envelope
    (``_profile_numbered``), in the kernel's argument order (``linear``, ``elements``, ``numbering``),
    with each element's DOF range, the tangent's band, each gap's two motion rows (``side``) and the
    system's hysteretic elements and live gaps.  Kept on the system when its arrays are read-only
    (``Model.assembled``'s, shared by every run of a model: a run and its check, a study's runs), so that a
    repeated run pays none of this; a system built by hand is prepared anew each time, since it may be
    edited in place.
    """
    if getattr(system, "_general_row", None) is not None:
        return system._general_row
    tab = system.element_tables()
    keep = ~(tab["ne_gap"] & (tab["ne_code"] == 0))  # gaps disabled (the no-pounding twin) are left out
    for k in ("ne_dof", "ne_coef", "ne_size", "ne_code", "ne_par", "ne_gap"):
        tab[k] = np.ascontiguousarray(tab[k][keep])
    n = system.n_dof
    order, tab, dof_motion, u0, v0 = _profile_numbered(tab, n, system.dof_motion, system.u0, system.v0)
    ne_gap = tab["ne_gap"]
    side = np.zeros((2, ne_gap.size), np.int64)  # each gap's motion rows: its differential ground motion
    for q in np.flatnonzero(ne_gap):
        d, c = tab["ne_dof"][q], tab["ne_coef"][q]
        side[0, q] = dof_motion[d[(d >= 0) & (c > 0)][0]]
        side[1, q] = dof_motion[d[(d >= 0) & (c < 0)][0]]
    ne_lo, ne_hi = _element_ranges(tab, n)
    f = _writable
    out_col = np.arange(n, dtype=np.int64) if order is None else np.ascontiguousarray(order, np.int64)
    row = dict(tab=tab, order=order, dof_motion=dof_motion, u0=f(u0)[0], v0=f(v0)[0], side=side,
               ne_lo=ne_lo, ne_hi=ne_hi,
               p_tangent=max(int(tab["p"]), bandwidth(n, tab["ne_dof"][~ne_gap])),  # the band with the storeys
               hyst=np.flatnonzero(system.el_law) if system.el_law is not None else np.zeros(0, np.int64),
               live=np.flatnonzero(system.gap_law != 0),  # the system's gap of each gap element
               linear=f(*(tab[k] for k in ("ms_dof", "ms_coef", "ms_val", "ms_a0", "le_dof", "le_coef", "le_k",
                                          "le_c"))),
               numbering=(np.ascontiguousarray(tab["first"], np.int64), out_col),
               elements=f(tab["dof_load"], dof_motion, tab["dof_infl"], tab["ne_dof"], tab["ne_coef"],
                          tab["ne_size"], tab["ne_code"], tab["ne_par"], ne_gap, ne_lo, ne_hi))
    if not system.mass.flags.writeable:
        system._general_row = row
    return row


def _profile_numbered(tab, n, dof_motion, u0, v0):
    """The general driver's tables on DOFs numbered for a small envelope (``structure.band.profile_order``).

    Returns (order or None, tables with the envelope ``first`` and the band ``p`` of that numbering,
    dof_motion, u0, v0 renumbered); order[new] = old.  Each building keeps its block, so outputs come
    back by one column permutation.  A building on a foundation numbers its sway and rocking DOFs
    first, which couple to every floor: renumbered last, its factor costs the tridiagonal's and two
    full rows instead of a full band (``_linear._factor_profile``).
    """
    storeys = tab["ne_dof"][~tab["ne_gap"]]
    key = hashlib.blake2b(repr((n, storeys.shape)).encode())
    for x in (tab["ms_dof"], tab["le_dof"], storeys):
        key.update(np.ascontiguousarray(x).tobytes())
    key = key.digest()
    if key not in _ORDERS:  # kept per pattern: a fit's evaluations and a study's runs share it
        if len(_ORDERS) >= 64:
            _ORDERS.pop(next(iter(_ORDERS)))
        _ORDERS[key] = _profile_order(tab, n, storeys)
    order, new, p, first = _ORDERS[key]
    dof_motion = np.asarray(dof_motion, np.int64)
    u0, v0 = np.asarray(u0, float), np.asarray(v0, float)
    tab = dict(tab, first=first)
    if order is not None:
        for k in ("ms_dof", "le_dof", "ne_dof"):
            tab[k] = np.ascontiguousarray(np.where(tab[k] >= 0, new[np.maximum(tab[k], 0)], -1))
        tab["dof_load"], tab["dof_infl"] = tab["dof_load"][order], tab["dof_infl"][order]
        dof_motion, u0, v0 = dof_motion[order], u0[order], v0[order]
        tab["p"] = p
    return order, tab, np.ascontiguousarray(dof_motion), np.ascontiguousarray(u0), np.ascontiguousarray(v0)


def _profile_order(tab, n, storeys):
    """(order or None, its inverse, the band and the envelope in the new numbering) of ``_profile_numbered``."""
    from .transition import components

    order = profile_order(n, components(tab, n), tab["ms_dof"], tab["le_dof"], storeys)
    if order is None:
        return None, None, int(tab["p"]), envelope(n, tab["ms_dof"], tab["le_dof"], storeys)
    new = np.empty(n, np.int64)
    new[order] = np.arange(n)
    ren = [np.where(x >= 0, new[np.maximum(x, 0)], -1) for x in (tab["ms_dof"], tab["le_dof"], storeys)]
    return order, new, bandwidth(n, *ren[:2]), envelope(n, *ren)


_ORDERS: dict = {}  # digest of the tables' DOFs -> _profile_order's result, oldest first


def _renumbered_matrices(system, order):
    """The row's dense (M, C, K) (``SystemArrays.matrices``), renumbered by ``order`` (None: as they are)."""
    mats = system.matrices()
    return mats if order is None else tuple(np.asarray(x)[np.ix_(order, order)] for x in mats)


def _free_flight_maps(matrices, dof_motion, tab, nm_rows, dt, nm, scheme, substeps, quadratic=False):
    """The general driver's free-flight maps (``transition.Transition``), or None where they do not apply.

    The caller has checked that the elements with state are gaps and bilinear storeys (piecewise
    linear: free flight while every storey is elastic) or, with ``quadratic``, Bouc-Wen and peak-oriented storeys too
    (their offsets a quadratic load within the step: ``transition._exact_maps``).  They apply when every building is a
    contiguous run of at most ``transition.MAX_BLOCK_DOFS`` DOFs and, for the Newmark scheme, the rule
    is average acceleration (whose trapezoidal energy sums the free-flight balance reproduces).
    ``matrices``: a callable returning the row's dense (M, C, K) in the tables' numbering (called only
    when the maps are not kept already); ``dof_motion`` (n,) int64 in that numbering.
    """
    from .transition import transition

    if scheme == "newmark" and (nm.beta, nm.gamma) != (0.25, 0.5):
        return None
    # kept per content: a run's no-pounding twin, the tolerance's check and a study's runs share the row's
    # linear part, and the matrix exponentials cost about a millisecond per building
    h = hashlib.blake2b(repr((nm_rows, float(dt), scheme, nm.beta, nm.gamma, substeps, quadratic)).encode())
    for k in ("ms_dof", "ms_coef", "ms_val", "ms_a0", "le_dof", "le_coef", "le_k", "le_c", "dof_load"):
        h.update(np.ascontiguousarray(tab[k]).tobytes())
    for k in ("ne_dof", "ne_coef", "ne_par"):  # the storeys (not the gaps: a run and its twin share the maps)
        h.update(np.ascontiguousarray(tab[k][~tab["ne_gap"]]).tobytes())
    h.update(dof_motion.tobytes())
    key = h.digest()
    if key not in _TRANSITIONS:
        if len(_TRANSITIONS) >= 32:
            _TRANSITIONS.pop(next(iter(_TRANSITIONS)))
        _TRANSITIONS[key] = transition(tab, matrices(), dof_motion, nm_rows, dt, scheme, nm.beta,
                                       nm.gamma, substeps, quadratic)
    return _TRANSITIONS[key]


_TRANSITIONS: dict = {}  # content digest -> transition.Transition (or None), oldest first
