"""Hysteretic storey laws: bilinear with kinematic hardening, Bouc-Wen, peak-oriented (Clough, Takeda), Iwan's
distributed-element law (Masing's rules, optionally self-centring) and the flag-shaped self-centring law."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, number_array
from . import codes as C

__all__ = ["StoreyLaw", "KINDS"]

KINDS = tuple(C.NAMES)


@dataclass
class StoreyLaw:
    """The lateral force-drift law of a building's storeys.

    Every numeric field is one value for all storeys or a list of one per
    storey, from the ground up.

    Parameters
    ----------
    kind : {"elastic", "bilinear", "bouc-wen", "peak-oriented", "iwan", "flag"}
        "bilinear": kinematic hardening, F = alpha k d + (1 - alpha) q,
        |q| <= fy (Simo & Hughes 1998, Sec. 1.4); "bouc-wen":
        F = alpha k d + (1 - alpha) k z with dz/dt = d'(t) (1 - |z/dy|^n
        (beta sgn(d' z) + gamma)) (Wen 1976, J. Eng. Mech. Div. 102(2),
        249-263, with A = 1); "peak-oriented": the stiffness-degrading law of
        reinforced-concrete storeys, a bilinear backbone, unloading at
        k (dy / d_m)^unloading_exponent (never flatter than the secant to the
        peak d_m) and reloading aimed at the largest
        excursion on the side it moves to (Clough & Johnston 1966; Takeda,
        Sozen & Nielsen 1970, with Otani's 1974 unloading), optionally
        pinched (the rules: ``seispound.integrate._peak_oriented``); "iwan":
        a linear spring alpha k, eight elastic-perfectly-plastic sliders whose
        yield drifts spread geometrically about dy, and optionally a
        self-centring nonlinear-elastic spring (Iwan 1966, J. Appl. Mech.
        33(4), 893-900: Masing's rules; ``seispound.integrate._iwan``); "flag":
        the flag-shaped loop of self-centring storeys, loading at k to dy and then
        at alpha k, unloading at k until the force has dropped by beta k dy,
        then at alpha k, and back to the origin at k
        (Christopoulos, Filiatrault & Folz 2002, EESD 31(5), 1131-1150;
        ``seispound.integrate._flag``); k the storey's ``storey_stiffness``.
    yield_drift : float or list, [m]
        dy; or give ``yield_force`` fy [N] (dy = fy / k).  Exactly one of the two.
    yield_force : float or list, [N]
    post_yield_ratio : float or list, [-]
        alpha, the post-yield stiffness over k, in [0, 1).
    n : float
        Bouc-Wen exponent (>= 1; large n approaches the bilinear law).
    beta, gamma : float
        Bouc-Wen shape parameters, beta >= |gamma| and beta + gamma > 0 (the
        bounded, dissipative class of Ikhouane, Manosa & Rodellar 2007, Syst.
        Control Lett. 56, 197-205); with beta + gamma = 1, z is bounded by dy
        and the hysteretic force by (1 - alpha) k dy.
    strength_degradation, stiffness_degradation : float, [-]
        Bouc-Wen only: Baber & Wen's (1981) delta_nu and delta_eta (>= 0, default 0:
        no degradation); strength and stiffness degrade as nu = 1 + delta_nu eps,
        eta = 1 + delta_eta eps with the hysteretic energy eps = integral of z
        d(drift) / dy^2 (about 4 mu per full cycle at ductility mu).
    unloading_exponent : float, [-]
        Peak-oriented only: beta_u in [0, 2] (default 0: Clough's law, unloading at
        k; Otani gives 0.3-0.5 for Takeda's).
    pinching : float, [-]
        Peak-oriented: the severity s in [0, 1) of the pinch, reloading first
        aims at (1 - s) times its target force on the target side's unloading
        line (Roufaiel & Meyer 1987); default 0, none.  Bouc-Wen: below.
    yield_spread : float, [decades]
        Iwan only: s in [0, 1] (default 0: every slider yields at dy); the
        sliders' yield drifts are dy 10^(s (2 (i + 1/2) / 8 - 1)), i = 0..7.
    self_centring : float, [-]
        Iwan only: c in [0, 1), the share of the hysteretic stiffness
        (1 - alpha) k in a nonlinear-elastic spring that saturates at dy
        (default 0: none; the loop narrows to a flag as c grows).
    energy_dissipation : float, [-]
        Flag only, and required there: beta in [0, 1], the force drop on unloading
        at k over the yield force k dy (Christopoulos et al.'s beta; the branches lie
        beta (1 - alpha) k dy apart; 0: nonlinear elastic, no dissipation; 1: the
        lower branch ends at the origin).  Every beta returns the storey
        to zero drift at zero force.
    pinching, pinching_rate, pinching_width : float, [-]
        Bouc-Wen only: the loop pinches near zero force as in Baber & Noori (1985,
        J. Eng. Mech. 111(8), 1010-1026) and Foliente (1995, J. Struct. Eng. 121(6),
        1013-1022), dz/dt multiplied by h(z) = 1 - zeta_1 exp(-(z / (psi dy))^2) with
        zeta_1 = zeta_s (1 - exp(-p eps)): ``pinching`` zeta_s in [0, 1) (default 0: none),
        ``pinching_rate`` p > 0 (default 1; the pinch grows with the energy eps above),
        ``pinching_width`` psi > 0 (default 0.2).  Foliente's offset q is 0 and his width
        a constant here.
    """

    kind: str = "elastic"
    yield_drift: object = None
    yield_force: object = None
    post_yield_ratio: object = 0.0
    n: float | None = None
    beta: float = 0.5
    gamma: float = 0.5
    strength_degradation: float = 0.0
    stiffness_degradation: float = 0.0
    unloading_exponent: float = 0.0
    pinching: float = 0.0
    pinching_rate: float = 1.0
    pinching_width: float = 0.2
    yield_spread: float = 0.0
    self_centring: float = 0.0
    energy_dissipation: float | None = None

    @property
    def code(self) -> int:
        return C.NAMES[self.kind]

    @property
    def hysteretic(self) -> bool:
        return self.kind != "elastic"

    def validate(self, n_storeys: int, key: str = "storey_law") -> None:
        """Check every field against a building of ``n_storeys``; InputError names ``<key>.<field>``."""
        if self.kind not in C.NAMES:
            raise InputError(f"kind must be one of {', '.join(repr(k) for k in KINDS)}, got {self.kind!r}",
                             key=f"{key}.kind")
        if not self.hysteretic:
            return
        given = [f for f in ("yield_drift", "yield_force") if getattr(self, f) is not None]
        if len(given) != 1:
            raise InputError("give exactly one of yield_drift [m] and yield_force [N]"
                             + (" (got both)" if len(given) == 2 else ""), key=f"{key}.yield_drift")
        self._per_storey(given[0], n_storeys, key, positive=True)
        alpha = self._per_storey("post_yield_ratio", n_storeys, key)
        if np.any((alpha < 0.0) | (alpha >= 1.0)):
            raise InputError(f"must lie in [0, 1), got {float(alpha[(alpha < 0) | (alpha >= 1)][0]):g}",
                             key=f"{key}.post_yield_ratio")
        if self.kind == "bouc-wen":
            if self.n is None:
                raise InputError("is required for a Bouc-Wen storey (the exponent of |z/dy|, >= 1)", key=f"{key}.n")
            for f in ("n", "beta", "gamma"):
                v = getattr(self, f)
                if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)):
                    raise InputError(f"must be a finite number, got {v!r}", key=f"{key}.{f}")
            if not 1.0 <= self.n <= 100.0:
                raise InputError(f"must lie in [1, 100], got {self.n:g}", key=f"{key}.n")
            if not self.beta + self.gamma > 0.0:
                raise InputError(f"beta + gamma must be > 0 (a bounded z), got {self.beta + self.gamma:g}",
                                 key=f"{key}.gamma")
            if not self.beta >= abs(self.gamma):
                # outside Ikhouane, Manosa & Rodellar's (2007) class of bounded, dissipative Bouc-Wen models
                raise InputError(f"must be >= |gamma| (a Bouc-Wen loop that dissipates energy), got beta "
                                 f"{self.beta:g} with gamma {self.gamma:g}", key=f"{key}.beta")
        for f in ("strength_degradation", "stiffness_degradation"):
            v = getattr(self, f)
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v >= 0.0):
                raise InputError(f"must be a finite number >= 0, got {v!r}", key=f"{key}.{f}")
            if v and self.kind != "bouc-wen":
                raise InputError("degradation is a Bouc-Wen storey's (Baber & Wen 1981)", key=f"{key}.{f}")
        for f, lo, hi in (("pinching", 0.0, 1.0), ("pinching_rate", 0.0, math.inf),
                          ("pinching_width", 0.0, math.inf)):
            v = getattr(self, f)
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            if not ok or not (lo <= v < hi if f == "pinching" else lo < v < hi):
                raise InputError(f"must be a finite number in {'[0, 1)' if f == 'pinching' else '(0, inf)'}, "
                                 f"got {v!r}", key=f"{key}.{f}")
        if self.pinching and self.kind not in ("bouc-wen", "peak-oriented"):
            raise InputError("pinching is a Bouc-Wen (Baber & Noori 1985) or peak-oriented storey's",
                             key=f"{key}.pinching")
        v = self.unloading_exponent
        if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and 0.0 <= v <= 2.0):
            raise InputError(f"must be a finite number in [0, 2], got {v!r}", key=f"{key}.unloading_exponent")
        if v and self.kind != "peak-oriented":
            raise InputError("the unloading exponent is a peak-oriented storey's (Otani 1974)",
                             key=f"{key}.unloading_exponent")
        for f, hi, closed in (("yield_spread", 1.0, True), ("self_centring", 1.0, False)):
            v = getattr(self, f)
            ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            if not ok or not (0.0 <= v <= hi if closed else 0.0 <= v < hi):
                raise InputError(f"must be a finite number in [0, 1{']' if closed else ')'}, got {v!r}",
                                 key=f"{key}.{f}")
            if v and self.kind != "iwan":
                raise InputError(f"{f.replace('_', ' ')} is an Iwan storey's", key=f"{key}.{f}")
        self._validate_flag(key)

    def _validate_flag(self, key) -> None:
        v = self.energy_dissipation
        if v is None:
            if self.kind == "flag":
                raise InputError("is required for a flag storey (the force drop on unloading over the yield force, "
                                 "in [0, 1])", key=f"{key}.energy_dissipation")
            return
        if self.kind != "flag":
            raise InputError("the energy dissipation coefficient is a flag storey's", key=f"{key}.energy_dissipation")
        if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and 0.0 <= v <= 1.0):
            raise InputError(f"must be a finite number in [0, 1], got {v!r}", key=f"{key}.energy_dissipation")

    def _per_storey(self, field, n_storeys, key, positive=False) -> np.ndarray:
        arr = number_array(getattr(self, field), f"{key}.{field}")
        if arr.size not in (1, n_storeys):
            raise InputError(f"give one value or {n_storeys} (one per storey), got {arr.size}", key=f"{key}.{field}")
        if not np.all(np.isfinite(arr)) or (positive and np.any(arr <= 0.0)):
            raise InputError("every entry must be a finite number" + (" > 0" if positive else ""),
                             key=f"{key}.{field}")
        return np.broadcast_to(arr, (n_storeys,)).astype(float)

    def yield_drifts(self, stiffness) -> np.ndarray:
        """dy [m] of each storey, shape (N,), from yield_drift or yield_force / k."""
        k = np.asarray(stiffness, float)
        if self.yield_drift is not None:
            return self._per_storey("yield_drift", k.size, "storey_law")
        return self._per_storey("yield_force", k.size, "storey_law") / k

    def kernel_rows(self, stiffness, n_par: int) -> tuple[np.ndarray, np.ndarray]:
        """(codes (N,), parameters (N, n_par)) of the storeys (``storey.codes`` columns); code 0: elastic."""
        k = np.asarray(stiffness, float)
        codes = np.full(k.size, self.code, np.int64)
        par = np.zeros((k.size, n_par))
        if not self.hysteretic:
            return codes, par
        dy = self.yield_drifts(k)
        alpha = self._per_storey("post_yield_ratio", k.size, "storey_law")
        if self.kind == "bilinear":
            par[:, C.B_K], par[:, C.B_FY], par[:, C.B_ALPHA] = k, k * dy, alpha
        elif self.kind == "peak-oriented":
            par[:, C.PO_K], par[:, C.PO_FY], par[:, C.PO_ALPHA] = k, k * dy, alpha
            par[:, C.PO_UNLOAD], par[:, C.PO_PINCH] = self.unloading_exponent, self.pinching
        elif self.kind == "iwan":
            par[:, C.IW_K], par[:, C.IW_DY], par[:, C.IW_ALPHA] = k, dy, alpha
            par[:, C.IW_SPREAD], par[:, C.IW_CENTRING] = self.yield_spread, self.self_centring
            par[:, C.IW_D0] = dy * 10.0 ** (-self.yield_spread * (1.0 - 1.0 / C.IWAN_SLIDERS))
            par[:, C.IW_RATIO] = 10.0 ** (2.0 * self.yield_spread / C.IWAN_SLIDERS)
        elif self.kind == "flag":
            par[:, C.FL_K], par[:, C.FL_DY], par[:, C.FL_ALPHA] = k, dy, alpha
            par[:, C.FL_BETA] = self.energy_dissipation
        else:
            par[:, C.BW_K], par[:, C.BW_DY], par[:, C.BW_ALPHA] = k, dy, alpha
            par[:, C.BW_N], par[:, C.BW_BETA], par[:, C.BW_GAMMA] = self.n, self.beta, self.gamma
            par[:, C.BW_DNU], par[:, C.BW_DETA] = self.strength_degradation, self.stiffness_degradation
            par[:, C.BW_PINCH], par[:, C.BW_PINCH_RATE] = self.pinching, self.pinching_rate
            par[:, C.BW_PINCH_WIDTH] = self.pinching_width
        return codes, par
