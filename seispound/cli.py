"""Command line: ``seispound run``, ``study``, ``query``, ``plot`` and ``laws``.

Bad input prints one line ``seispound: error: FILE: KEY: message`` and exits
with code 2, without a traceback and without writing anything.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

from .errors import InputError

EXIT_INPUT = 2
EXIT_UNCONVERGED = 3  # calibrate: the fit stopped at its cap on simulations (--allow-unconverged: 0)
EXIT_FAILED = 1


def _parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="seispound",
                                 description="Earthquake-induced pounding between adjacent shear buildings.")
    ap.add_argument("--version", action="store_true", help="print the version and exit")
    sub = ap.add_subparsers(dest="command")
    run = sub.add_parser("run", help="simulate a model file and write the result Dataset (HDF5)")
    run.add_argument("model", help="TOML model file")
    run.add_argument("-o", "--output", help="result file (.h5); default: MODEL with suffix .h5")
    run.add_argument("--no-twin", action="store_true",
                     help="skip the no-pounding twin run (amplification is then NaN)")
    run.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    run.add_argument("--force", action="store_true",
                     help="run even when a plausibility guard refuses the input (a PGA above 3 g ...); "
                          "the findings are still printed and stored in the result")
    sub.add_parser("laws", help="list the contact laws, their parameters and units")
    st = sub.add_parser("study", help="run a parametric study (records x parameter axes) into one HDF5 store",
                        description="Run every run of STUDY.toml not yet in the store; rerun the same "
                                    "command to resume after an interruption.")
    st.add_argument("study", help="TOML study file (base model, records, axes)")
    st.add_argument("-o", "--output", help="the store (.h5); default: STUDY with suffix .h5")
    st.add_argument("--scheduler",
                    help='"local" (dask\'s local multiprocessing scheduler; the default when dask is '
                         'installed, else "serial"), "cluster" (a dask.distributed LocalCluster), "serial" '
                         '(this process, no dask), or the address tcp://HOST:PORT of a running '
                         'dask.distributed scheduler')
    st.add_argument("--workers", type=int, help="worker processes for local and cluster (default: all cores)")
    st.add_argument("--chunk", type=int, help="runs per task (default: about 16 tasks per worker, at most 10)")
    st.add_argument("--snapshot", type=float, default=30.0,
                    help="seconds between rewrites of the store while running (0: only at the end; default 30)")
    st.add_argument("--overwrite", action="store_true",
                    help="replace a store (and journal) of a different study at the output path")
    st.add_argument("-q", "--quiet", action="store_true", help="no progress bar or summary")
    st.add_argument("--force", action="store_true",
                    help="run records that a plausibility guard refuses (a PGA above 3 g)")
    cal = sub.add_parser("calibrate", help="fit model parameters to recordings (least squares, with uncertainties)",
                         description="Fit the model's parameters named by dotted paths so that its simulated "
                                     "channels match the recorded ones; write the calibrated model.")
    cal.add_argument("model", help="TOML model file")
    cal.add_argument("recording", nargs="*", help="recording files (any format obspy reads)")
    cal.add_argument("--channels", required=True, help="channel map (TOML [[channel]] tables)")
    cal.add_argument("--trials", help="trials file ([[trial]] tables), instead of recording files")
    cal.add_argument("--fit", action="append", default=[], metavar="PATH[=lo:hi]",
                     help="a parameter to fit, by its dotted path (as in a study axis); repeat for more")
    cal.add_argument("-o", "--output", help="calibrated model file (.toml); default: MODEL_calibrated.toml")
    cal.add_argument("--max-evaluations", type=int, help="cap on the number of simulations")
    cal.add_argument("--allow-unconverged", action="store_true",
                     help="write the model even if the fit stops at --max-evaluations (exit 0)")
    cal.add_argument("--starts", type=int, default=16,
                     help="global starts across the bounds when the first fit ends far above the noise "
                          "(default 16; 0: the model's own values only)")
    cal.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    imp = sub.add_parser("impact", help="the seed paper's procedure on impact tests: per trial and law, the "
                                        "stiffness matching the peak force, e from the displacements, NE of the "
                                        "first pulse",
                         description="For two pendulum bodies and one gap: per trial (a recording of the force and "
                                     "both bodies' displacements) and per contact law, fit the stiffness so that the "
                                     "simulated peak force equals the recorded one, take e from the velocities "
                                     "before and after the impact, and report NE (seed Eq. 10) over the first "
                                     "positive force pulse, as a table like the seed's Table 1 and a figure like "
                                     "its Fig. 7.")
    imp.add_argument("model", help="TOML model file: two 1-DoF bodies and one gap (models/slab_pendulum.toml)")
    imp.add_argument("--trials", required=True, help="trials file ([[trial]] recording = ...)")
    imp.add_argument("--channels", required=True, help="channel map: one force, one displacement per body")
    imp.add_argument("--laws", default="LVe,MLVe,NIVe,Hd,LHC", help="comma-separated laws (default: the seed's five)")
    imp.add_argument("-o", "--output", help="the table (markdown); default: printed only")
    imp.add_argument("--figure", help="a PNG of measured against simulated force per trial")
    imp.add_argument("-q", "--quiet", action="store_true", help="no progress or table on the terminal")
    from .diagnose.hypotheses import HYPOTHESES  # the registry names the physics (no fitting code imported)

    physics = ", ".join(HYPOTHESES)
    dg = sub.add_parser("diagnose", help="locate where a simulation and a recording differ and name the physics "
                                          "the model left out",
                        description="Check the numerics, recalibrate the model's own parameters, locate the "
                                    f"residual (channels, windows, bands), try each missing physics ({physics}) "
                                    "and keep what the data support.")
    dg.add_argument("model", help="TOML model file")
    dg.add_argument("recording", nargs="*", help="recording files (any format obspy reads)")
    dg.add_argument("--channels", required=True, help="channel map (TOML [[channel]] tables)")
    dg.add_argument("--trials", help="trials file ([[trial]] tables), instead of recording files")
    dg.add_argument("--report", required=True, help="REPORT.json")
    dg.add_argument("-o", "--output", help="the augmented model (.toml); default: MODEL_augmented.toml by the report")
    dg.add_argument("--figure", help="PNG of recorded, simulated and diagnosed channels, mismatch marked")
    dg.add_argument("--hypotheses", help=f"comma-separated physics to try (default all: {physics})")
    dg.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    from .study.query import add_query_parser

    add_query_parser(sub)
    from .plot import add_plot_parser

    add_plot_parser(sub)
    return ap


def main(argv=None) -> int:
    args = _parser().parse_args(argv)
    if args.version:
        from . import __version__

        print(__version__)
        return 0
    try:
        if args.command == "run":
            return _run(args)
        if args.command == "laws":
            return _laws()
        if args.command == "study":
            return _study(args)
        if args.command == "calibrate":
            return _calibrate(args)
        if args.command == "impact":
            return _impact(args)
        if args.command == "diagnose":
            return _diagnose(args)
        if args.command == "query":
            from .study.query import cmd_query

            return cmd_query(args)
        if args.command == "plot":
            from .plot import cmd_plot

            return cmd_plot(args)
    except InputError as err:
        print(f"seispound: error: {err}", file=sys.stderr)
        return EXIT_INPUT
    except BrokenPipeError:  # output piped into `head`: not an error
        sys.stderr.close()
        return 0
    _parser().print_help()
    return EXIT_INPUT


def _run(args) -> int:
    from .integrate import IntegrationError
    from .model import load_model
    from .results import write_result
    from .simulation import simulate

    from ._output import check_writable
    from .plausibility import PlausibilityWarning
    from .results.io import RESULT_SUFFIXES

    model_path = Path(args.model)
    out = Path(args.output) if args.output else model_path.with_suffix(".h5")
    check_writable(out, key="--output", suffixes=RESULT_SUFFIXES)  # before any work
    model = load_model(model_path)
    try:
        with warnings.catch_warnings():  # findings are printed by the summary, from the result
            warnings.simplefilter("ignore", PlausibilityWarning)
            ds = simulate(model, twin=not args.no_twin, force=args.force)
    except IntegrationError as err:
        print(f"seispound: error: {model_path}: {err}", file=sys.stderr)
        return EXIT_FAILED
    write_result(ds, out)
    if not args.quiet:
        print(summary(ds, out))
    return 0


def _calibrate(args) -> int:
    import warnings as _w

    from ._output import atomic_output, check_writable
    from .calibrate import calibrate
    from .plausibility import PlausibilityWarning

    model_path = Path(args.model)
    out = Path(args.output) if args.output else model_path.with_name(model_path.stem + "_calibrated.toml")
    check_writable(out, key="--output", suffixes=(".toml",))
    if args.trials and args.recording:
        raise InputError("give recording files or --trials, not both", key="recording")
    if args.max_evaluations is not None and args.max_evaluations < 1:
        raise InputError(f"must be >= 1, got {args.max_evaluations}", key="--max-evaluations")
    if args.starts < 0:
        raise InputError(f"must be >= 0, got {args.starts}", key="--starts")
    with _w.catch_warnings():
        _w.simplefilter("ignore", PlausibilityWarning)
        res = calibrate(model_path, args.recording or None, channels=args.channels, fit=args.fit,
                        trials=args.trials, progress=not args.quiet, max_evaluations=args.max_evaluations,
                        output=out, starts=args.starts)
    if not res.converged and not args.allow_unconverged:
        if not args.quiet:
            print(res.summary())
        print(f"seispound: the fit stopped at --max-evaluations {args.max_evaluations} before converging; nothing "
              "written (more evaluations, or --allow-unconverged to write it anyway)", file=sys.stderr)
        return EXIT_UNCONVERGED
    with atomic_output(out, key="--output") as tmp:
        Path(tmp).write_text(res.model_text, encoding="utf-8")
    if not args.quiet:
        print(res.summary())
        print(f"  written to {out}")
    return 0


def _diagnose(args) -> int:
    import warnings as _w

    from ._output import check_writable
    from .diagnose import diagnose
    from .plausibility import PlausibilityWarning

    check_writable(Path(args.report), key="--report", suffixes=(".json",))
    if args.output:
        check_writable(Path(args.output), key="--output", suffixes=(".toml",))
    if args.figure:
        check_writable(Path(args.figure), key="--figure", suffixes=(".png",))
    if args.trials and args.recording:
        raise InputError("give recording files or --trials, not both", key="recording")
    names = None if args.hypotheses is None else [h.strip() for h in args.hypotheses.split(",") if h.strip()]
    if names == []:
        from .diagnose.hypotheses import HYPOTHESES

        raise InputError(f"give one or more of: {', '.join(HYPOTHESES)}", key="--hypotheses")
    with _w.catch_warnings():
        _w.simplefilter("ignore", PlausibilityWarning)
        try:
            res = diagnose(args.model, args.recording or None, channels=args.channels, trials=args.trials,
                           report=args.report, output=args.output, figure=args.figure, progress=not args.quiet,
                           hypotheses=names)
        except InputError as err:
            if err.key == "hypotheses":  # the option's name, as the user typed it
                raise InputError(err.message, key="--hypotheses") from None
            raise
    if not args.quiet:
        print(res.summary())
        print(f"  report: {args.report}; model: {res.augmented_model}")
    return 0


def _impact(args) -> int:
    from ._output import atomic_output, check_writable
    from .calibrate.impact import impact_study
    from .contact import get_law

    laws = [x.strip() for x in args.laws.split(",") if x.strip()]
    for law in laws:
        try:
            get_law(law)
        except InputError as err:
            raise InputError(err.message, key="--laws") from None
    for path, key, suffixes in ((args.output, "--output", (".md", ".txt")), (args.figure, "--figure", (".png",))):
        if path:
            check_writable(Path(path), key=key, suffixes=suffixes)
    study = impact_study(args.model, args.trials, args.channels, laws=tuple(laws), progress=not args.quiet)
    table = study.table()
    if args.output:
        with atomic_output(Path(args.output), key="--output") as tmp:
            Path(tmp).write_text(table + "\n", encoding="utf-8")
    if args.figure:
        with atomic_output(Path(args.figure), key="--figure") as tmp:
            study.figure(tmp)
    if not args.quiet:
        print(table)
    return 0


def _study(args) -> int:
    from .plausibility import PlausibilityWarning
    from .study import load_study, run_study

    path = Path(args.study)
    out = Path(args.output) if args.output else path.with_suffix(".h5")
    for name in ("workers", "chunk"):
        val = getattr(args, name)
        if val is not None and val < 1:
            raise InputError(f"must be an integer >= 1, got {val}", key=f"--{name}")
    if not args.snapshot >= 0:
        raise InputError(f"must be >= 0 seconds, got {args.snapshot}", key="--snapshot")
    study = load_study(path)
    scheduler = args.scheduler
    if scheduler is None:  # all cores with dask (the `dask` extra); one without it
        from .study.execute import default_scheduler

        scheduler = default_scheduler()
        if scheduler == "serial" and not args.quiet:
            print("seispound: dask is not installed, so the runs go one at a time in this process; "
                  "pip install 'seispound[dask]' to use every core", file=sys.stderr)
    if not args.quiet:
        dims = " x ".join(f"{n} {d}" for n, d in zip(study.shape, study.run_dims))
        print(f"{study.title}\n  {study.n_runs} runs ({dims}) -> {out}", flush=True)
    try:
        with warnings.catch_warnings():  # -q: the findings stay unsaid (progress mode prints them)
            warnings.simplefilter("ignore", PlausibilityWarning)
            res = run_study(study, out, scheduler=scheduler, workers=args.workers, chunk=args.chunk,
                            progress=not args.quiet, snapshot=args.snapshot, overwrite=args.overwrite,
                            force=args.force)
    except KeyboardInterrupt:
        print(f"seispound: interrupted; finished runs are kept in {out} and its journal: "
              "rerun the same command to resume", file=sys.stderr)
        return 130
    if not args.quiet:
        if res["ran"] == 0 and res["pending"] == 0:
            print(f"  all {study.n_runs} runs were already stored in {out}")
        else:
            print(f"  {res['ran']} runs in {res['seconds']:.1f} s; store: {res['done']} done, "
                  f"{res['failed']} failed, {res['pending']} pending -> {out}")
    return 0


def summary(ds, out=None) -> str:
    """A short text summary of a result Dataset."""
    lines = [f"{ds.attrs.get('title', '')}"]
    nb, ng, ni = ds.sizes["building"], ds.sizes["gap"], ds.sizes["impact"]
    lines.append(f"  {nb} buildings, {ng} gap elements, {ni} impacts, "
                 f"{float(ds.time[-1]):.3g} s at dt = {ds.attrs['dt']:g} s"
                 + (f" ({ds.attrs['scheme']} scheme)" if "scheme" in ds.attrs else ""))
    if ds.attrs.get("driver") == "general":  # the scheme changed: say why and how it was kept accurate
        n = int(ds.attrs.get("newmark_substeps", 1))
        sub = f"{n} substep{'s' if n > 1 else ''} per analysis step"
        free = int(json.loads(ds.attrs.get("integrator_stats", "{}")).get("free_flight_steps", 0))
        if free:
            lines.append(f"  general driver (yielding storeys, a foundation or floor-to-storey gaps): {free} of "
                         f"{ds.sizes['time'] - 1} analysis steps in free flight ({ds.attrs.get('scheme')} steps of "
                         f"each building), Newmark steps around impacts and yields, {sub}")
        else:
            lines.append("  Newmark steps throughout (yielding storeys, a foundation or floor-to-storey gaps need the "
                         f"general driver), {sub}")
    if ni and "contact_substeps" in ds.attrs:
        n, est = int(ds.attrs["contact_substeps"]), float(ds.attrs.get("contact_error_estimate", float("nan")))
        if ds.attrs.get("contact_substeps_from") == "tolerance":
            peak, runs = float(ds.attrs.get("peak_error_estimate", float("nan"))), int(ds.attrs.get("tolerance_runs", 1))
            lines.append(f"  {n} contact substeps per impact, chosen for a tolerance of "
                         f"{float(ds.attrs['tolerance']):.3g}: estimated error of the peaks {peak:.2g} (of an "
                         f"impact {est:.2g}), from {runs} runs")
        else:
            lines.append(f"  {n} contact substeps per impact, as the model gives")
    if ng:
        lines.append("  gap  between        floors  size [m]  impacts  peak force [kN]")
        for g in range(ng):
            left, right = _gap_side(ds, g, "left"), _gap_side(ds, g, "right")
            lines.append(f"  {g:>3}  {ds.gap_left.values[g]:>6}|{ds.gap_right.values[g]:<6}  "
                         f"{left:>3}|{right:<3} "
                         f"{float(ds.gap_size[g]):>8.4f}  {int(ds.impact_count[g]):>7}  "
                         f"{float(ds.peak_pounding_force[g]) / 1e3:>15.1f}")
    amp = ds.amplification
    if amp.notnull().any():
        where = amp.fillna(-1.0).argmax(dim=("building", "floor"))
        b = str(ds.building.values[int(where["building"])])
        f = int(ds.floor.values[int(where["floor"])])
        without = float(ds.peak_displacement_no_pounding.sel(building=b, floor=f))
        with_ = float(ds.peak_displacement.sel(building=b, floor=f))
        ratio = f"{float(amp.max()):.3f}" if _meaningful(with_, without) else "not meaningful (no response without)"
        lines.append(f"  largest displacement amplification (peak floor displacement with / without pounding) "
                     f"{ratio} at building {b}, floor {f} ({_num(with_ * 100, '.2f')} cm with pounding, "
                     f"{_num(without * 100, '.2f')} cm without)")
    lines += _engineering_lines(ds)
    for finding in json.loads(ds.attrs.get("plausibility", "[]")):
        lines.append(f"  {'note' if finding.get('advisory') else 'warning'}: {finding['message']}")
    if out is not None:
        lines.append(f"  written to {out}")
    return "\n".join(lines)


RATIO_FLOOR = 0.01  # a ratio whose denominator is below this share of its numerator says nothing


def _meaningful(with_, without) -> bool:
    """Whether with / without is a ratio worth printing: not of two near-zero peaks (a pendulum at rest without
    its impact, the row's unexcited floor)."""
    return without > 0 and without >= RATIO_FLOOR * abs(with_)


def _num(x, spec) -> str:
    """``x`` formatted by ``spec``, never as -0.000."""
    s = format(x, spec)
    return format(0.0, spec) if float(s) == 0.0 else s  # a negative value that rounds to zero


def _gap_side(ds, g, side) -> str:
    """A gap side in the summary: its floor ("3"), or the storey it strikes and where ("s3@0.50": storey 3, half
    way up)."""
    floor = int(ds[f"gap_{side}_floor"][g])
    w = float(ds[f"gap_{side}_weight"][g]) if f"gap_{side}_weight" in ds.coords else 1.0
    return str(floor) if w == 1.0 else f"s{floor}@{w:.2f}"


def _engineering_lines(ds) -> list[str]:
    """Per building: fixed-base periods, and the largest peak acceleration, drift ratio and storey shear
    with and without pounding (floor where the largest with pounding occurs)."""
    import numpy as np

    if "peak_acceleration" not in ds:
        return []
    out = ["  building  periods [s]           quantity (largest over floors)   with     without   ratio  floor"]
    yielding = _yielding(ds)
    rows = (("peak_acceleration", "floor acceleration [g]", 1 / 9.80665, ".3f"),
            ("peak_drift_ratio", "drift ratio [%]", 100.0, ".3f"), ("peak_storey_shear", "storey shear [kN]", 1e-3,
                                                                     ".0f"))
    for b in ds.building.values:
        periods = ds.period.sel(building=b).values
        periods = periods[np.isfinite(periods)][:3]
        head = f"  {b:<8}  {', '.join(f'{t:.3g}' for t in periods):<20}"
        for i, (var, label, scale, fmt) in enumerate(rows):
            w = ds[var].sel(building=b).values
            if not np.isfinite(w).any():
                continue
            f = int(np.nanargmax(w))
            without = float(ds[f"{var}_no_pounding"].sel(building=b).values[f])
            ratio = f"{w[f] / without:>6.2f}" if _meaningful(w[f], without) else f"{'-':>6}"
            out.append(f"{head if i == 0 else ' ' * len(head)}  {label:<31} {_num(w[f] * scale, '>8' + fmt)}  "
                       f"{_num(without * scale, '>8' + fmt)}  {ratio}  {int(ds.floor.values[f]):>5}")
        if b in yielding and "residual_drift" in ds:
            r = np.abs(ds.residual_drift.sel(building=b).values)
            f = int(np.nanargmax(r))
            out.append(f"{' ' * len(head)}  {'residual drift [mm]':<31} {_num(r[f] * 1e3, '>8.2f')}  "
                       f"{'':>8}  {'':>6}  {int(ds.floor.values[f]):>5}")
    return out


def _yielding(ds) -> set:
    """The buildings whose storeys can yield (a storey law other than elastic in the stored model text)."""
    import tomllib

    try:
        data = tomllib.loads(ds.attrs.get("model_text", ""))
    except tomllib.TOMLDecodeError:
        return set()
    return {str(b.get("name")) for b in data.get("building", [])
            if isinstance(b.get("storey_law"), dict) and b["storey_law"].get("kind", "elastic") != "elastic"}


def _laws() -> int:
    from .contact import get_law, law_names

    for name in law_names():
        cls = get_law(name)
        print(f"{cls.name:<10} {cls.formula}")
        print(f"{'':<10} reference: {cls.reference}; tension: {cls.tension_note or 'allowed'}")
        for prm in cls.describe_params():
            print(f"{'':<12}{prm.name:<12} [{prm.units}]  {prm.doc}")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
