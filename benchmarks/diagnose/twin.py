"""An independent solver for the concealed-effect benchmark: rows of buildings with one effect each.

Written apart from the package (NumPy and SciPy only; nothing from ``seispound``): the equations
of motion as a first-order ODE, integrated by ``solve_ivp`` (LSODA, tight tolerances, steps of
at most 1 ms), contact onsets and separations as terminal events, Hd contact (seed Eqs. 7-8:
F = k d^1.5 + zeta d^1.5 d', zeta from Eq. 8 at each onset with e = e(v0)).

Effects (one per case):

* ``inelastic-storey``: storeys with Bouc-Wen hysteresis (Wen 1976, A = 1, beta = gamma = 0.5):
  F = alpha k d + (1 - alpha) k z, dz/dt = d' (1 - |z/dy|^n (beta sgn(d' z) + gamma)), a yield
  drift per storey;
* ``spatially-varying-input``: a building's ground acceleration delayed (wave passage); its ground
  displacement and velocity are ODE states, so gaps close on absolute positions;
* ``velocity-dependent-restitution``: e(v0) instead of a constant e;
* ``soil-structure-interaction``: a rigid foundation that sways and rocks on springs and dashpots,
  written in coordinates relative to the foundation (coupled mass matrix), unlike the package;
* ``distributed-mass``: every floor a chain of lumped nodes joined by axial springs, its storey
  springs shared by the nodes, contacts on the end nodes.

Outputs at the requested times: absolute floor accelerations (at the floor's middle node for a
chain) and roof displacements relative to the ground under each building.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.optimize import brentq


@dataclass
class Building:
    name: str
    masses: list
    stiffness: list
    height: float = 3.0  # every storey
    ratio: float = 0.05  # Rayleigh, modes 1 and 2 of the fixed-base building
    yield_drift: list | None = None  # Bouc-Wen storeys (alpha 0.05, n 2)
    delay: float = 0.0  # s, its ground motion's delay
    foundation: dict | None = None  # kx, cx, kt, ct, m0, I0
    chain: dict | None = None  # nodes, axial stiffness per link [N/m], axial damping [N s/m]

    @property
    def n(self):
        return len(self.masses)


@dataclass
class Row:
    buildings: list
    gaps: list  # (left building index, right building index, size [m]) at every common floor
    k_contact: float = 2.75e9
    restitution: object = 0.65  # a number, or a function of the approach velocity v0 [m/s]
    alpha: float = 0.05
    bw_n: float = 2.0
    extra: dict = field(default_factory=dict)


def hunt_crossley_zeta(k, e, v0):
    """zeta [N s/m^2.5] from seed Eq. 8, (1 + e) = x ln|(x + 1)/(x - e)|, x = k / (zeta v0), on x > e."""
    if e >= 1.0:
        return 0.0
    f = lambda x: x * math.log((x + 1.0) / (x - e)) - (1.0 + e)
    x = brentq(f, e * (1 + 1e-12) + 1e-300, 1e6)
    return k / (x * v0)


def _rayleigh(b):
    n = b.n
    m = np.asarray(b.masses, float)
    k = np.asarray(b.stiffness, float)
    K = np.zeros((n, n))
    for s in range(n):
        K[s, s] += k[s]
        if s > 0:
            K[s - 1, s - 1] += k[s]
            K[s - 1, s] -= k[s]
            K[s, s - 1] -= k[s]
    w = np.sqrt(eigh(K, np.diag(m), eigvals_only=True))
    wi, wj = w[0], w[min(1, n - 1)]
    return 2 * b.ratio * wi * wj / (wi + wj), 2 * b.ratio / (wi + wj), K


class _Layout:
    """DOFs, matrices and output maps of a row (module docstring)."""

    def __init__(self, row):
        self.row = row
        blocks, nodes_of, roof_of, gap_dofs = [], [], [], []
        n = 0
        for bi, b in enumerate(row.buildings):
            start = n
            nodes = b.chain["nodes"] if b.chain else 1
            floor_nodes = [[start + f * nodes + p for p in range(nodes)] for f in range(b.n)]
            n += b.n * nodes
            fnd = None
            if b.foundation:
                fnd = (n, n + 1)  # u0, theta
                n += 2
            blocks.append((start, n, floor_nodes, fnd))
        self.n = n
        M, C, K = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
        R = np.zeros((n, len(row.buildings)))  # inertial load per unit ground acceleration of each building
        # T maps DOFs to each node's total displacement relative to its building's ground
        T = np.eye(n)
        self.hyst = []  # (building, storey, dof above (list of (dof, share)), dof below, k, dy)
        for bi, (b, (start, stop, floor_nodes, fnd)) in enumerate(zip(row.buildings, blocks)):
            a0, a1, _ = _rayleigh(b)
            nodes = len(floor_nodes[0])
            share = np.full(nodes, 1.0 / max(nodes - 1, 1)) if nodes > 1 else np.ones(1)
            if nodes > 1:
                share[[0, -1]] *= 0.5
            z = b.height * np.arange(1, b.n + 1)
            for f in range(b.n):
                for p, dof in enumerate(floor_nodes[f]):
                    m = b.masses[f] * share[p]
                    M[dof, dof] += m
                    C[dof, dof] += a0 * m
                    R[dof, bi] += m
                    if fnd:  # relative to the foundation: total = x + u0 + z theta
                        T[dof, fnd[0]] += 1.0
                        T[dof, fnd[1]] += z[f]
                    below = floor_nodes[f - 1][p] if f > 0 else None
                    ks = b.stiffness[f] * share[p]
                    if b.yield_drift is not None:
                        self.hyst.append((dof, below, ks, float(b.yield_drift[f])))
                        _spring(C, dof, below, a1 * ks)
                    else:
                        _spring(K, dof, below, ks)
                        _spring(C, dof, below, a1 * ks)
                for p in range(nodes - 1):
                    _spring(K, floor_nodes[f][p + 1], floor_nodes[f][p], b.chain["axial_stiffness"])
                    _spring(C, floor_nodes[f][p + 1], floor_nodes[f][p], b.chain["axial_damping"])
            if fnd:
                fd = b.foundation
                K[fnd[0], fnd[0]] += fd["kx"]
                C[fnd[0], fnd[0]] += fd["cx"]
                K[fnd[1], fnd[1]] += fd["kt"]
                C[fnd[1], fnd[1]] += fd["ct"]
                # the floors' inertia in the foundation's coordinates (coupled), and the foundation's own
                rows_ = [d for fl in floor_nodes for d in fl]
                Mfull = np.zeros((n, n))
                for d in rows_:
                    r = T[d]
                    Mfull += M[d, d] * np.outer(r, r)
                for d in rows_:
                    R[:, bi] += M[d, d] * T[d]
                    R[d, bi] -= M[d, d]
                    M[d, d] = 0.0
                M += Mfull
                M[fnd[0], fnd[0]] += fd["m0"]
                M[fnd[1], fnd[1]] += fd["I0"]
                R[fnd[0], bi] += fd["m0"]
            roof_of.append(floor_nodes[-1][len(floor_nodes[-1]) // 2])
            nodes_of.append(floor_nodes)
        self.M, self.C, self.K, self.R, self.T = M, C, K, R, T
        self.Minv = np.linalg.inv(M)
        self.nodes_of = nodes_of
        for gi, (li, ri, size) in enumerate(row.gaps):
            bl, br = row.buildings[li], row.buildings[ri]
            for f in range(min(bl.n, br.n)):
                gap_dofs.append((li, nodes_of[li][f][-1], ri, nodes_of[ri][f][0], size, f))
        self.gap_dofs = gap_dofs


def _spring(A, i, j, k):
    A[i, i] += k
    if j is not None:
        A[j, j] += k
        A[i, j] -= k
        A[j, i] -= k


def simulate(row: Row, t_ag, ag, t_eval, max_step=1e-3, rtol=1e-8):
    """Integrate ``row`` under the ground acceleration (t_ag, ag) [s, m/s^2]; outputs at t_eval.

    Returns {"acc": {(building, floor): absolute acceleration}, "roof": {building: roof displacement
    relative to its ground}, "impacts": number of impacts}.
    """
    L = _Layout(row)
    n, nb, nh = L.n, len(row.buildings), len(L.hyst)
    delays = np.array([b.delay for b in row.buildings])
    ng = len(L.gap_dofs)
    closed = np.zeros(ng, bool)
    zeta = np.zeros(ng)
    impacts = [0]

    def ground(t):
        return np.interp(t - delays, t_ag, ag, left=0.0)

    def gap_state(g, y):
        li, i, ri, j, size, _ = L.gap_dofs[g]
        u, v = L.T @ y[:n], L.T @ y[n:2 * n]
        ug, vg = y[2 * n + nh:2 * n + nh + nb], y[2 * n + nh + nb:2 * n + nh + 2 * nb]
        return (u[i] + ug[li] - u[j] - ug[ri] - size, v[i] + vg[li] - v[j] - vg[ri])

    def forces(t, y):
        u, v = y[:n], y[n:2 * n]
        zs = y[2 * n:2 * n + nh]
        f = -L.C @ v - L.K @ u
        dz = np.zeros(nh)
        for h, (i, j, k, dy) in enumerate(L.hyst):
            d = u[i] - (u[j] if j is not None else 0.0)
            dd = v[i] - (v[j] if j is not None else 0.0)
            fs = row.alpha * k * d + (1 - row.alpha) * k * zs[h]
            f[i] -= fs
            if j is not None:
                f[j] += fs
            x = abs(zs[h]) / dy
            dz[h] = dd * (1.0 - x ** row.bw_n * (0.5 * np.sign(dd * zs[h]) + 0.5))
        Tt = L.T.T
        for g in range(ng):
            if closed[g]:
                d, r = gap_state(g, y)
                F = max(row.k_contact * max(d, 0.0) ** 1.5 + zeta[g] * max(d, 0.0) ** 1.5 * r, 0.0)
                _li, i, _ri, j, _, _ = L.gap_dofs[g]
                f -= F * Tt[:, i]
                f += F * Tt[:, j]
        return f, dz

    def rhs(t, y):
        f, dz = forces(t, y)
        agb = ground(t)
        a = L.Minv @ (f - L.R @ agb)
        return np.concatenate([y[n:2 * n], a, dz, y[2 * n + nh + nb:], agb])

    N = 2 * n + nh + 2 * nb
    iu, iv, ig, ivg = slice(0, n), slice(n, 2 * n), slice(2 * n + nh, 2 * n + nh + nb), slice(2 * n + nh + nb, N)
    J0 = np.zeros((N, N))  # the constant part: kinematics, linear storeys, hysteretic springs' elastic share
    J0[iu, iv] = np.eye(n)
    J0[iv, iu] = -L.Minv @ L.K
    J0[iv, iv] = -L.Minv @ L.C
    J0[ig, ivg] = np.eye(nb)
    for h, (i, j, k, _dy) in enumerate(L.hyst):
        col = L.Minv[:, i] - (L.Minv[:, j] if j is not None else 0.0)  # acceleration per unit storey force
        J0[iv, i] -= row.alpha * k * col
        if j is not None:
            J0[iv, j] += row.alpha * k * col
        J0[iv, 2 * n + h] -= (1 - row.alpha) * k * col
    # d(gap closure)/d(u, ug) for each gap: the same row serves d(closure rate)/d(v, vg)
    grad = np.zeros((ng, n + nb))
    for g, (li, i, ri, j, _size, _f) in enumerate(L.gap_dofs):
        grad[g, :n] = L.T[i] - L.T[j]
        grad[g, n + li] += 1.0
        grad[g, n + ri] -= 1.0
    pos, vel = np.r_[0:n, 2 * n + nh:2 * n + nh + nb], np.r_[n:2 * n, 2 * n + nh + nb:N]

    def jac(t, y):
        """The exact Jacobian of ``rhs``: it only steers LSODA's Newton iterations (the error control
        does not use it), and saves the n finite-difference right-hand sides each Jacobian costs."""
        J = J0.copy()
        zs = y[2 * n:2 * n + nh]
        for h, (i, j, k, dy) in enumerate(L.hyst):
            dd = y[n + i] - (y[n + j] if j is not None else 0.0)
            x = abs(zs[h]) / dy
            w = 0.5 * np.sign(dd * zs[h]) + 0.5
            dzdd = 1.0 - x ** row.bw_n * w
            J[2 * n + h, n + i] = dzdd
            if j is not None:
                J[2 * n + h, n + j] = -dzdd
            if zs[h] != 0.0:
                J[2 * n + h, 2 * n + h] = -dd * w * row.bw_n * x ** (row.bw_n - 1) * np.sign(zs[h]) / dy
        for g in range(ng):
            if not closed[g]:
                continue
            d, r = gap_state(g, y)
            if d <= 0.0 or row.k_contact + zeta[g] * r <= 0.0:
                continue  # no force, or the force clipped at zero
            dF_dd = 1.5 * (row.k_contact + zeta[g] * r) * math.sqrt(d)
            dF_dr = zeta[g] * d ** 1.5
            _li, i, _ri, j, _, _ = L.gap_dofs[g]
            col = L.Minv @ (L.T[j] - L.T[i])  # acceleration per unit contact force
            J[n:2 * n, pos] += np.outer(col, dF_dd * grad[g])
            J[n:2 * n, vel] += np.outer(col, dF_dr * grad[g])
        return J

    def events():
        evs = []
        for g in range(ng):
            def ev(t, y, g=g):
                return gap_state(g, y)[0]
            ev.terminal, ev.direction = True, (-1.0 if closed[g] else 1.0)
            evs.append(ev)
        return evs

    y = np.zeros(2 * n + nh + 2 * nb)
    t, t_end = 0.0, float(t_eval[-1])
    out = np.full((len(t_eval), y.size), np.nan)
    state_at = [None] * len(t_eval)  # the contact state (closed, zeta) each output sample was computed in
    done = np.zeros(len(t_eval), bool)
    while t < t_end * (1 - 1e-12):
        sol = solve_ivp(rhs, (t, t_end), y, method="LSODA", rtol=rtol, atol=1e-12, max_step=max_step, jac=jac,
                        events=events() or None, dense_output=True)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        t1 = sol.t[-1]
        fired = []
        if sol.status == 1:
            fired = sorted((sol.t_events[g][0], g) for g in range(ng) if sol.t_events[g].size)
            t1 = fired[0][0]
        sel = (~done) & (t_eval >= t) & (t_eval <= t1)
        if sel.any():
            out[sel] = sol.sol(t_eval[sel]).T
            for k in np.flatnonzero(sel):
                state_at[k] = (closed.copy(), zeta.copy())
            done |= sel
        y = sol.sol(t1)
        t = t1
        for te, g in fired:
            if te - fired[0][0] > 1e-12:
                break
            if closed[g]:
                closed[g] = False
            else:
                d, r = gap_state(g, y)
                e = row.restitution(r) if callable(row.restitution) else row.restitution
                zeta[g] = hunt_crossley_zeta(row.k_contact, e, max(r, 1e-9))
                closed[g] = True
                impacts[0] += 1
    # outputs: absolute accelerations from the equations at each output time
    acc, roof = {}, {}
    A = np.empty((len(t_eval), n))
    for k, tk in enumerate(t_eval):
        closed[:], zeta[:] = state_at[k]
        A[k] = rhs(tk, out[k])[n:2 * n]
    U = out[:, :n] @ L.T.T
    Atot = A @ L.T.T
    for bi, b in enumerate(row.buildings):
        agb = np.array([ground(tk)[bi] for tk in t_eval])
        for f in range(b.n):
            nodes = L.nodes_of[bi][f]
            d = nodes[len(nodes) // 2]
            acc[(b.name, f + 1)] = Atot[:, d] + agb
        roof[b.name] = U[:, L.nodes_of[bi][-1][len(L.nodes_of[bi][-1]) // 2]]
    return {"acc": acc, "roof": roof, "impacts": impacts[0]}
