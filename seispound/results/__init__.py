"""Result Dataset schema and HDF5 storage."""

from .io import open_result, write_result
from .metrics import normalised_error
from .schema import ENERGY_COMPONENTS, SCHEMA, SCHEMA_VERSION, build_dataset

__all__ = ["normalised_error", "build_dataset", "write_result", "open_result", "SCHEMA", "SCHEMA_VERSION", "ENERGY_COMPONENTS"]
