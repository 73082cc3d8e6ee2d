"""What ``simulate`` spends outside the kernel, part by part, and what xarray alone costs for the result.

``python -m benchmarks.outside [--case pair|lve|row] [--repeat 200] [--cold DT]``

The user's path on one of the peer cases (``benchmarks/peer/userpath.py``; the record in
memory, dt 0.01 s, 4 contact substeps, ``twin=False``) is run as ``simulate`` runs it, each
part timed inside the call: validation and assembly lookup with the record's preparation,
the guards before the run, the integration, the finiteness check, the result Dataset, the
guards after.  Reported: the minimum and median of each over ``--repeat`` calls, the whole
``simulate`` timed on its own, and two floors of the Dataset:

* **xarray alone**: the run's own variables, already computed, made into ``xr.Variable`` s and a
  Dataset with its dimension indexes (``results.construct.dataset``): what any eager xarray
  result with this schema costs, whatever computes the arrays;
* **the layout**: the five (time, building, floor) histories copied from the kernel's DOF
  columns into a NaN-padded buffer, the least NumPy work the schema's layout needs.

Their sum over the kernel's time bounds the share outside the kernel from below.

``--cold DT``: before each timed call, OpenSeesPy analyses the same case at step DT (as
``benchmarks.peer.userpath`` alternates the two programs), so that each part is timed with
the caches another program left; the floors are then not timed.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

import numpy as np

CASES = {"pair": 0, "lve": 1, "row": 3}


def _parts(model):
    """One ``simulate``-shaped call, the time of each part [s] (the order of ``seispound.simulate``)."""
    from seispound import __version__
    from seispound.integrate import integrate
    from seispound.plausibility import check_after_run, check_before_run, check_model, issue, to_json
    from seispound.results import build_dataset
    from seispound.results.schema import Layout
    from seispound.simulation import _check_finite, _run_inputs

    t = [time.perf_counter()]
    kept, system, motions = _run_inputs(model)
    t.append(time.perf_counter())
    if "model_findings" not in kept:
        kept["model_findings"] = tuple(check_model(model))
    ag, prov = motions.rows[0], motions.provenance
    found = check_before_run(model, prov, ag, model_findings=kept["model_findings"])
    issue(found, force=False, file=model.source)
    t.append(time.perf_counter())
    an = model.analysis
    raw = integrate(system, motions.rows, an.dt, an.nsteps, an.newmark, scheme=an.scheme)
    t.append(time.perf_counter())
    _check_finite(raw, an.dt)
    t.append(time.perf_counter())
    if "layout" not in kept:
        kept["layout"] = Layout(model, system)
    ds = build_dataset(model, system, raw, None, ag, prov, __version__, motions=motions, layout=kept["layout"])
    t.append(time.perf_counter())
    after = check_after_run(ds)
    issue(after, force=True)
    ds.attrs["plausibility"] = to_json(found + after)
    t.append(time.perf_counter())
    return [b - a for a, b in zip(t, t[1:])], ds, raw


PARTS = ["validation, assembly lookup, record", "guards before", "integration", "finiteness",
         "result Dataset", "guards after"]


def xarray_floor(ds):
    """A callable that builds ``ds`` again from its computed arrays: Variables, indexes, Dataset."""
    from seispound.results.construct import dataset, variable

    coords = {k: (v.dims, np.asarray(v.values), dict(v.attrs)) for k, v in ds.coords.items()}
    data = {k: (v.dims, np.asarray(v.values), dict(v.attrs)) for k, v in ds.data_vars.items()}

    def build():
        return dataset({k: variable(d, a, dict(at)) for k, (d, a, at) in data.items()}, coords, dict(ds.attrs))
    return build


def layout_floor(raw, lay):
    """A callable that lays the five histories out on (time, building, floor), NaN-padded, by slice copies."""
    from seispound.results.schema import _scatter

    nt = raw.displacement.shape[0]
    b_of, f_of = lay.system.dof_building, lay.system.dof_floor - 1
    srcs = [raw.displacement, raw.velocity, raw.acceleration, raw.displacement, raw.displacement]

    def build():
        hist = np.full((5, nt, lay.nb, lay.nfmax), np.nan)
        for dst, src in zip(hist, srcs):
            _scatter(dst, src, lay.runs, b_of, f_of)
        return hist
    return build


def _times(fn, repeat):
    fn()
    out = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return out


def main(argv=None) -> int:
    import seispound as sp
    from benchmarks.peer.userpath import cases, user_model

    ap = argparse.ArgumentParser(prog="python -m benchmarks.outside", description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", choices=sorted(CASES), default="pair")
    ap.add_argument("--repeat", type=int, default=200)
    ap.add_argument("--cold", type=float, default=None, metavar="DT",
                    help="run OpenSeesPy on the case at step DT before each timed call")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # the guards' warnings are part of the timed path, not of the report
    case = cases(20.0)[CASES[args.case]]
    model = user_model(case, 0.01, 4)
    for _ in range(20):
        _parts(model)
    if args.cold is not None:
        from benchmarks.peer.userpath import time_opensees

        rows = []
        for _ in range(args.repeat):
            time_opensees(case, args.cold)
            rows.append(_parts(model)[0])
        rows = np.array(rows)
        print(f"{case.name}: after OpenSeesPy at dt {args.cold:g} each time; {args.repeat} calls, us (min / median)")
        for name, col in zip(PARTS, rows.T):
            print(f"  {name:38s} {col.min() * 1e6:8.0f} {np.median(col) * 1e6:8.0f}")
        return 0
    rows = np.array([_parts(model)[0] for _ in range(args.repeat)])
    whole = _times(lambda: sp.simulate(model, twin=False), args.repeat)
    _, ds, raw = _parts(model)
    floor_x = _times(xarray_floor(ds), args.repeat)
    floor_l = _times(layout_floor(raw, model.kept()["layout"]), args.repeat)
    print(f"{case.name}: {int(ds.impact_count.sum())} impacts, {len(ds.variables)} variables "
          f"({len(ds.data_vars)} data, {len(ds.coords)} coordinates), {len(ds.xindexes)} indexes; "
          f"{args.repeat} calls, times in us (min / median)")
    for name, col in zip(PARTS, rows.T):
        print(f"  {name:38s} {col.min() * 1e6:8.0f} {np.median(col) * 1e6:8.0f}")
    kernel = rows[:, 2]
    outside = rows.sum(axis=1) - kernel
    print(f"  {'outside the integration (sum)':38s} {outside.min() * 1e6:8.0f} {np.median(outside) * 1e6:8.0f}")
    for name, col in (("whole simulate, timed on its own", whole), ("floor: xarray alone (this schema)", floor_x),
                      ("floor: the histories laid out", floor_l)):
        print(f"  {name:38s} {min(col) * 1e6:8.0f} {statistics.median(col) * 1e6:8.0f}")
    k, o = kernel.min(), outside.min()
    lo = min(floor_x) + min(floor_l)
    print(f"share outside the integration: {o / (k + o):.0%} (minima); at the two floors alone: "
          f"{lo / (k + lo):.0%}; 10 % needs at most {k / 9 * 1e6:.0f} us outside")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
