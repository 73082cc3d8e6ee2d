"""The distributed-element storey law of Iwan (``storey.codes.IWAN``): Masing's rules, optionally self-centring.

Private: the material protocol (``_material.material_trial`` and ``material_energy``) calls
:func:`iwan_trial` and :func:`iwan_energy`.

A storey of initial stiffness k is three springs in parallel (k [N/m], drifts [m], forces [N]):

* a linear spring of stiffness alpha k (the post-yield stiffness);
* a self-centring spring, nonlinear elastic: k_c clip(d, -dy, dy) with k_c = c (1 - alpha) k (c = 0: none);
* N = ``IWAN_SLIDERS`` elastic-perfectly-plastic sliders (a spring k_i = (1 - c) (1 - alpha) k / N in series
  with a Coulomb slider), slider i yielding at the drift d_i = dy 10^(s (2 (i + 1/2) / N - 1)): geometrically
  spaced, their geometric mean dy, spanning 10^(+-s (1 - 1/N)) (s [decades] = 0: every slider at dy).

The sliders are the parallel-series model of Iwan (1966), "A distributed-element model for hysteresis and its
steady-state dynamic response", J. Appl. Mech. 33(4), 893-900.  Iwan shows that such a model obeys Masing's
(1926) rules: from a reversal point (d_r, f_r), the branch is the virgin curve of the sliders scaled by two,
f_r - 2 F((d_r - d) / 2), and an inner loop closes where it started (the extended rules hold without a memory
of reversal points: the sliders' offsets are that memory).  With s = 0 and c = 0 the law is the bilinear law
with kinematic hardening (``BILINEAR``).  The self-centring spring retraces its curve, so with c > 0 the
storey dissipates only the sliders' share and returns towards zero drift: a flag-shaped loop whose unloading
stiffness is alpha k + (1 - c) (1 - alpha) k (derived here; the idealised flag of Christopoulos, Filiatrault &
Folz 2002, EESD 31(5), 1131-1150, unloads at k and is not of this form).  The spacing, the self-centring spring
and its saturation at dy are this package's choices: they give Masing-type and flag-type loops two parameters.

Every spring is piecewise linear in d and the sliders are rate independent, so the return map of each slider
(Simo & Hughes 1998, Computational Inelasticity, Sec. 1.4) is exact for a drift that moves monotonically
within the step, as the bilinear law's is.

State columns: the sliders' offsets p_i [m] (slider i carries k_i (d - p_i), |d - p_i| <= d_i), then the drift
[m] (``ST_IWAN_DRIFT``: where the committed state lies, which the elastic predictor's test reads).
"""

from __future__ import annotations

from seispound._jit import njit

from ..storey.codes import IW_ALPHA, IW_CENTRING, IW_D0, IW_DY, IW_K, IW_RATIO, IWAN_SLIDERS

ST_IWAN_DRIFT = IWAN_SLIDERS  # the state column after the sliders' offsets


@njit(cache=True, inline="always")
def _first_and_ratio(par, q):
    """(d_0 [m], d_(i+1) / d_i [-]) of the sliders' geometric yield drifts: d_0 = dy 10^(-s (1 - 1/N)), the ratio
    10^(2 s / N), computed once by ``StoreyLaw.kernel_rows`` (columns IW_D0, IW_RATIO)."""
    return par[q, IW_D0], par[q, IW_RATIO]


@njit(cache=True)
def iwan_trial(par, committed, trial, q, delta):
    """Force [N] and tangent [N/m] of Iwan storey q at drift ``delta`` [m], each slider's offset moved by its
    return map from the committed one and written to row q of ``trial``.

    The tangent is k less what the yielded sliders and a saturated self-centring spring take away, so that it
    equals k exactly while every spring is elastic (what the elastic predictor tests, ``_general._kept_elastic``).
    """
    k, dy, alpha = par[q, IW_K], par[q, IW_DY], par[q, IW_ALPHA]
    kc = par[q, IW_CENTRING] * (1.0 - alpha) * k
    ki = (1.0 - par[q, IW_CENTRING]) * (1.0 - alpha) * k / IWAN_SLIDERS
    f = alpha * k * delta
    kt = k
    if delta > dy:
        f += kc * dy
        kt -= kc
    elif delta < -dy:
        f -= kc * dy
        kt -= kc
    else:
        f += kc * delta
    di, ratio = _first_and_ratio(par, q)
    for i in range(IWAN_SLIDERS):
        e = delta - committed[q, i]
        if e > di:
            e = di
            kt -= ki
        elif e < -di:
            e = -di
            kt -= ki
        trial[q, i] = delta - e
        f += ki * e
        di *= ratio
    trial[q, ST_IWAN_DRIFT] = delta
    return f, kt


@njit(cache=True)  # not inlined: the energy and the elastic predictor's test inline the protocol, and a loop
def iwan_energy(par, state, q, delta):
    """Recoverable energy [J] of Iwan storey q in ``state`` at drift ``delta`` [m]: alpha k delta^2 / 2, the
    self-centring spring's k_c delta^2 / 2 within dy and k_c dy (|delta| - dy / 2) beyond, and each slider's
    k_i (delta - p_i)^2 / 2 (the integral of each spring's force; what the sliders absorbed beyond it is
    dissipated)."""
    k, dy, alpha = par[q, IW_K], par[q, IW_DY], par[q, IW_ALPHA]
    kc = par[q, IW_CENTRING] * (1.0 - alpha) * k
    ki = (1.0 - par[q, IW_CENTRING]) * (1.0 - alpha) * k / IWAN_SLIDERS
    a = abs(delta)
    e = 0.5 * alpha * k * delta * delta + (0.5 * kc * a * a if a <= dy else kc * dy * (a - 0.5 * dy))
    for i in range(IWAN_SLIDERS):
        x = delta - state[q, i]
        e += 0.5 * ki * x * x
    return e


@njit(cache=True)
def iwan_window(par, state, q):
    """(lo, hi [m], c [N]) of Iwan storey q in ``state``: the drifts between which every spring stays elastic
    (each slider within d_i of its offset, the self-centring spring within +-dy), and the storey's force
    k delta - c there, c = sum k_i p_i (the free flight's offset, ``_general_flight``; derived here: the
    springs' forces summed with every one elastic)."""
    k, dy, alpha = par[q, IW_K], par[q, IW_DY], par[q, IW_ALPHA]
    ki = (1.0 - par[q, IW_CENTRING]) * (1.0 - alpha) * k / IWAN_SLIDERS
    di, ratio = _first_and_ratio(par, q)
    lo, hi, c = -dy, dy, 0.0
    for i in range(IWAN_SLIDERS):
        p = state[q, i]
        lo = max(lo, p - di)
        hi = min(hi, p + di)
        c += ki * p
        di *= ratio
    return lo, hi, c


@njit(cache=True)
def iwan_kept_elastic(par, state, q, kt):
    """Did Iwan storey q move elastically from its committed point (``state``) to a trial point of tangent
    ``kt`` [N/m]?  The trial point lies inside the springs' elastic window (tangent k), and so must the
    committed one: the window is an interval, so the straight move between them is elastic throughout; a
    committed point beyond +-dy (the self-centring spring saturated) left its window and came back at
    another force."""
    if kt != par[q, IW_K]:
        return False
    lo, hi, _ = iwan_window(par, state, q)
    d = state[q, ST_IWAN_DRIFT]
    tol = 1e-12 * par[q, IW_DY]
    return lo - tol <= d <= hi + tol
