"""seispound: earthquake-induced pounding between adjacent multi-storey shear buildings.

Quick use::

    import seispound as sp
    model = sp.load_model("models/two_buildings.toml")
    ds = sp.simulate(model)            # xarray.Dataset, with the no-pounding twin
    sp.write_result(ds, "two.h5")
"""

from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("seispound")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

from .errors import InputError
from .model import Analysis, GroundMotionSpec, Model, load_model
from .results import open_result, write_result
from .simulate import simulate

__all__ = ["InputError", "Model", "Analysis", "GroundMotionSpec", "load_model", "simulate",
           "write_result", "open_result", "__version__"]
