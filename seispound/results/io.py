"""HDF5 storage of result Datasets (h5netcdf engine; readable by h5py and xarray)."""

from __future__ import annotations

from pathlib import Path

import xarray as xr

from .._output import atomic_output, check_writable
from ..errors import InputError

__all__ = ["write_result", "open_result", "RESULT_SUFFIXES"]

#: Suffixes of result files.
RESULT_SUFFIXES = (".h5", ".hdf5", ".nc")


def write_result(ds: xr.Dataset, path) -> Path:
    """Write ``ds`` to ``path`` (HDF5 via h5netcdf), atomically.

    The file is written under a temporary name in the same folder and renamed
    at the end, so an interrupted or failed write leaves nothing half-written;
    the finished file has the permissions of the umask (``0o666 & ~umask``).

    Raises
    ------
    InputError
        If ``path`` cannot be written (a folder, a missing or read-only
        folder, no permission), before anything is written.
    """
    path = check_writable(path, key="output")
    encoding = {name: {"zlib": True, "complevel": 4} for name, v in ds.data_vars.items() if v.ndim >= 2}
    with atomic_output(path, key="output") as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=encoding, invalid_netcdf=False)
    return path


def open_result(path) -> xr.Dataset:
    """Open a result file written by :func:`write_result` (loaded into memory)."""
    path = Path(path)
    if not path.is_file():
        raise InputError("result file not found", file=path)
    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()
