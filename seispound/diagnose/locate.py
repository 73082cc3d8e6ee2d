"""Where a residual lives: channels, time windows and frequency bands, against the sensor-noise floor.

The noise floor of each channel is estimated from the recording itself: for white noise
of variance s^2 on a signal smooth at the sampling rate, the second difference has
variance 6 s^2, so s = MAD(diff2) / 0.6745 / sqrt(6) (a robust scale; the structural
response, well below the Nyquist frequency, contributes little to second differences).
The residual's spectrum (Welch) is compared with the white-noise level 2 s^2 dt per Hz;
bands where it stays above four times that level hold the mismatch.
"""

from __future__ import annotations

import numpy as np

__all__ = ["noise_sigma", "locate"]


def noise_sigma(x) -> float:
    """Sensor-noise standard deviation of a recorded channel (module docstring)."""
    d2 = np.diff(np.asarray(x, float), 2)
    return float(np.median(np.abs(d2 - np.median(d2))) / 0.6745 / np.sqrt(6.0))


def noise_ne(x) -> float:
    """The NE (seed Eq. 10) that the sensor noise alone leaves on a recorded channel ``x``: sigma sqrt(n) / ||x||."""
    x = np.asarray(x, float)
    return noise_sigma(x) * np.sqrt(x.size) / max(np.linalg.norm(x), 1e-300)


def locate(residuals: dict, recorded: dict, dt: float, window: float = 1.0, impact_times=()) -> list[dict]:
    """Per channel: its share of the residual energy, the window holding most of it, and the band above the noise.

    ``residuals``, ``recorded``: {trace id: samples}; ``impact_times``: impact onsets [s] of the
    simulation, to tie each window to the impacts in it.  Returns a list of
    ``{channel, t_start, t_end, band_hz: [lo, hi], residual_share, ne, noise_ne, impacts_in_window,
    share_after_impacts}``, largest share first; ``noise_ne`` is the NE that noise alone would leave
    (s sqrt(n) / ||recorded||); ``share_after_impacts`` the share of the channel's residual energy
    within 0.1 s after an impact (against 0.1 s times the impact rate for a residual unrelated to them).
    """
    from scipy.signal import welch

    total = sum(float(r @ r) for r in residuals.values()) or 1.0
    times = np.asarray(impact_times, float)
    n_all = next(iter(residuals.values())).size if residuals else 0
    after = np.zeros(n_all, bool)  # samples within 0.1 s after an impact onset
    for t in times:
        after[int(t / dt):int((t + 0.1) / dt) + 1] = True
    out = []
    for cid, r in residuals.items():
        x = recorded[cid]
        sig = noise_sigma(x)
        n = r.size
        w = max(int(round(window / dt)), 4)
        energy = np.add.reduceat(r * r, np.arange(0, n, w))
        k = int(np.argmax(energy))
        nper = min(512, n)
        f, p = welch(r, fs=1.0 / dt, nperseg=nper)
        floor = 2.0 * sig * sig * dt
        above = p > 4.0 * floor
        band = [0.0, 0.0]
        if above.any():
            # the contiguous run of bins above the floor that holds the most residual power
            best, lo = (0.0, 0, 0), None
            for i in range(f.size + 1):
                if i < f.size and above[i]:
                    lo = i if lo is None else lo
                elif lo is not None:
                    pw = float(p[lo:i].sum())
                    if pw > best[0]:
                        best = (pw, lo, i - 1)
                    lo = None
            band = [float(f[best[1]]), float(f[best[2]])]
        norm = float(np.linalg.norm(x)) or 1.0
        t0, t1 = k * w * dt, min((k + 1) * w, n) * dt
        out.append({"channel": cid, "t_start": float(t0), "t_end": float(t1), "band_hz": band,
                    "residual_share": float(r @ r) / total, "ne": float(np.linalg.norm(r)) / norm,
                    "noise_ne": sig * np.sqrt(n) / norm,
                    "impacts_in_window": int(np.count_nonzero((times >= t0) & (times < t1))),
                    "share_after_impacts": float(r[after] @ r[after]) / max(float(r @ r), 1e-300)})
    out.sort(key=lambda m: -m["residual_share"])
    return out
