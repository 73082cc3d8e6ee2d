"""The per-floor read-out of a row whose DOFs are not its floors (``results.floors.floor_view``)."""

from __future__ import annotations

import contextlib
import warnings

import numpy as np
from threadpoolctl import threadpool_info

import seispound._blas as blas
from seispound import load_model
from seispound.results.floors import floor_view
from seispound.simulation import run_inputs, run_row

from benchmarks.physics_accuracy import CASES, _text


def _soil_raw(tmp_path):
    """The 5 + 8 storey pair of ``benchmarks.physics_accuracy`` with soil under B, 2 s of it: (raw, system)."""
    f = tmp_path / "soil.toml"
    f.write_text(_text(CASES["soil and footing"], 0.005).replace("duration = 20.0", "duration = 2.0"))
    m = load_model(f)
    system, motions = run_inputs(m)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_row(m, system, motions.rows), system


def test_read_out_on_one_blas_thread(tmp_path, monkeypatch):
    """Its products run on one BLAS thread (on a busy machine a second thread waits for a core: a study of
    this pair on two workers took 1.6 times as long, ``benchmarks.blas_threads --study``), with the same
    values as on the default threads (a regression guard: both are one product)."""
    raw, system = _soil_raw(tmp_path)
    seen = []
    real = blas.one_thread

    @contextlib.contextmanager
    def spy():
        with real():
            seen.append({lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"})
            yield

    monkeypatch.setattr(blas, "one_thread", spy)
    limited = floor_view(raw, system)[0]
    assert seen == [{1}]
    monkeypatch.setattr(blas, "one_thread", contextlib.nullcontext)
    free = floor_view(raw, system)[0]
    for name in ("displacement", "velocity", "acceleration", "drift"):
        a, b = getattr(limited, name), getattr(free, name)
        assert a.shape == (raw.displacement.shape[0], 13)
        np.testing.assert_array_equal(a, b)
    # the floors are the DOFs that are not the foundation's (sway, rocking, cone): a selection
    np.testing.assert_array_equal(limited.displacement, raw.displacement[:, system.outputs.single])
