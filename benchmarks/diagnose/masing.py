"""Ramberg-Osgood storey hysteresis with Masing's rules for the held-out generator (``outside.py``).

Independent of the package (NumPy only).  A smooth law with no elastic range:

* **Backbone** (Ramberg & Osgood 1943, NACA TN 902; as a storey law, Jennings 1964, "Periodic response of
  a general yielding structure", Journal of the Engineering Mechanics Division, ASCE 90(EM2), 131-166):
  ``d = f / k0 (1 + a |f / Fy|^(r - 1))``, with the initial stiffness ``k0``, the yield drift ``dy`` (Fy =
  k0 dy; the drift at Fy is (1 + a) dy), ``a > 0`` and ``r > 1``; symmetric.
* **Branches** (Masing 1926): from a reversal point (d_r, f_r) the curve is the backbone scaled by 2,
  ``d - d_r = 2 D((f - f_r) / 2)`` with D the backbone above; it leaves the reversal at ``k0``.
* **Irregular loading: the extended Masing rules** as stated by Kwok, Stewart, Hashash, Matasovic,
  Pyke, Wang & Yang (2007), "Use of exact solutions of wave propagation problems to guide implementation
  of nonlinear seismic ground response analysis procedures", Journal of Geotechnical and
  Geoenvironmental Engineering 133(11), 1385-1398 (after Pyke 1979 and Vucetic 1990): (1) first loading
  follows the backbone; (2) a reversal starts a branch as above; (3) a branch that exceeds the largest
  past excursion meets the backbone there (the branch from a backbone point (d1, f1) reaches the backbone
  at (-d1, -f1), tangentially) and follows it; (4) a branch that reaches the reversal point it started
  from the opposite side of (its loop closes) continues on the curve that was being followed before that
  point: full memory, kept as a stack of reversal points (rule 3 is rule 4 with the backbone's mirror
  point as the bottom of the stack).

**Integration: the force as an ODE state, the reversal points by events.**  Along any curve of the law the
tangent is a function of the force alone, ``kt = k0 / (1 + a r |(f - f_o) / (n Fy)|^(r - 1))``
(f_o = 0, n = 1 on the backbone; f_o = f_r, n = 2 on a branch), so ``df/dt = kt v`` is smooth between
reversals and no inversion of the backbone is needed.  A reversal point must be held when the drift turns
(no continuous rate can sample and hold it), so ``Memory`` keeps each storey's stack of reversal points
and its direction of motion, and gives two event functions for ``solve_ivp``: the smallest of the storeys'
drift rates in their directions of motion (a zero: a reversal, push) and the smallest of their distances
to the points where their loops close (a zero: rule 4, pop two).  Both are terminal: the caller restarts
the integration after updating the memory (``on_event``), as ``outside.simulate`` does for contact.
At a reversal the rate kt v is continuous (v = 0), only its derivative jumps.
"""

from __future__ import annotations

import numpy as np

FAR = 1e3  # m: the distance to the loop's closing point of a storey on the backbone (no closing point)
# the event functions' floors: a storey at rest (its drift rate exactly zero, as the top storeys in the first steps)
# or resting on its closing point would hold an event function at zero, and an event would fire at every restart; a
# reversal is found when the drift rate has passed REST_RATE the other way (1e-12 m/s: the reversal point is
# then ~1e-24 m away), a loop's closing when the drift has passed the point by CLOSE_PAST
REST_RATE = 1e-12  # m/s
CLOSE_PAST = 1e-15  # m


def backbone_drift(f, k0, dy, a, r):
    """The backbone's drift at force ``f`` (explicit; the force at a drift needs a root)."""
    f = np.asarray(f, float)
    return f / k0 * (1.0 + a * np.abs(f / (k0 * dy)) ** (r - 1.0))


def backbone(d, k0, dy, a, r):
    """The backbone's force at drift ``d`` (scalar), by bracketed root finding on ``backbone_drift``."""
    from scipy.optimize import brentq

    if d == 0.0:
        return 0.0
    s = np.sign(d)
    hi = k0 * abs(d)  # the backbone lies under the elastic line
    return float(s * brentq(lambda x: backbone_drift(x, k0, dy, a, r) - abs(d), 0.0, hi, xtol=1e-15 * hi,
                            rtol=1e-15))


def tangent(f, f_o, n, k0, dy, a, r):
    """The tangent stiffness at force ``f`` on the curve from (., f_o) scaled by ``n`` (vectorised)."""
    x = np.abs((np.asarray(f, float) - f_o) / (n * k0 * dy))
    return k0 / (1.0 + a * r * x ** (r - 1.0))


class Memory:
    """The Masing memory of ``m`` storeys: each one's stack of reversal points (drift, force), its direction of
    motion (+1 / -1) and whether it has left the origin; the current curve (f_o, n) and the drift of the point
    where its loop closes, as arrays for the rates and events."""

    def __init__(self, k0, dy, a, r):
        self.k0, self.dy, self.a, self.r = (np.atleast_1d(np.asarray(x, float)).copy() for x in (k0, dy, a, r))
        m = self.k0.size
        self.stack = [[] for _ in range(m)]
        self.s = np.ones(m)
        self.virgin = np.ones(m, bool)  # on the first loading from the origin (its direction is the drift's sign)
        self.f_o = np.zeros(m)
        self.n = np.ones(m)
        self.d_close = np.full(m, np.nan)  # nan: on the backbone, no closing point
        self.reversals = 0

    def rates(self, v, f):
        """df/dt of every storey for drift rates ``v`` and forces ``f``."""
        return tangent(f, self.f_o, self.n, self.k0, self.dy, self.a, self.r) * np.asarray(v, float)

    def tangent(self, f):
        return tangent(f, self.f_o, self.n, self.k0, self.dy, self.a, self.r)

    def turning(self, d, v):
        """Each storey's drift rate in its direction of motion (a storey on its first loading: in the direction
        of its drift; 1 at the origin, where it has no direction yet)."""
        d, v = np.asarray(d, float), np.asarray(v, float)
        first = np.where(d == 0.0, 1.0, np.sign(d) * v)
        return np.where(self.virgin, first, self.s * v) + REST_RATE

    def closing(self, d):
        """Each storey's distance to the point where its loop closes, in its direction of motion."""
        g = self.s * (self.d_close - np.asarray(d, float)) + CLOSE_PAST
        return np.where(np.isnan(self.d_close), FAR, g)

    def events(self, drift, rate):
        """Two terminal event functions of (t, y) for solve_ivp, from ``drift(t, y)`` and ``rate(t, y)`` (the
        storeys' drifts and drift rates): a reversal and a loop's closing."""
        def reversal(t, y):
            return float(np.min(self.turning(drift(t, y), rate(t, y))))

        def closing(t, y):
            return float(np.min(self.closing(drift(t, y))))

        reversal.terminal = closing.terminal = True
        reversal.direction = closing.direction = -1.0
        return [reversal, closing]

    def _curve(self, i):
        st = self.stack[i]
        if not st:
            self.f_o[i], self.n[i], self.d_close[i] = 0.0, 1.0, np.nan
            return
        self.f_o[i], self.n[i] = st[-1][1], 2.0
        self.d_close[i] = st[-2][0] if len(st) >= 2 else -st[0][0]  # rule 4; rule 3: the mirror of the first

    def on_event(self, kind, d, v, f):
        """Update the memory after the event ``kind`` (0: a reversal, 1: a loop's closing) at the storeys'
        drifts ``d``, rates ``v`` and forces ``f``; returns the storeys updated."""
        d, v, f = (np.asarray(x, float) for x in (d, v, f))
        if kind == 0:
            g = self.turning(d, v)
            hit = set(np.flatnonzero(g <= 0.0)) | {int(np.argmin(g))}
            for i in sorted(hit):
                self.s[i] = -np.sign(d[i]) if self.virgin[i] else -self.s[i]
                self.virgin[i] = False
                self.stack[i].append((float(d[i]), float(f[i])))
                self._curve(i)
                self.reversals += 1
        else:
            g = self.closing(d)
            hit = set(np.flatnonzero(g <= 0.0)) | {int(np.argmin(g))}
            for i in sorted(hit):
                if np.isnan(self.d_close[i]):
                    continue
                st = self.stack[i]
                del st[-2:]  # both ends of the closed loop (one: the mirror of the first reached, on the backbone)
                self._curve(i)
        return sorted(hit)


def follow(t, d, v, k0, dy, a, r, rtol=1e-10, memory=False):
    """The force along a prescribed drift history (callables ``d(t)``, ``v(t)``) at the times ``t`` (with
    ``memory``: also the ``Memory`` at the end).

    Integrates ``df/dt = kt v`` with ``solve_ivp`` (RK45), restarting at every event of ``Memory`` as
    ``outside.simulate`` does; the check of the formulation against hand-derived paths in
    ``tests/diagnose/test_generator_outside.py``."""
    from scipy.integrate import solve_ivp

    mem = Memory(k0, dy, a, r)
    drift = lambda tt, yy=None: np.atleast_1d(d(tt))
    rate = lambda tt, yy=None: np.atleast_1d(v(tt))
    out = np.full(len(t), np.nan)
    t0, t_end, y = float(t[0]), float(t[-1]), np.zeros(1)
    max_step = (t_end - t0) / 2000.0
    while t0 < t_end - 1e-12 * max(1.0, t_end):
        sol = solve_ivp(lambda tt, yy: mem.rates(rate(tt), yy), (t0, t_end), y, method="RK45", rtol=rtol,
                        atol=[1e-10 * k0 * dy], max_step=max_step, events=mem.events(drift, rate),
                        dense_output=True)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        t1, kind = sol.t[-1], None
        if sol.status == 1:
            t1, kind = min((float(sol.t_events[k][0]), k) for k in (0, 1) if sol.t_events[k].size)
        sel = np.isnan(out) & (t >= t0) & (t <= t1)
        out[sel] = sol.sol(t[sel])[0]
        y = sol.sol(t1)
        if kind is not None:
            mem.on_event(kind, drift(t1), rate(t1), y)
        t0 = t1
    return (out, mem) if memory else out
