"""seispound: earthquake-induced pounding between adjacent multi-storey shear buildings.

Quick use::

    import seispound as sp
    model = sp.load_model("models/two_buildings.toml")
    ds = sp.simulate(model)            # xarray.Dataset, with the no-pounding twin
    sp.write_result(ds, "two.h5")
"""

from importlib import import_module
from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("seispound")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

from ._memory import keep_freed_memory
from .errors import InputError

# a run's large arrays from memory the process already holds, not fresh pages (``_memory``: a fresh process's
# simulate of a row with a foundation 0.81 of its time); SEISPOUND_KEEP_MEMORY=0 leaves glibc's defaults
keep_freed_memory()

# Public names load their modules on first use, so that the command line
# (`seispound laws`, error paths) does not pay for numba and xarray up front.
_LAZY = {
    "Model": ".model", "Analysis": ".model", "BuildingMotion": ".model", "GroundMotionSpec": ".model",
    "load_model": ".model",
    "simulate": ".simulation", "write_result": ".results", "open_result": ".results",
    "normalised_error": ".results", "response_spectrum": ".spectra", "floor_spectrum": ".spectra",
    "load_study": ".study", "run_study": ".study", "open_study": ".study.query",
}

__all__ = ["InputError", "__version__", *_LAZY]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'seispound' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
