"""The peak-oriented storey law (``storey.codes.PEAK_ORIENTED``): stiffness degrading, optionally pinched.

Private: the material protocol (``_material.material_trial``) calls :func:`peak_oriented_move`.

Rules (Clough & Johnston 1966, Proc. Japan Earthquake Eng. Symp., 227-232; Takeda, Sozen & Nielsen 1970,
J. Struct. Div. 96(12), 2557-2573, in the simplified form of Otani 1974 and of Saiidi & Sozen 1981, Struct.
Res. Ser. 465, U. Illinois), with the storey's force f [N] and drift d [m]:

* backbone: bilinear and symmetric, f = k d up to the yield drift dy = fy / k, then slope alpha k;
* unloading (f and the drift's motion of opposite signs): a line of slope k_u = k (dy / d_m)^beta_u, d_m the
  largest excursion on the side f is on (dy before that side yields; beta_u = 0 is Clough's law, 0.3-0.5
  Takeda's as Otani gives it), never flatter than the secant to that peak (``_unloading_stiffness``);
* reloading (f zero or of the motion's sign, off the backbone): a line from the current point aimed at the
  largest excursion on the side it moves to, on the backbone (the yield point before that side yields), so
  that a partial reversal reloads straight back towards the same peak (Saiidi & Sozen's simplification of
  Takeda's inner loops);
* pinching (severity s in [0, 1)): while below it, reloading first aims at the pinch point on the target
  side's unloading line at (1 - s) times the target force, then at the target (the crack-closing point of
  Roufaiel & Meyer 1987, J. Struct. Eng. 113(3), 429-444; s = 0: no pinch);
* a reloading line steeper than k (its target behind the current drift) is replaced by the elastic line to
  the backbone.

The law is rate independent and piecewise linear, so a monotonic move of the drift is followed exactly,
segment by segment, from the committed point: the return map is exact for a deformation linear in the step,
as the bilinear law's is.
"""

from __future__ import annotations

from seispound._jit import njit

# the state columns: force [N], drift [m], the largest positive and negative excursions [m] (0: not yet
# beyond the yield drift, read as +-dy, so that the zero initial state is the virgin storey)
ST_F, ST_D, ST_DPOS, ST_DNEG = 0, 1, 2, 3
# a move crosses at most: unloading to zero force, a pinch point, the target, the backbone
_MAX_SEGMENTS = 8
# a move bends where a segment's slope differs from its first's by more than this fraction of k (round-off
# makes the virgin storey's unloading and reloading lines, both of slope k, differ by about 1e-16 k)
BEND = 1e-9


@njit(cache=True, inline="always")
def _backbone(x, s, k, dy, alpha):
    """The backbone force [N] at drift x [m] on side s (+1 or -1), s x >= dy."""
    return s * k * dy + alpha * k * (x - s * dy)


@njit(cache=True, inline="always")
def _unloading_stiffness(k, dy, alpha, beta_u, peak):
    """k_u = k (dy / d_m)^beta_u [N/m] for the largest excursion d_m = |peak| >= dy of the side (Otani 1974),
    held at least the peak's secant stiffness F_m / d_m = k (alpha + (1 - alpha) dy / d_m) (derived here: a
    flatter unloading line would end past the origin, and below alpha k its loops would make energy; the
    exponent reaches it only at large ductility and a large alpha, e.g. beta_u 0.9 and alpha 0.23 at 5)."""
    if beta_u == 0.0:
        return k
    ratio = dy / peak
    return k * max(ratio ** beta_u, alpha + (1.0 - alpha) * ratio)


@njit(cache=True, inline="always")
def _bends(kt, k_first, k):
    """(the first segment's slope [N/m], whether slope kt [N/m] differs from it): -1 is no segment yet."""
    if k_first < 0.0:
        return kt, False
    return k_first, abs(kt - k_first) > BEND * k


@njit(cache=True)
def peak_oriented_move(par, d, f, dpos, dneg, delta, rate):
    """The force [N], tangent [N/m] and excursions [m] after the drift moves monotonically from d to delta,
    and whether the move's slope changes on the way.

    Parameters
    ----------
    par : tuple of float
        (k [N/m], fy [N], alpha [-], beta_u [-], pinching severity [-]).
    d, f : float
        The committed drift [m] and force [N].
    dpos, dneg : float
        The largest excursions so far [m], dpos >= dy and dneg <= -dy.
    delta : float
        The trial drift [m].
    rate : float
        The drift's rate [m/s]: the direction whose tangent is returned when delta equals d.

    Returns
    -------
    f, kt, dpos, dneg : float
        The force at delta, the slope of the segment it ends on, and the excursions.
    bent : bool
        A segment of the move has another slope than its first (by more than ``BEND`` k): the force is not
        linear in the drift along the move.
    """
    k, fy, alpha, beta_u, pinch = par
    dy = fy / k
    m = 1.0 if (delta > d or (delta == d and rate >= 0.0)) else -1.0
    kt = k
    k_first, bent = -1.0, False
    for _ in range(_MAX_SEGMENTS):
        if f * m < 0.0:  # unloading towards zero force
            ku = _unloading_stiffness(k, dy, alpha, beta_u, dpos if f > 0.0 else -dneg)
            d0 = d - f / ku
            kt = ku
            k_first, b = _bends(kt, k_first, k)
            bent = bent or b
            if m * (delta - d0) <= 0.0:
                return f + ku * (delta - d), kt, dpos, dneg, bent
            d, f = d0, 0.0
            continue
        peak = dpos if m > 0.0 else dneg
        if m * d >= m * peak and m * f >= m * _backbone(d, m, k, dy, alpha) - 1e-12 * fy:
            # on the backbone, moving on: the excursion follows
            kt = alpha * k
            k_first, b = _bends(kt, k_first, k)
            f += kt * (delta - d)
            return f, kt, (delta if m > 0.0 else dpos), (delta if m < 0.0 else dneg), bent or b
        d_aim, f_aim = peak, _backbone(peak, m, k, dy, alpha)
        if pinch > 0.0 and m * f < m * (1.0 - pinch) * f_aim:
            d_pinch = peak - pinch * f_aim / _unloading_stiffness(k, dy, alpha, beta_u, m * peak)
            if m * d < m * d_pinch and (f_aim * (1.0 - pinch) - f) * m <= k * m * (d_pinch - d):
                d_aim, f_aim = d_pinch, (1.0 - pinch) * f_aim
        run = d_aim - d
        if m * run <= 0.0 or not (0.0 <= m * (f_aim - f) <= k * m * run):
            # aimed steeper than elastic (or behind): the elastic line to the backbone
            d_aim = m * dy + (k * d - f) / (k * (1.0 - alpha))
            if m * (d_aim - d) < 0.0:
                d_aim = d
            f_aim, run = _backbone(d_aim, m, k, dy, alpha), d_aim - d
            kt = k
        else:
            kt = (f_aim - f) / run
        k_first, b = _bends(kt, k_first, k)
        bent = bent or b
        if m * (delta - d_aim) <= 0.0:
            return f + kt * (delta - d), kt, dpos, dneg, bent
        d, f = d_aim, f_aim
        if m * d >= m * peak:  # the target reached: the backbone from here
            if m > 0.0:
                dpos = d
            else:
                dneg = d
    return f + kt * (delta - d), kt, dpos, dneg, bent


@njit(cache=True)
def peak_oriented_energy(par, f, dpos, dneg):
    """Recoverable energy [J]: f^2 / (2 k_u), what unloading to zero force along the current side's unloading
    line returns (derived here; the work done on the storey beyond it is dissipated)."""
    k, fy, alpha, beta_u, pinch = par
    if f == 0.0:
        return 0.0
    ku = _unloading_stiffness(k, fy / k, alpha, beta_u, dpos if f > 0.0 else -dneg)
    return 0.5 * f * f / ku
