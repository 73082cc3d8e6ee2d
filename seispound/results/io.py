"""HDF5 storage of result Datasets (h5netcdf engine; readable by h5py and xarray)."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import xarray as xr

from ..errors import InputError

__all__ = ["write_result", "open_result"]


def write_result(ds: xr.Dataset, path) -> Path:
    """Write ``ds`` to ``path`` (HDF5 via h5netcdf), atomically.

    The file is written under a temporary name in the same folder and renamed
    at the end, so an interrupted or failed write leaves nothing half-written.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(f"output folder does not exist: {folder}", file=path, key="output")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    os.close(fd)
    try:
        encoding = {name: {"zlib": True, "complevel": 4} for name, v in ds.data_vars.items()
                    if v.ndim >= 2}
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding, invalid_netcdf=False)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def open_result(path) -> xr.Dataset:
    """Open a result file written by :func:`write_result` (loaded into memory)."""
    path = Path(path)
    if not path.is_file():
        raise InputError("result file not found", file=path)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()
