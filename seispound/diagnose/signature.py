"""Signatures a residual can show before any hypothesis is fitted: the rocking signature of a soft foundation.

A uniform factor c on a shear building's storey stiffnesses scales every mode's omega^2 by c
and leaves the mode shapes alone.  A flexible foundation does not.  To first order in its
flexibility (Rayleigh's quotient with the fixed-base mode shapes, the foundation springs in
series with the building), mode j's omega^2 falls by the share

    d_j = omega_j^2 (L_j^2 / K_x + H_j^2 / K_theta),   L_j = sum_i m_i phi_ij,   H_j = sum_i m_i z_i phi_ij,

with phi_j mass-normalised (phi_j^T M phi_j = 1), so that L_j^2 is the mode's effective mass and
H_j / L_j its effective height (Chopra, Dynamics of Structures, 4th ed., Sec. 13.2 for the
effective modal mass and height; Veletsos & Meek 1974, and Stewart, Fenves & Seed 1999, Eq. 1,
for the single-mode form 1 / omega~^2 = 1 / omega^2 + 1 / omega_x^2 + 1 / omega_theta^2).
For sway alone d_j is nearly the same in every mode (omega_j^2 L_j^2 is constant over j for a
uniform shear beam), which a storey-stiffness factor absorbs; rocking is not: the moment of
the higher modes' inertia forces about the base nearly cancels (H_2^2 is a few per cent of
H_1^2), so a rocking foundation lowers the first mode far more than the second.

What a recalibrated fixed-base model leaves, then: a storey-stiffness factor that is a
compromise, too stiff in the first mode's band and too soft in the second's.  ``band_factors``
measures this directly: in a band around each fixed-base mode, the storey-stiffness change
that the residual asks for, by a one-parameter least-squares projection of the band-passed
residual on the band-passed sensitivity of the simulation to that building's stiffness factor.
``rocking_score`` turns the first two bands' estimates into a one-sided z-score: the data ask
the second mode to be stiffer than the first.  A uniform stiffness error, a damping error or
wrong gaps ask for the same change in both bands (z near zero); only a base flexibility that
acts on the first mode more than on the second gives z >> 0.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["BAND", "Z_ROCKING", "band_factors", "foundation_shift", "rocking_score", "shear_modes"]

BAND = 0.15  # half-width of a mode's band, a share of its frequency (5 % damping: half-power half-width 5 %)
Z_ROCKING = 3.0  # one-sided z of the rocking signature (second band stiffer than the first) needed to test SSI


def shear_modes(masses, stiffness) -> tuple[np.ndarray, np.ndarray]:
    """Fixed-base modes of a shear building: (omega [rad/s], shape (N,); phi, mass-normalised columns, (N, N)).

    ``masses`` [kg] floor 1 up; ``stiffness`` [N/m], storey i joining floor i-1 to floor i.
    """
    from scipy.linalg import eigh

    from ..structure.building import shear_stiffness_matrix

    w2, phi = eigh(shear_stiffness_matrix(stiffness), np.diag(np.asarray(masses, float)))  # phi^T M phi = I
    return np.sqrt(w2), phi


def foundation_shift(masses, stiffness, heights, sway_stiffness, rocking_stiffness) -> np.ndarray:
    """First-order share by which sway and rocking springs lower each fixed-base mode's omega^2 (module docstring).

    ``heights`` [m]: storey heights (floor elevations are their cumulative sums);
    ``sway_stiffness`` [N/m], ``rocking_stiffness`` [N m/rad].  Returns d_j, shape (N,), with
    omega~_j^2 = omega_j^2 (1 - d_j) + O(d^2).
    """
    w, phi = shear_modes(masses, stiffness)
    m = np.asarray(masses, float)
    z = np.cumsum(np.asarray(heights, float))
    L = m @ phi
    H = (m * z) @ phi
    return w * w * (L * L / float(sway_stiffness) + H * H / float(rocking_stiffness))


def band_factors(residual: dict, sensitivity: dict, dt: float, bands) -> list[tuple[float, float]]:
    """Per band, the stiffness-factor change the residual asks for and its standard error: [(dk, sigma)].

    ``residual``: {channel: recorded - simulated}; ``sensitivity``: {channel: d(simulated) / d(factor)}
    on the same grid (a building's channels); ``dt`` [s]; ``bands``: [(lo, hi)] [Hz].  In each band
    (a 4th-order Butterworth band-pass, forward and backward), dk = <J, r> / <J, J> over the
    channels.  Its standard error takes the band's residual after the fit as noise with
    2 (hi - lo) T independent samples (T the record's length: the band's degrees of freedom),
    counted once for all channels, because a building's floor channels see the same noise
    propagated from the input: sigma^2 = (<r, r> - dk <J, r>) / (n_band - 1) / <J, J>.
    """
    from scipy.signal import butter, sosfiltfilt

    out = []
    ids = [c for c in residual if c in sensitivity]
    T = dt * (len(residual[ids[0]]) if ids else 0)
    for lo, hi in bands:
        sos = butter(4, [lo, hi], btype="band", fs=1.0 / dt, output="sos")
        jr = jj = rr = 0.0
        for c in ids:
            J = sosfiltfilt(sos, np.asarray(sensitivity[c], float))
            r = sosfiltfilt(sos, np.asarray(residual[c], float))
            jr += float(J @ r)
            jj += float(J @ J)
            rr += float(r @ r)
        if jj <= 0.0:
            out.append((0.0, math.inf))
            continue
        dk = jr / jj
        n_band = max(2.0 * (hi - lo) * T, 2.0)
        out.append((dk, math.sqrt(max(rr - dk * jr, 0.0) / (n_band - 1.0) / jj)))
    return out


def rocking_score(factors) -> float:
    """One-sided z of the rocking signature from ``band_factors`` of the first two modes' bands.

    z = (dk_2 - dk_1) / sqrt(sigma_1^2 + sigma_2^2): positive when the second mode's band asks for
    stiffer storeys than the first's, as a flexible foundation makes it (module docstring).
    """
    (d1, s1), (d2, s2) = factors[:2]
    s = math.hypot(s1, s2)
    return (d2 - d1) / s if s > 0 and math.isfinite(s) else 0.0
