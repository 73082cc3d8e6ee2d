"""The held-out solver: rows of buildings with physics in forms the hypothesis library does not hold.

Written apart from the package and from ``twin.py`` (NumPy and SciPy only; nothing from
``seispound``), for ``suite.py`` (``python -m benchmarks.diagnose.generate OUT --suite outside``).

**Coordinates.**  Every DOF of a building is its displacement relative to the free field under
that building (total, foundation motion included), so the mass matrix is diagonal.  A building on
soil has a foundation sway ``u0`` and rocking ``theta``; its superstructure deforms by
``q = x - (u0 + z theta)`` (z: the DOF's height above the foundation), and its stiffness and
damping are those of the fixed-base structure written in q: ``K = B^T K_s B``, ``C = B^T C_s B``
(B: x -> q).  Internal soil DOFs (``soil.py``) are relative to the free field and take no inertial
load.  Every building has its own ground acceleration (``ag[b]``); its ground displacement and
velocity are ODE states, so gaps close on absolute positions.

**Superstructure.**  Storeys: linear springs, or hysteretic storeys with the force as an ODE state:
Takeda/Clough (``hysteresis.py``; ``Bldg.takeda``), flag-shaped self-centring (``flag.py``),
Ramberg-Osgood with Masing's rules (``masing.py``) or tension-only X-braced (``braced.py``; the last three
``Bldg.hysteresis``; a building's storeys all of one law).  Each hysteretic storey has three states (its force
and two of its law's: Takeda's largest excursions, the flag's slip); a Masing storey's reversal points are held
by terminal events (``masing.Memory``), as contact is.  A braced storey's two states are its braces' plastic
elongations, its force algebraic in its drift and them (its force state unused, held at zero).  Rayleigh damping
from the fixed-base lumped building's modes 1 and 2 (on the storeys' initial stiffness).  Floors: one node, or a
chain of ``nodes`` nodes with a mass profile (``chain["weights"]``, any shape), equal links of stiffness ``k_link`` and stiffness-proportional
link dashpots ``beta_link * k_link``; the storey spring below a floor is shared by its nodes in
proportion to their tributary lengths.  Attachments (bolted elements): a node of mass ``m`` on a
joint spring and dashpot at a floor's contact face, its mass taken from the floor's; contact acts on it.

**Contact.**  Hd (F = k d^1.5 + zeta d^1.5 d', clipped at zero), zeta from the approach velocity
v0 (at least ``V0_FLOOR`` = 1 mm/s) at each onset for e = e(v0), from (1 + e) = x ln((x + 1)/(x - e)), x = k / (zeta v0) (seed
Eq. 8), solved here by ``toms748``.  Onsets and separations are terminal events of ``solve_ivp``
(rtol 1e-8, steps of at most ``max_step``; LSODA on small elastic rows, RK45 on large or hysteretic
ones, see ``simulate``), as are a Masing storey's reversals and the closings of its loops.

Outputs at the requested times: floor sensors' absolute accelerations (mid-length of a chain, by
linear interpolation between nodes), roof displacements relative to the free field, each
foundation's absolute acceleration (the base sensor), the contact forces of the first gap.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.optimize import root_scalar

from . import braced, flag, hysteresis, masing

V0_FLOOR = 1e-3  # m/s: zeta of a grazing contact is set at this approach velocity (zeta grows as 1/v0)


@dataclass
class Bldg:
    name: str
    masses: list
    stiffness: list
    heights: list
    ratio: float = 0.05
    chain: dict | None = None  # {"nodes": p, "weights": p mass shares, "k_link": N/m, "beta_link": s}
    attachment: dict | None = None  # {"mass": kg, "k": N/m, "c": N s/m}, at every contact face
    takeda: dict | None = None  # {"dy": [per storey], "alpha", "beta", "pinch" (None)}
    # another storey law (instead of takeda): {"kind": "flag", "dy": [per storey], "alpha", "beta_f"} (flag.py),
    # {"kind": "masing", "dy": [per storey], "a", "r"} (masing.py) or {"kind": "braced", "dy": [per storey], "r_f",
    # "a_h"} (braced.py)
    hysteresis: dict | None = None
    soil: dict | None = None  # soil.py's model plus "m0", "I0"
    v0: float = 0.0  # initial velocity of every DOF of the building (impact tests)

    @property
    def n(self):
        return len(self.masses)


@dataclass
class Row:
    buildings: list
    gaps: list  # (left index, right index, size [m]); contact at every common floor
    k_contact: float = 2.75e9
    restitution: object = 0.65  # a number or a function of v0 [m/s]
    extra: dict = field(default_factory=dict)


def zeta_for(k, e, v0):
    """Hd damping coefficient for restitution e at approach velocity v0 (seed Eq. 8), by toms748."""
    if e >= 1.0:
        return 0.0
    g = lambda x: x * math.log1p((1.0 + e) / (x - e)) - (1.0 + e)
    lo, hi = e + 1e-12 * max(e, 1e-3), 10.0
    while g(hi) > 0.0:
        hi *= 10.0
    x = root_scalar(g, bracket=(lo, hi), method="toms748", xtol=1e-14, rtol=1e-13).root
    return k / (x * v0)


def fixed_base_rayleigh(masses, stiffness, ratio):
    """(a0, a1) of Rayleigh damping at ``ratio`` in modes 1 and 2 of the lumped fixed-base building."""
    n = len(masses)
    k = np.asarray(stiffness, float)
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    w = np.sqrt(eigh(K, np.diag(np.asarray(masses, float)), eigvals_only=True))
    w1, w2 = w[0], w[min(1, n - 1)]
    return 2 * ratio * w1 * w2 / (w1 + w2), 2 * ratio / (w1 + w2)


class Assembly:
    """The row's matrices, hysteretic storeys, contact pairs and output maps (module docstring)."""

    def __init__(self, row: Row):
        self.row = row
        nb = len(row.buildings)
        faces = [[False, False] for _ in range(nb)]  # a left / right neighbour
        for li, ri, _s in row.gaps:
            faces[li][1] = True
            faces[ri][0] = True
        masses, blocks = [], []
        n = 0

        def new(m):
            nonlocal n
            masses.append(float(m))
            n += 1
            return n - 1

        for bi, b in enumerate(row.buildings):
            blk = {"floors": [], "att": [], "z": [], "fnd": None, "cells": []}
            z = np.cumsum(b.heights)
            for f in range(b.n):
                # an attachment's mass is part of the floor's (the floor keeps the rest): with a rigid joint the
                # floor is the lumped one
                n_att = sum(1 for side in (0, 1) if b.attachment and faces[bi][side])
                mf = b.masses[f] - (n_att * b.attachment["mass"] if n_att else 0.0)
                if b.chain:
                    w = np.asarray(b.chain["weights"], float)
                    nodes = [new(mf * wi / w.sum()) for wi in w]
                else:
                    nodes = [new(mf)]
                blk["floors"].append(nodes)
                att = [None, None]
                for side in (0, 1):
                    if b.attachment and faces[bi][side]:
                        att[side] = new(b.attachment["mass"])
                blk["att"].append(att)
            if b.soil:
                blk["fnd"] = (new(b.soil["m0"]), new(b.soil["I0"] + b.soil.get("trapped_inertia", 0.0)))
                blk["cells"] = [new(m) for _g, _c, m in b.soil["cells"]]
            blk["zf"] = z
            blocks.append(blk)
        self.n = n
        self.mass = np.array(masses)
        K, C = np.zeros((n, n)), np.zeros((n, n))
        R = np.zeros((n, nb))
        self.hyst = []  # (building, storey): drift rows
        Dh = []
        hk0, hdy, halpha, hbeta, hpinch, hkind = [], [], [], [], [], []
        for bi, (b, blk) in enumerate(zip(row.buildings, blocks)):
            struct = [d for f in range(b.n) for d in blk["floors"][f] + [a for a in blk["att"][f] if a is not None]]
            zof = {}
            for f in range(b.n):
                for d in blk["floors"][f] + [a for a in blk["att"][f] if a is not None]:
                    zof[d] = blk["zf"][f]
            # B: x -> q for the structural DOFs (rows in the order of struct)
            B = np.zeros((len(struct), n))
            for r, d in enumerate(struct):
                B[r, d] = 1.0
                if blk["fnd"]:
                    B[r, blk["fnd"][0]] -= 1.0
                    B[r, blk["fnd"][1]] -= zof[d]
            loc = {d: r for r, d in enumerate(struct)}
            ns = len(struct)
            Ks, Cs = np.zeros((ns, ns)), np.zeros((ns, ns))
            a0, a1 = fixed_base_rayleigh(b.masses, b.stiffness, b.ratio)
            for d in struct:
                Cs[loc[d], loc[d]] += a0 * self.mass[d]
            for f in range(b.n):
                nodes = blk["floors"][f]
                p = len(nodes)
                share = np.ones(p) if p == 1 else np.r_[0.5, np.ones(p - 2), 0.5] / (p - 1)
                for i, d in enumerate(nodes):
                    below = blk["floors"][f - 1][i] if f > 0 else None
                    ks = b.stiffness[f] * share[i]
                    _pair(Cs, loc[d], None if below is None else loc[below], a1 * ks)
                    if b.takeda is None and b.hysteresis is None:
                        _pair(Ks, loc[d], None if below is None else loc[below], ks)
                    else:
                        row_ = np.zeros(ns)
                        row_[loc[d]] += 1.0
                        if below is not None:
                            row_[loc[below]] -= 1.0
                        Dh.append(row_ @ B)
                        self.hyst.append((bi, f))
                        hk0.append(ks)
                        law = b.takeda if b.takeda is not None else b.hysteresis
                        kind = "takeda" if b.takeda is not None else law["kind"]
                        hkind.append(kind)
                        hdy.append(law["dy"][f])
                        # (alpha, beta): Takeda's (alpha, beta); flag's (alpha, beta_f); Masing's (a, r); braced
                        # (r_f, a_h)
                        na, nb_ = {"takeda": ("alpha", "beta"), "flag": ("alpha", "beta_f"), "masing": ("a", "r"),
                                   "braced": ("r_f", "a_h")}[kind]
                        halpha.append(law[na])
                        hbeta.append(law[nb_])
                        hpinch.append((law.get("pinch") or 2.0) if kind == "takeda" else 2.0)  # 2: no pinching
                for i in range(p - 1):
                    _pair(Ks, loc[nodes[i + 1]], loc[nodes[i]], b.chain["k_link"])
                    _pair(Cs, loc[nodes[i + 1]], loc[nodes[i]], b.chain["beta_link"] * b.chain["k_link"])
                for side, end in ((0, nodes[0]), (1, nodes[-1])):
                    a = blk["att"][f][side]
                    if a is not None:
                        _pair(Ks, loc[a], loc[end], b.attachment["k"])
                        _pair(Cs, loc[a], loc[end], b.attachment["c"])
            K += B.T @ Ks @ B
            C += B.T @ Cs @ B
            for d in struct:
                R[d, bi] = self.mass[d]
            if blk["fnd"]:
                s = b.soil
                u0, th = blk["fnd"]
                idx = [u0, th]
                K[np.ix_(idx, idx)] += s["K"]
                C[np.ix_(idx, idx)] += s["C"]
                R[u0, bi] = self.mass[u0]
                for (g, c, _m), cd in zip(s["cells"], blk["cells"]):
                    v = np.zeros(n)
                    v[u0], v[th], v[cd] = g[0], g[1], -1.0
                    C += c * np.outer(v, v)
        self.K, self.C, self.R = K, C, R
        self.blocks = blocks
        self.Dh = np.array(Dh).reshape(len(Dh), n)
        self.hpar = tuple(np.array(x, float) for x in (hk0, hdy, halpha, hbeta))
        self.hpinch = np.array(hpinch, float) if self.hyst else None
        # each law's storeys (indices into the hysteretic storeys)
        self.hkind = np.array(hkind, dtype=object)
        self.groups = {k: np.flatnonzero(self.hkind == k) for k in ("takeda", "flag", "masing", "braced")}
        # contact pairs: (left building, its right face DOF, right building, its left face DOF, size, floor)
        self.pairs = []
        for li, ri, size in row.gaps:
            bl, br = row.buildings[li], row.buildings[ri]
            for f in range(min(bl.n, br.n)):
                i = blocks[li]["att"][f][1] if blocks[li]["att"][f][1] is not None else blocks[li]["floors"][f][-1]
                j = blocks[ri]["att"][f][0] if blocks[ri]["att"][f][0] is not None else blocks[ri]["floors"][f][0]
                self.pairs.append((li, i, ri, j, float(size), f))
        # floor sensors: mid-length of the floor's nodes
        self.sensor = {}
        for b, blk in zip(row.buildings, blocks):
            for f in range(b.n):
                nodes = blk["floors"][f]
                w = np.zeros(n)
                x = 0.5 * (len(nodes) - 1)
                lo = int(math.floor(x))
                hi = min(lo + 1, len(nodes) - 1)
                w[nodes[lo]] += 1.0 - (x - lo)
                w[nodes[hi]] += x - lo
                self.sensor[(b.name, f + 1)] = w


def _pair(A, i, j, k):
    A[i, i] += k
    if j is not None:
        A[j, j] += k
        A[i, j] -= k
        A[j, i] -= k


def simulate(row: Row, t_ag, ag, t_eval, max_step=1e-3, rtol=1e-8, forces=False, method="auto"):
    """Integrate ``row`` under ground accelerations ``ag`` [nb x len(t_ag)] (one row per building; a single
    row is used for all); outputs at ``t_eval``.

    Returns {"acc": {(building, floor): absolute acceleration}, "roof": {building: displacement relative
    to the free field}, "base": {building: foundation absolute acceleration}, "impacts": count,
    "force": contact force of the first pair (with ``forces``), "v_in"/"v_out": approach and
    separation velocities of each impact, "peak_drift": {building: largest storey drift}}."""
    A = Assembly(row)
    n, nb, nh = A.n, len(row.buildings), len(A.hyst)
    ag = np.atleast_2d(np.asarray(ag, float))
    if ag.shape[0] == 1:
        ag = np.repeat(ag, nb, axis=0)
    minv = 1.0 / A.mass
    pairs = A.pairs
    npair = len(pairs)
    closed = np.zeros(npair, bool)
    zeta = np.zeros(npair)
    log = {"impacts": 0, "v_in": [], "v_out": [], "t_in": []}
    k_c = row.k_contact
    # state layout
    sx, sv = slice(0, n), slice(n, 2 * n)
    sf, sp, sn = slice(2 * n, 2 * n + nh), slice(2 * n + nh, 2 * n + 2 * nh), slice(2 * n + 2 * nh, 2 * n + 3 * nh)
    o = 2 * n + 3 * nh
    sug, svg = slice(o, o + nb), slice(o + nb, o + 2 * nb)
    N = o + 2 * nb
    Dh = A.Dh
    k0, dy, alpha, beta = A.hpar
    # each law's storeys: Takeda's states (f, dpos, dneg); the flag's (f, p, unused); Masing's (f, unused, unused),
    # its reversal points held by events (masing.Memory); braced (unused, p1, p2): the braces' plastic elongations,
    # the force algebraic (storey_forces)
    it, ifl, ims, ibr = (A.groups[k] if nh else np.zeros(0, int) for k in ("takeda", "flag", "masing", "braced"))
    pinch = None
    if it.size and np.any(A.hpinch[it] < 1.0):
        pinch = A.hpinch[it]
    par_t = tuple(x[it] for x in (k0, dy, alpha, beta))
    par_f = tuple(x[ifl] for x in (k0, dy, alpha, beta))
    par_b = tuple(x[ibr] for x in (k0, dy, alpha, beta))
    Db = Dh[ibr] if ibr.size else None

    def storey_forces(x, y):
        """The hysteretic storeys' forces: the force states, a braced storey's from its drift and elongations."""
        fh = y[sf]
        if ibr.size:
            fh = fh.copy()
            fh[ibr] = braced.force(Db @ x, y[sp][ibr], y[sn][ibr], *par_b)
        return fh
    mem = masing.Memory(*(x[ims] for x in (k0, dy, alpha, beta))) if ims.size else None
    Dm = Dh[ims] if ims.size else None
    # closure gradient of each pair over (x, ug)
    G = np.zeros((npair, n))
    Gg = np.zeros((npair, nb))
    for p, (li, i, ri, j, _s, _f) in enumerate(pairs):
        G[p, i], G[p, j] = 1.0, -1.0
        Gg[p, li], Gg[p, ri] = 1.0, -1.0
    sizes = np.array([p[4] for p in pairs])

    def ground(t):
        return np.array([np.interp(t, t_ag, ag[b], left=0.0, right=0.0) for b in range(nb)])

    def closure(y):
        return G @ y[sx] + Gg @ y[sug] - sizes, G @ y[sv] + Gg @ y[svg]

    def contact_force(y):
        if not closed.any():
            return np.zeros(npair)
        d, r = closure(y)
        dp = np.maximum(d, 0.0) ** 1.5
        return np.where(closed, np.maximum(k_c * dp + zeta * dp * r, 0.0), 0.0)

    def rhs(t, y):
        x, v = y[sx], y[sv]
        fint = A.K @ x + A.C @ v
        dy_ = np.zeros(N)
        if nh:
            fh = storey_forces(x, y)
            fint = fint + Dh.T @ fh
            drift, rate = Dh @ x, Dh @ v
            df, dp_, dn_ = np.zeros(nh), np.zeros(nh), np.zeros(nh)
            if it.size:
                df[it], dp_[it], dn_[it] = hysteresis.rates(drift[it], rate[it], fh[it], y[sp][it], y[sn][it], *par_t,
                                                            pinch)
            if ifl.size:
                df[ifl], dp_[ifl] = flag.rates(rate[ifl], fh[ifl], y[sp][ifl], *par_f)
            if ims.size:
                df[ims] = mem.rates(rate[ims], fh[ims])
            if ibr.size:
                dp_[ibr], dn_[ibr] = braced.rates(drift[ibr], rate[ibr], y[sp][ibr], y[sn][ibr], *par_b)
            dy_[sf], dy_[sp], dy_[sn] = df, dp_, dn_
        F = contact_force(y)
        fext = -A.R @ ground(t) - G.T @ F
        dy_[sx] = v
        dy_[sv] = minv * (fext - fint)
        dy_[sug] = y[svg]
        dy_[svg] = ground(t)
        return dy_

    J0 = np.zeros((N, N))
    J0[sx, sv] = np.eye(n)
    J0[sv, sx] = -minv[:, None] * A.K
    J0[sv, sv] = -minv[:, None] * A.C
    J0[sug, svg] = np.eye(nb)
    if nh:
        J0[sv, sf] = -minv[:, None] * Dh.T

    def jac(t, y):
        J = J0.copy()
        if nh:
            kt, on_p, on_n, dd, dfv = (np.zeros(nh) for _ in range(5))
            drift, rate, fh = Dh @ y[sx], Dh @ y[sv], storey_forces(y[sx], y)
            if it.size:
                kt[it], on_p[it], on_n[it], dd[it], dfv[it] = hysteresis.tangent(
                    drift[it], rate[it], fh[it], y[sp][it], y[sn][it], *par_t, pinch, partials=True)
            if ifl.size:
                kt[ifl], flow = flag.tangent(rate[ifl], fh[ifl], y[sp][ifl], *par_f)
                on_p[ifl] = (1.0 - par_f[2]) * flow  # d(dp/dt)/d(rate)
            if ims.size:
                kt[ims] = mem.tangent(fh[ims])
                h = 1e-7 * k0[ims] * dy[ims]  # d(kt v)/df by a central difference
                dfv[ims] = rate[ims] * (mem.tangent(fh[ims] + h) - mem.tangent(fh[ims] - h)) / (2 * h)
            J[sf, sv] = kt[:, None] * Dh
            J[sf, sx] = dd[:, None] * Dh
            J[sf, sf] = np.diag(dfv)
            J[sp, sv] = on_p[:, None] * Dh
            J[sn, sv] = on_n[:, None] * Dh
            if ibr.size:  # the force is algebraic: its partials enter the velocities' rows (its force state's are zero)
                _kt, fl1, fl2, kd, kp1, kp2 = braced.tangent(drift[ibr], rate[ibr], y[sp][ibr], y[sn][ibr], *par_b,
                                                            partials=True)
                J[sv, 2 * n + ibr] = 0.0
                J[sv, sx] -= minv[:, None] * (Db.T @ (kd[:, None] * Db))
                J[sv, 2 * n + nh + ibr] = -minv[:, None] * (Db.T * kp1)
                J[sv, 2 * n + 2 * nh + ibr] = -minv[:, None] * (Db.T * kp2)
                one = 1.0 - par_b[3]
                J[2 * n + nh + ibr, sv] = (one * fl1)[:, None] * Db
                J[2 * n + 2 * nh + ibr, sv] = (-one * fl2)[:, None] * Db
        if closed.any():
            d, r = closure(y)
            for p in np.flatnonzero(closed & (d > 0.0)):
                if k_c + zeta[p] * r[p] <= 0.0:
                    continue
                dFd = 1.5 * (k_c + zeta[p] * r[p]) * math.sqrt(d[p])
                dFr = zeta[p] * d[p] ** 1.5
                col = -minv * G[p]
                J[sv, sx] += np.outer(col, dFd * G[p])
                J[sv, sug] += np.outer(col, dFd * Gg[p])
                J[sv, sv] += np.outer(col, dFr * G[p])
                J[sv, svg] += np.outer(col, dFr * Gg[p])
        return J

    def make_events():
        evs = []
        for p in range(npair):
            def ev(t, y, p=p):
                return float(G[p] @ y[sx] + Gg[p] @ y[sug] - sizes[p])
            ev.terminal = True
            ev.direction = -1.0 if closed[p] else 1.0
            evs.append(ev)
        if mem is not None:  # events npair (a Masing storey's reversal) and npair + 1 (a loop's closing)
            evs += mem.events(lambda t, y: Dm @ y[sx], lambda t, y: Dm @ y[sv])
        return evs

    # absolute tolerances: 1e-12 on displacements, velocities and the ground's states; 1e-7 Fy on storey forces
    # (at a force's zero crossing its rate kinks: 1e-12 N held LSODA at 1e-13 s steps)
    atol = np.full(N, 1e-12)
    if nh:
        atol[sf] = 1e-7 * k0 * dy
        atol[sp][ifl] = 1e-10 * dy[ifl]  # the flag's slip
        atol[sp][ibr] = atol[sn][ibr] = 1e-10 * dy[ibr]  # the braces' plastic elongations
    y = np.zeros(N)
    for bi, b in enumerate(row.buildings):
        if b.v0:
            blk = A.blocks[bi]
            for f in range(b.n):
                for d in blk["floors"][f] + [a for a in blk["att"][f] if a is not None]:
                    y[n + d] = b.v0
    if nh:
        y[sp][it], y[sn][it] = dy[it], -dy[it]
    # pairs touching at rest and approaching: closed from the start
    d0, r0 = closure(y)
    for p in range(npair):
        if abs(d0[p]) <= 1e-15 and r0[p] > 0.0:
            e = row.restitution(r0[p]) if callable(row.restitution) else row.restitution
            zeta[p], closed[p] = zeta_for(k_c, e, r0[p]), True
            log["impacts"] += 1
            log["v_in"].append(float(r0[p]))
            log["t_in"].append(0.0)
    # LSODA (with the analytic Jacobian) on small elastic systems; RK45 on large ones (chains of many nodes:
    # LSODA's dense internals cost ~9 ms a step, and the row is not stiff at steps of max_step; within 3e-6)
    # and on hysteretic ones (LSODA stalled at 1e-10 s steps at the kinks of a Takeda storey's force rate;
    # RK45 within 1e-5 of LSODA where both finish)
    meth = method if method != "auto" else ("LSODA" if N <= 160 and not nh else "RK45")
    t, t_end = float(t_eval[0]), float(t_eval[-1])
    stuck = 0  # restarts in a row without progress (events at the start time)
    out = np.full((len(t_eval), N), np.nan)
    states = [None] * len(t_eval)
    done = np.zeros(len(t_eval), bool)
    while t < t_end - 1e-12 * max(1.0, t_end):
        sol = solve_ivp(rhs, (t, t_end), y, method=meth, rtol=rtol, atol=atol, max_step=max_step,
                        **({"jac": jac} if meth == "LSODA" else {}),
                        events=make_events() or None, dense_output=True)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        t1 = sol.t[-1]
        fired = []
        if sol.status == 1:
            fired = sorted((float(sol.t_events[p][0]), p) for p in range(len(sol.t_events)) if sol.t_events[p].size)
            t1 = fired[0][0]
        sel = (~done) & (t_eval >= t) & (t_eval <= t1)
        if sel.any():
            out[sel] = sol.sol(t_eval[sel]).T
            for k in np.flatnonzero(sel):
                states[k] = (closed.copy(), zeta.copy())
            done |= sel
        y = sol.sol(t1)
        stuck = stuck + 1 if t1 <= t else 0
        if stuck > 100:
            raise RuntimeError(f"no progress at t = {t}: events at the start time")
        t = t1
        for te, p in fired:
            if te - fired[0][0] > 1e-12:
                break
            if p >= npair:  # a Masing storey turned, or its loop closed
                mem.on_event(p - npair, Dm @ y[sx], Dm @ y[sv], y[sf][ims])
                continue
            r = closure(y)[1][p]
            if closed[p]:
                closed[p] = False
                log["v_out"].append(float(r))
            else:
                e = row.restitution(r) if callable(row.restitution) else row.restitution
                zeta[p] = zeta_for(k_c, e, max(r, V0_FLOOR))
                closed[p] = True
                log["impacts"] += 1
                log["v_in"].append(float(r))
                log["t_in"].append(te)
    # outputs
    acc_all = np.empty((len(t_eval), n))
    fc = np.zeros(len(t_eval))
    for k, tk in enumerate(t_eval):
        closed[:], zeta[:] = states[k]
        acc_all[k] = rhs(tk, out[k])[sv]
        if forces and npair:
            fc[k] = contact_force(out[k])[0]
    gr = np.array([ground(tk) for tk in t_eval])
    res = {"acc": {}, "roof": {}, "base": {}, "impacts": log["impacts"], "v_in": log["v_in"], "v_out": log["v_out"],
           "t_in": log["t_in"], "peak_drift": {}}
    for bi, (b, blk) in enumerate(zip(row.buildings, A.blocks)):
        for f in range(b.n):
            w = A.sensor[(b.name, f + 1)]
            res["acc"][(b.name, f + 1)] = acc_all @ w + gr[:, bi]
        res["roof"][b.name] = out[:, :n] @ A.sensor[(b.name, b.n)]
        res["base"][b.name] = gr[:, bi] + (acc_all[:, blk["fnd"][0]] if blk["fnd"] else 0.0)
    if nh:
        drift = out[:, :n] @ Dh.T
        fo = out[:, sf].copy()  # every hysteretic storey's force (columns in Assembly.hyst order)
        if ibr.size:
            fo[:, ibr] = braced.force(drift[:, ibr], out[:, sp][:, ibr], out[:, sn][:, ibr], *par_b)
        res["storey_force"] = fo
        for bi, b in enumerate(row.buildings):
            cols = [h for h, (hb, _f) in enumerate(A.hyst) if hb == bi]
            if cols:
                res["peak_drift"][b.name] = float(np.abs(drift[:, cols]).max())
    if forces:
        res["force"] = fc
    if mem is not None:
        res["masing_reversals"] = mem.reversals
    return res


def linear_periods(row: Row, building: int, fixed_base=False):
    """The first-mode period [s] of one building, linearised (initial stiffness, open gaps).

    With its foundation and soil cells: from the complex eigenvalues of the damped state matrix
    (2 pi / Im of the lowest underdamped pair whose mass-weighted amplitude lies mostly on the
    floors: a soil cell's own low mode is not the building's); ``fixed_base``: the superstructure
    alone."""
    b = row.buildings[building]
    import copy

    bb = copy.deepcopy(b)
    bb.takeda = bb.hysteresis = None
    bb.v0 = 0.0
    if fixed_base:
        bb.soil = None
    A = Assembly(Row([bb], []))
    n = A.n
    S = np.zeros((2 * n, 2 * n))
    S[:n, n:] = np.eye(n)
    S[n:, :n] = -A.K / A.mass[:, None]
    S[n:, n:] = -A.C / A.mass[:, None]
    lam, vec = np.linalg.eig(S)
    # the building's mode, not a soil cell's: the floors (and attachments), created first, carry most of the
    # mode's mass-weighted amplitude (the soil model's own cells ring on their own at low frequency too)
    n_struct = n - (2 + len(bb.soil["cells"]) if bb.soil else 0)
    w = A.mass[:, None] * np.abs(vec[:n]) ** 2
    share = w[:n_struct].sum(axis=0) / np.maximum(w.sum(axis=0), 1e-300)
    ok = (np.abs(lam.imag) > 1e-6) & (share >= 0.5)
    return float(2 * math.pi / np.min(np.abs(lam.imag[ok])))


def first_axial_hz(b: Bldg, floor: int = 0):
    """The first free-free axial frequency [Hz] of a chain floor (with its attachments' masses lumped on the ends)."""
    if not b.chain:
        return None
    w = np.asarray(b.chain["weights"], float)
    m = b.masses[floor] * w / w.sum()
    p = len(m)
    K = np.zeros((p, p))
    for i in range(p - 1):
        K[i:i + 2, i:i + 2] += b.chain["k_link"] * np.array([[1.0, -1.0], [-1.0, 1.0]])
    ev = eigh(K, np.diag(m), eigvals_only=True)
    return float(math.sqrt(max(ev[1], 0.0)) / (2 * math.pi))
