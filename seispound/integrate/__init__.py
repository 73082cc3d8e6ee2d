"""Newmark-beta integration of a row of buildings with contact (numba kernel behind a validating front end)."""

from .newmark import IntegrationError, Newmark, RawResult, integrate

__all__ = ["Newmark", "RawResult", "integrate", "IntegrationError"]
