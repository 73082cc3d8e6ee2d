"""The fast Dataset construction (``results/construct.py``) against xarray's public constructor."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from seispound import load_model, simulate
from seispound.results import construct
from tests._models import REPO, short_copy


def _both(model, monkeypatch):
    """The same run's Dataset built by the fast path and by ``xr.Dataset``."""
    monkeypatch.setattr(construct, "FAST", True)
    fast = simulate(model)
    monkeypatch.setattr(construct, "FAST", False)
    public = simulate(model)
    return fast, public


@pytest.mark.parametrize("name", ["two_buildings.toml", "row_of_three.toml", "yielding_pair.toml",
                                  "slab_pendulum_rods.toml"])
def test_fast_construction_is_identical_to_the_public_constructor(name, tmp_path, monkeypatch):
    # the rod-floor slabs (node coordinates) run free, 0.05 s, as bundled
    path = REPO / "models" / name if "rods" in name else short_copy(tmp_path, 2.0, name)
    fast, public = _both(load_model(path), monkeypatch)
    for ds in (fast, public):
        ds.attrs.pop("created_utc")  # a clock reading
    xr.testing.assert_identical(fast, public)
    assert set(fast.xindexes) == set(public.xindexes)
    for name in fast.variables:
        assert fast[name].dtype == public[name].dtype, name
    # selections by label work on the fast one's indexes
    b = str(fast.building.values[0])
    np.testing.assert_array_equal(fast.displacement.sel(building=b, floor=1).values,
                                  public.displacement.sel(building=b, floor=1).values)
    assert fast.sel(time=slice(0.0, 0.5)).sizes["time"] == public.sel(time=slice(0.0, 0.5)).sizes["time"]


def test_inconsistent_dimension_sizes_are_refused():
    with pytest.raises(ValueError, match="dimension 'time' of 'b' has size 3"):
        construct.dataset({"a": xr.Variable(("time",), np.zeros(2)), "b": xr.Variable(("time",), np.zeros(3))},
                          {}, {}, fast=True)
