"""Energy bookkeeping of free-flight blocks (relative frame; Uang & Bertero 1990).

input = kinetic + strain + damping + contact.  The physical path's steps add
their work in the corrector (``_newmark_step._accept_rows``) by the
trapezoidal rule, which balances exactly for Newmark's average acceleration;
free-flight blocks compute the same increments in modal form, by that rule
(Newmark blocks) or exactly (exact blocks).
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit


@njit(cache=True, fastmath=True)
def _block_energy(nb, Q, QV, DQ, P, f_start, md_w2, md_c, Eb):
    """Energy increments of a free-flight block, in modal form (Du . f = dq . f_q for mass-normalised modes).

    Eb[0, k]: input work of step k, 0.5 (p_k + p_k+1) . dq; Eb[1, k]: work of the storey
    and damping forces, 0.5 (f_k + f_k+1) . dq with f = omega^2 q + c q'; Eb[2, k], Eb[3, k]:
    kinetic and strain energy at its end.  (fastmath: the sums may be reassociated.)
    """
    n = md_w2.size
    for k in range(nb):
        de = 0.0
        dw = 0.0
        ek = 0.0
        es = 0.0
        for j in range(n):
            f1 = md_w2[j] * Q[k, j] + md_c[j] * QV[k, j]
            f0 = f_start[j] if k == 0 else md_w2[j] * Q[k - 1, j] + md_c[j] * QV[k - 1, j]
            de += 0.5 * (P[k, j] + P[k + 1, j]) * DQ[k, j]
            dw += 0.5 * (f0 + f1) * DQ[k, j]
            ek += 0.5 * QV[k, j] * QV[k, j]
            es += 0.5 * md_w2[j] * Q[k, j] * Q[k, j]
        Eb[0, k] = de
        Eb[1, k] = dw
        Eb[2, k] = ek
        Eb[3, k] = es


@njit(cache=True, fastmath=True)
def _block_energy_exact(nb, Q, QV, DQ, P, qv_start, md_w2, md_c, dt, Eb):
    """Energy increments of an exact free-flight block (rows of Eb as in :func:`_block_energy`).

    The input work of mode j over a step, W = int p q' dt with p linear, is
    p0 dq + (p1 - p0) / h (h q1 - I), I = int q dt; and I follows exactly from
    the mode's equation integrated over the step, dv + c dq + w2 I = h (p0 + p1) / 2.
    The trajectory being exact, the work of the storey and damping forces is
    then the input work less the change of kinetic energy, so the balance
    holds to round-off without a quadrature of the damping work.
    """
    n = md_w2.size
    inv = np.empty(n)  # 1 / (w2 dt): no division in the loop
    for j in range(n):
        inv[j] = 1.0 / (md_w2[j] * dt)
    for k in range(nb):
        de = 0.0
        dk = 0.0
        ek = 0.0
        es = 0.0
        for j in range(n):
            q1 = Q[k, j]
            v1 = QV[k, j]
            v0 = qv_start[j] if k == 0 else QV[k - 1, j]
            dq = DQ[k, j]
            p0 = P[k, j]
            p1 = P[k + 1, j]
            integral_dt = (0.5 * dt * (p0 + p1) - (v1 - v0) - md_c[j] * dq) * inv[j]  # int q dt / dt
            de += p0 * dq + (p1 - p0) * (q1 - integral_dt)
            dk += 0.5 * (v1 * v1 - v0 * v0)
            ek += 0.5 * v1 * v1
            es += 0.5 * md_w2[j] * q1 * q1
        Eb[0, k] = de
        Eb[1, k] = de - dk
        Eb[2, k] = ek
        Eb[3, k] = es
