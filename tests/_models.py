"""Shortened copies of the bundled model files for tests that run them."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def short_copy(folder: Path, duration: float, name: str = "two_buildings.toml", as_name: str | None = None) -> Path:
    """models/<name> written to folder/<as_name or name>, its record path absolute and its duration shortened."""
    text = (REPO / "models" / name).read_text(encoding="utf-8")
    text, n_file = re.subn(r'(?m)^file = "([^"]+)"',
                           lambda m: f'file = "{(REPO / "models" / m.group(1)).resolve().as_posix()}"', text)
    text, n_dur = re.subn(r"(?m)^duration = [0-9.eE+-]+", f"duration = {duration}", text)
    assert (n_file, n_dur) == (1, 1), f"models/{name} changed shape: adapt tests/_models.short_copy"
    path = folder / (as_name or name)
    path.write_text(text, encoding="utf-8")
    return path


def made_recording(data: dict, base, chans, true: dict, seed: int, noise: float = 0.01) -> list:
    """Trials holding the package's own simulation of model table ``data`` at the values ``true``
    ({path: value}) on channels ``chans``, each with white noise of ``noise`` times its standard deviation
    (a recording whose truth is known, for calibration and diagnosis tests)."""
    import numpy as np

    from seispound.calibrate.observe import Observer, Trial
    from seispound.calibrate.recording import Recording

    dt = data["analysis"].get("dt", 0.005)
    n = int(round(data["analysis"]["duration"] / dt)) + 1
    blank = [Trial(Recording(dt, {c.id: np.zeros(n) for c in chans}, []))]
    sims = Observer(data, base, chans, blank).simulate(list(true.items()))[0]
    rng = np.random.default_rng(seed)
    rec = {c.id: sims[c.id] + noise * sims[c.id].std() * rng.standard_normal(n) for c in chans}
    return [Trial(Recording(dt, rec, []))]
