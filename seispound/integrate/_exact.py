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
squared Taylor series, accurate to round-off.  Where w h and c h are small (the
short steps around contact events), the same series is summed in two scalars
instead (Cayley-Hamilton: A^k = alpha_k I + beta_k A), at about a fifth of the cost.
"""

from __future__ import annotations

import math

import numpy as np
from seispound._jit import njit

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
    for j in range(w2.size):
        w = math.sqrt(w2[j])
        zeta = 0.5 * c[j] / w if w > 0.0 else 2.0
        if zeta < 0.9 and w * h >= CLOSED_FORM_WH:
            _closed_form(w, zeta, h, out, j)
        elif w * h <= SERIES_WH and c[j] * h <= SERIES_WH:
            _series(w2[j], c[j], h, out, j)
        else:  # over-damped with a long step
            _exponential(w2[j], c[j], h, out, j)


@njit(cache=True)
def _exponential(w2, c, h, out, j):
    """Column j of ``out`` from the exponential of the 4 x 4 matrix M h (:func:`exact_coefficients`)."""
    M = np.zeros((4, 4))
    E = np.empty((4, 4))
    X, term, tmp = np.empty((4, 4)), np.empty((4, 4)), np.empty((4, 4))  # the exponential's scratch
    M[0, 1] = h
    M[1, 0] = -w2 * h
    M[1, 1] = -c * h
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


# The two-scalar series serves steps with w h and c h at most this: its terms fall at least
# as x^k / (k+1)! with x = (w + c) h <= 0.4, so at most 16 of them reach 1e-18 of the first.
SERIES_WH = 0.2


@njit(cache=True)
def _series(w2, c, h, out, j):
    """Column j of ``out`` for a short step: exp(M h) of the exponential above, summed in scalars.

    With A = [[0, 1], [-w2, -c]] (Cayley-Hamilton, A^2 = -c A - w2 I), A^k = alpha_k I + beta_k A,
    alpha_(k+1) = -w2 beta_k, beta_(k+1) = alpha_k - c beta_k (alpha_0 = 1, beta_0 = 0), and
    A^k b = (beta_k, beta_(k+1)) for b = (0, 1).  The step's exact solution under a load linear in
    time, P0 + (P1 - P0) s / h (integrating (h - s)^k / k! against 1 and s / h), is then

        Phi   = sum h^k / k! (alpha_k I + beta_k A),
        Gamma1 = sum A^k b h^(k+1) / (k+2)!,   Gamma0 = sum A^k b h^(k+1) (k+1) / (k+2)!,

    each entry led by its first nonzero term, with the rest smaller by powers of (w + c) h, so no
    cancellation for small w h (where the closed form loses (w h)^-2 of its digits).  The same
    coefficients as :func:`_expm4` on the 4 x 4 matrix, to round-off
    (tests/integrate/test_exact_step.py).
    """
    al, be = 1.0, 0.0  # alpha_k, beta_k times h^k / k!  (so each stays near (w h)^k / k!)
    x = (math.sqrt(w2) + c) * h
    nxt = 1.0  # x^k / k!
    qq, qv, vq, vv = 0.0, 0.0, 0.0, 0.0
    g1q, g1v, g0q, g0v = 0.0, 0.0, 0.0, 0.0
    for k in range(40):
        # alpha_(k+1), beta_(k+1) times h^k / k! (one power of h short, restored below)
        al1 = -w2 * be
        be1 = al - c * be
        qq += al
        qv += be
        vq += al1
        vv += be1
        f1 = h / ((k + 1.0) * (k + 2.0))  # h^(k+1) / (k+2)! over h^k / k!
        g1q += be * f1
        g1v += be1 * f1
        g0q += be * f1 * (k + 1.0)
        g0v += be1 * f1 * (k + 1.0)
        # each sum's next term is below x^k / (k+1)! of its first nonzero one, x = (w + c) h
        if k >= 2 and nxt / (k + 1.0) <= 1e-18:
            break
        nxt *= x / (k + 1.0)
        al, be = al1 * h / (k + 1.0), be1 * h / (k + 1.0)
    out[F_QQ, j] = qq
    out[F_QV, j] = qv
    out[F_VQ, j] = vq
    out[F_VV, j] = vv
    out[G0_Q, j] = g0q
    out[G0_V, j] = g0v
    out[G1_Q, j] = g1q
    out[G1_V, j] = g1v


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
