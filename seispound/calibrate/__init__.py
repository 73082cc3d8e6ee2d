"""Calibration against recordings: ``seispound calibrate`` and :func:`calibrate`.

Recordings are any files obspy reads; a channel map (``channels.py``) ties each trace to a
model quantity; a trials file lists tests that differ only in initial conditions; the fit
(``fit.py``) is least squares over the simulator with uncertainties, through the lean
simulation path (``observe.py``).
"""

from .api import calibrate, load_trials
from .channels import Channel, load_channels
from .fit import CalibrationResult, FitParameter
from .recording import Recording, read_recording

__all__ = ["calibrate", "load_trials", "Channel", "load_channels", "CalibrationResult", "FitParameter",
           "Recording", "read_recording"]
