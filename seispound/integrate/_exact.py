"""Exact step of a linear modal oscillator under a load linear in time (Nigam & Jennings 1969).

Each mode of a classically damped building obeys q'' + c q' + w2 q = P(t); with
P linear over a step of length h (the ground acceleration is linear between
samples), the state x = (q, q') at the step's end is exactly

    x1 = Phi x0 + G0 P0 + G1 P1,

Phi = exp(A h), A = [[0, 1], [-w2, -c]] (Nigam & Jennings 1969, BSSA 59(2):909-922;
Chopra, Dynamics of Structures, Sec. 5.2 and Table 5.2.1, which writes the
same coefficients in closed form for c < 2 sqrt(w2)).  Here Phi, G0, G1 come
from one exponential of the 4 x 4 matrix [[A, b, 0], [0, 0, 1], [0, 0, 0]]
acting on (x, P, dP/dt) (Van Loan 1978, IEEE TAC 23(3):395-404): valid for any
damping (over-damped high modes included) and free of the cancellation the
closed form suffers when w h is small.  The exponential is a scaled and
squared Taylor series, accurate to round-off.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# columns of the coefficient table (8, n): q1 = F_QQ q + F_QV v + G0_Q P0 + G1_Q P1, v1 likewise
F_QQ, F_QV, F_VQ, F_VV, G0_Q, G0_V, G1_Q, G1_V = 0, 1, 2, 3, 4, 5, 6, 7


@njit(cache=True)
def _expm4(M, out, X, term, tmp):
    """exp(M) of a 4 x 4 matrix into ``out``: scaling so that |M| / 2^s <= 1/2, Taylor series, squaring.

    The series stops at the first k >= 4 with |X|^(k-2) / k! <= 1e-18 (at most 18 terms): the
    smallest entries of exp(M) here start at the third power of X (E[0, 3] ~ h^3 / 6), so the
    first neglected term is below 1e-18 of them.  A located step's part of dt has |X| ~ w h << 1
    and needs 7-10 terms instead of 18.  X, term, tmp: 4 x 4 scratch.
    """
    norm = 0.0
    for i in range(4):
        row = 0.0
        for j in range(4):
            row += abs(M[i, j])
        norm = max(norm, row)
    s = 0
    if norm > 0.5:
        s = int(math.ceil(math.log2(norm / 0.5)))
    scale = 0.5**s
    for i in range(4):
        for j in range(4):
            X[i, j] = M[i, j] * scale
            out[i, j] = 1.0 if i == j else 0.0
            term[i, j] = out[i, j]
    xn = norm * scale
    bound = 1.0  # |X|^(k-2) / k!, updated as k grows
    for k in range(1, 19):
        for i in range(4):
            for j in range(4):
                acc = 0.0
                for q in range(4):
                    acc += term[i, q] * X[q, j]
                tmp[i, j] = acc / k
        for i in range(4):
            for j in range(4):
                term[i, j] = tmp[i, j]
                out[i, j] += term[i, j]
        bound = bound / k * (xn if k > 2 else 1.0)
        if k >= 4 and bound <= 1e-18:
            break
    for _ in range(s):
        for i in range(4):
            for j in range(4):
                acc = 0.0
                for q in range(4):
                    acc += out[i, q] * out[q, j]
                tmp[i, j] = acc
        for i in range(4):
            for j in range(4):
                out[i, j] = tmp[i, j]


@njit(cache=True)
def exact_coefficients(w2, c, h, out):
    """Step coefficients of every mode for a step h [s] into out (8, n) (columns F_QQ ... G1_V).

    w2 (n,) [1/s^2], c (n,) [1/s]: q'' + c q' + w2 q = P.  With dP = (P1 - P0) / h
    the augmented state (q, v, P, dP) evolves by exp(M h), M = [[0, 1, 0, 0],
    [-w2, -c, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0]]; so x1 = E[:2, :2] x0 +
    E[:2, 2] P0 + E[:2, 3] dP, i.e. G0 = E[:2, 2] - E[:2, 3] / h, G1 = E[:2, 3] / h.
    """
    M = np.zeros((4, 4))
    E = np.empty((4, 4))
    X, term, tmp = np.empty((4, 4)), np.empty((4, 4)), np.empty((4, 4))  # the exponential's scratch
    for j in range(w2.size):
        w = math.sqrt(w2[j])
        zeta = 0.5 * c[j] / w if w > 0.0 else 2.0
        if zeta < 0.9 and w * h >= CLOSED_FORM_WH:
            _closed_form(w, zeta, h, out, j)
            continue
        M[0, 1] = h
        M[1, 0] = -w2[j] * h
        M[1, 1] = -c[j] * h
        M[1, 2] = h
        M[2, 3] = h
        _expm4(M, E, X, term, tmp)
        out[F_QQ, j] = E[0, 0]
        out[F_QV, j] = E[0, 1]
        out[F_VQ, j] = E[1, 0]
        out[F_VV, j] = E[1, 1]
        out[G0_Q, j] = E[0, 2] - E[0, 3] / h
        out[G0_V, j] = E[1, 2] - E[1, 3] / h
        out[G1_Q, j] = E[0, 3] / h
        out[G1_V, j] = E[1, 3] / h


# Below this w h the closed form loses digits to cancellation (relative error ~ 1e-16 / (w h)^2);
# the exponential takes over (it costs about 20 times more).
CLOSED_FORM_WH = 0.1


@njit(cache=True)
def _closed_form(w, z, h, out, j):
    """Chopra's Table 5.2.1 (m = 1, k = w^2, under-damped) into column j of ``out``."""
    k = w * w
    sq = math.sqrt(1.0 - z * z)
    wd = w * sq
    ex = math.exp(-z * w * h)
    s = math.sin(wd * h)
    co = math.cos(wd * h)
    r = z / sq
    wh = w * h
    out[F_QQ, j] = ex * (r * s + co)
    out[F_QV, j] = ex * s / wd
    out[F_VQ, j] = -ex * w / sq * s
    out[F_VV, j] = ex * (co - r * s)
    out[G0_Q, j] = (2.0 * z / wh + ex * (((1.0 - 2.0 * z * z) / (wd * h) - r) * s - (1.0 + 2.0 * z / wh) * co)) / k
    out[G1_Q, j] = (1.0 - 2.0 * z / wh + ex * ((2.0 * z * z - 1.0) / (wd * h) * s + 2.0 * z / wh * co)) / k
    out[G0_V, j] = (-1.0 / h + ex * ((w / sq + z / (h * sq)) * s + co / h)) / k
    out[G1_V, j] = (1.0 - ex * (r * s + co)) / (k * h)


@njit(cache=True, inline="always")
def exact_step(co, j, q, v, p0, p1):
    """Mode j's (q, v) after one step with coefficients ``co`` (8, n) and loads p0, p1 at its ends."""
    q1 = co[F_QQ, j] * q + co[F_QV, j] * v + co[G0_Q, j] * p0 + co[G1_Q, j] * p1
    v1 = co[F_VQ, j] * q + co[F_VV, j] * v + co[G0_V, j] * p0 + co[G1_V, j] * p1
    return q1, v1
