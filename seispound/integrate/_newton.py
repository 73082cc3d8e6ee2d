"""The condensed Newton iteration on the forces of the active elements, shared by both drivers.

The linear part of a step is solved first (the predictor); the elements with state that are
active in it (closed gaps, storeys with a hysteretic law) then iterate on their own forces F,
coupled through G = B^T K_hat^-1 B (Sherman-Morrison-Woodbury; ``_kernel``'s module
docstring).  Each law is evaluated through the material protocol (``_material``), so a gap and
a yielding storey are iterated by the same code.
"""

from __future__ import annotations

from seispound._jit import njit

from ._linear import _dense_solve
from ._material import material_trial


@njit(cache=True, inline="always")
def _trial(code, par, states, q, k, s1, lin, Fm, resv, kt):
    """Element q's law at its linear-step deformation less s1 = (G F)_k: the residual F - f and the
    consistent tangent d f/d delta + cc d f/d rate into resv[k] and kt[k]; returns f [N].

    states = (st_c, st_t): the committed and trial states; lin = (dl, rl, cc): the linear step's
    deformations [m] and rates [m/s] and gamma/(beta h) [1/s]."""
    dl, rl, cc = lin
    f, dfd, dfv = material_trial(code[q], par, states[0], states[1], q, dl[k] - s1, rl[k] - cc * s1)
    resv[k] = Fm[k] - f
    kt[k] = dfd + cc * dfv
    return f


@njit(cache=True, inline="always")
def _newton(grp, Gm, trial, code, par, states, tol, work):
    """Newton-Raphson on the forces Fm[lo:hi] of one group of active elements (both drivers).

    The deformation and rate of element act[k] are dl[k] - (G F)_k and rl[k] - cc (G F)_k
    (G = B^T K_hat^-1 B restricted to the group, Gm[lo:hi, lo:hi]; the condensation of
    ``_kernel``'s module docstring).  Each law is evaluated through the material protocol
    (``_material.material_trial``: from its committed state st_c into st_t, which a redone
    step simply overwrites); the residual F - F_law is tested against rtol times the largest
    of ``scale`` and the forces.  grp = (lo, hi, act); trial = (dl, rl, Fm, cc): the linear step's
    deformations [m] and rates [m/s], the forces [N] iterated, gamma/(beta h) [1/s]; states = (st_c,
    st_t); tol = (scale [N], rtol, max_iter); work = (resv, kt, Sm, ym).  Returns (converged,
    iterations beyond the first evaluation).
    """
    lo, hi, act = grp
    dl, rl, Fm, cc = trial
    scale, rtol, max_iter = tol
    resv, kt, Sm, ym = work
    m = hi - lo
    it = 0
    while True:
        rn = 0.0
        sc = scale
        for k in range(lo, hi):
            s1 = 0.0
            for r in range(lo, hi):
                s1 += Gm[k, r] * Fm[r]
            f = _trial(code, par, states, act[k], k, s1, (dl, rl, cc), Fm, resv, kt)
            rn = max(rn, abs(resv[k]))
            sc = max(sc, abs(f))
        if rn <= rtol * sc:
            return True, it
        if it >= max_iter:
            return False, it
        it += 1
        # Newton: (I + diag(kt) G) dF = -res, on the group (local indices in Sm, ym)
        for k in range(lo, hi):
            for r in range(lo, hi):
                Sm[k - lo, r - lo] = kt[k] * Gm[k, r]
            Sm[k - lo, k - lo] += 1.0
            ym[k - lo] = -resv[k]
        _dense_solve(m, Sm, ym)
        for k in range(lo, hi):
            Fm[k] += ym[k - lo]
