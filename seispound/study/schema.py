"""The study store: one HDF5 file (netCDF-4 via h5netcdf) holding a labelled cube of runs.

Schema ``seispound-study`` version 2 (``ds.attrs["schema_version"]``)
---------------------------------------------------------------------------
Dimensions
    record (nr)
        one per ground-motion record, in the order of the study file.
    <axis> ...
        one per ``[[axis]]`` of the study file, in file order, named by the
        axis ``name``.  The *run dimensions* are ``("record", *axes)``.
    building (nb), floor (max floors; absent floors are NaN), gap (one per
    gap element), as in the single-run schema (:mod:`seispound.results.schema`);
    time (decimated analysis instants), only when histories are stored.
Coordinates
    record (record names, str); record_file (record) str, the file path as given;
    each axis dimension: its values (float or str) for a single-path axis, or
    0..n-1 for a zipped axis, whose members are then coordinates along it
    named by their dotted path (for example ``gap.1.size``);
    building (names); floor (1-based); gap (0-based); gap_left, gap_right
    (building names), gap_left_floor, gap_right_floor, gap_height [m] along gap;
    time [s] when histories are stored.
Data variables (dims = run dims + the trailing ones shown; units in ``attrs["units"]``)
    status (run dims) int8: 1 done, 0 failed, -1 not run yet (``flag_values``/``flag_meanings``)
    error (run dims) str: the one-line error of a failed run, "" otherwise
    amplification (..., building, floor) [1]: peak |u| with pounding / without
    peak_displacement (..., building, floor) [m]
    peak_displacement_no_pounding (..., building, floor) [m]
    peak_drift (..., building, floor) [m]
    peak_acceleration, peak_acceleration_no_pounding [m/s^2], acceleration_amplification [1],
    peak_drift_ratio, peak_drift_ratio_no_pounding, drift_ratio_amplification [1],
    peak_storey_shear, peak_storey_shear_no_pounding [N], storey_shear_amplification [1]
        (..., building, floor): as in the single-run schema (:mod:`seispound.results.peaks`)
    max_acceleration_amplification, max_drift_ratio_amplification, max_storey_shear_amplification [1],
    max_peak_acceleration [m/s^2], max_peak_drift_ratio [1] (run dims): maxima over building and floor
    peak_pounding_force (..., gap) [N]
    impact_count (..., gap) int64 (-1 where the run is not done)
    max_amplification (run dims) [1]: max over building and floor
    max_pounding_force (run dims) [N]: max over gap
    total_impacts (run dims) int64 (-1 where not done)
    histories, when asked for (``[output] histories``), chunked one run per
    chunk and compressed: displacement, velocity, acceleration, drift
    (..., time, building, floor) and pounding_force (..., time, gap)
Attributes
    schema, schema_version, title, seispound_version, study_file, study_text,
    model_file, model_text, records (JSON list: per record its file, sha256
    and reader provenance), axes (JSON list of the axis definitions),
    run_dims (JSON list), study_hash (what a resumed study must match),
    runs_total, runs_done, runs_failed.

Values of runs that are not done (failed or not run yet) are NaN for floats.
"""

from __future__ import annotations

SCHEMA = "seispound-study"
SCHEMA_VERSION = 3

STATUS_DONE = 1
STATUS_FAILED = 0
STATUS_PENDING = -1

# (name, trailing dims, units, long name, dtype)
SUMMARY_VARIABLES = [
    ("amplification", ("building", "floor"), "1", "displacement amplification: peak with pounding / peak without",
     "f8"),
    ("peak_displacement", ("building", "floor"), "m", "peak |displacement| with pounding", "f8"),
    ("peak_displacement_no_pounding", ("building", "floor"), "m",
     "peak |displacement| without pounding (gaps disabled)", "f8"),
    ("peak_drift", ("building", "floor"), "m", "peak |inter-storey drift|", "f8"),
    *[(f"{prefix}{name}{suffix}", ("building", "floor"), units, f"{what}{tail}", "f8")
      for name, units, what in (("acceleration", "m/s^2", "peak |absolute floor acceleration|"),
                                ("drift_ratio", "1", "peak |inter-storey drift| / storey height"),
                                ("storey_shear", "N", "peak |storey shear| (spring force k x drift)"))
      for prefix, suffix, tail, units in (("peak_", "", ", with pounding", units),
                                          ("peak_", "_no_pounding", ", without pounding", units),
                                          ("", "_amplification", ": with pounding / without", "1"))],
    ("peak_pounding_force", ("gap",), "N", "peak pounding force", "f8"),
    ("impact_count", ("gap",), "1", "number of impacts", "i8"),
    ("max_amplification", (), "1", "largest amplification over buildings and floors", "f8"),
    ("max_acceleration_amplification", (), "1", "largest floor acceleration amplification", "f8"),
    ("max_drift_ratio_amplification", (), "1", "largest drift ratio amplification", "f8"),
    ("max_storey_shear_amplification", (), "1", "largest storey shear amplification", "f8"),
    ("max_peak_acceleration", (), "m/s^2", "largest peak absolute floor acceleration, with pounding", "f8"),
    ("max_peak_drift_ratio", (), "1", "largest peak drift ratio, with pounding", "f8"),
    ("max_pounding_force", (), "N", "largest peak pounding force over the gap elements", "f8"),
    ("total_impacts", (), "1", "number of impacts, all gap elements", "i8"),
    ("contact_substeps", (), "1", "contact substeps per impact duration, as run (chosen from analysis.tolerance "
                                  "unless the model gives them)", "i8"),
    ("contact_error_estimate", (), "1", "estimated relative error of one impact at those substeps (NaN when given)",
     "f8"),
    ("peak_error_estimate", (), "1", "estimated relative error of the run's peaks, from the run at half its "
                                     "substeps (NaN when given or nothing pounded)", "f8"),
]

# history name -> (trailing dims, units, long name)
HISTORY_VARIABLES = {
    "displacement": (("time", "building", "floor"), "m", "floor displacement relative to the ground"),
    "velocity": (("time", "building", "floor"), "m/s", "floor velocity relative to the ground"),
    "acceleration": (("time", "building", "floor"), "m/s^2", "absolute floor acceleration"),
    "drift": (("time", "building", "floor"), "m", "inter-storey drift (floor minus floor below)"),
    "pounding_force": (("time", "gap"), "N", "pounding force (compression positive)"),
}

# names a study axis may not take (they are dimensions of the store already)
RESERVED_DIMS = {"record", "building", "floor", "gap", "time", "impact", "energy_component"}
