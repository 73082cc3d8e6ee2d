"""A study of 100 000 runs: throughput, peak memory, store size, a kill -9 and its resume, query latency.

``python -m benchmarks.study_scale`` writes a pair of buildings (2 and 3
storeys, the 2-storey one's storey stiffness an axis) and a study of

    4 bundled records x 5 contact laws (zipped with their stiffness)
    x 50 gap sizes (4 mm to 20 cm) x 100 storey stiffnesses of building A
    = 100 000 runs (400 no-pounding twins)

and then, with ``seispound study`` (the default local scheduler, ``--workers``
processes):

1. times one run in this process (median and mean of 201 spread over the
   study, twins computed outside), as the model gives its contact substeps and
   as the default tolerance would choose them; compares the study's peaks at
   8, 16 and 32 contact substeps with 256 on a 1200-run sample of its cube;
   times a rebuild of the store from a journal of every run (what each
   snapshot does);
2. runs the study uninterrupted: wall time (process start to exit), runs per
   second, peak RSS of the orchestrating process and of the largest worker,
   store size;
3. runs it again into another store, kills the whole process group with
   SIGKILL once the journal holds ``--kill-at`` of the runs, reruns the same
   command, and checks that the resumed store is complete (every run done,
   none failed, no journal left), that the resume computed only the runs the
   journal did not hold, and that it is identical (``xarray.Dataset.identical``:
   every variable, coordinate and attribute) to the uninterrupted store;
4. runs the same study file against the tcp:// address of a dask.distributed
   scheduler with ``--cluster-workers`` workers (a LocalCluster this benchmark
   starts, standing in for a cluster) and checks that its store is identical
   to the local scheduler's;
5. times queries on the uninterrupted store: ``seispound query`` commands
   (process start included) and their Python equivalents on an open store,
   medians of ``--repeat``.

``--runs N`` scales the study down (fewer stiffnesses, then fewer gaps) for a
smoke run.  The model gives ``[analysis] contact_substeps = 32``, so each run
integrates once (without it every run that pounds would be run a second time
to check its tolerance, and the substeps would differ between runs).

Peak RSS: of the study process, ``getrusage`` where it exits normally and its
``VmHWM`` sampled from /proc every 0.1 s where it is killed; of the largest
worker, its ``VmHWM`` sampled the same way.  (``RUSAGE_CHILDREN`` is no measure
of the workers: its peak includes the short-lived helper that obspy's import
forks from the study process to run ``git rev-parse``, reported at the study
process's size.)  CPU time: ``getrusage`` of the study process and of its
children.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

RECORDS = ["elcentro_180", "elcentro_270", "corralitos_000", "corralitos_090"]
LAWS = [("LVe", 1.6e8), ("MLVe", 1.6e8), ("NIVe", 2.75e9), ("Hd", 2.75e9), ("LHC", 1.6e8)]
DURATION, DT, SUBSTEPS = 30.0, 0.005, 32
CHECK_SUBSTEPS = (8, 16, 32, 256)  # the substeps check: 256 is the reference

MODEL = """\
title = "A 2-storey and a 3-storey building, 30 s of record"

[analysis]
dt = {dt}                # s: the Corralitos records' step (El Centro's is 0.01 s)
duration = {duration}          # s
contact_substeps = {substeps}   # given: each run integrates once (no tolerance check)

[ground_motion]
file = "{record}"   # replaced by each record of the study
units = "g"

[contact]
law = "Hd"
stiffness = 2.75e9
restitution = 0.65

[[building]]
name = "A"
floors = 2
floor_masses = 1.0e5
storey_stiffness = 1.5e8
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}

[[building]]
name = "B"
floors = 3
floor_masses = 1.0e5
storey_stiffness = 5.0e7
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}

[[gap]]
between = ["A", "B"]
size = 0.02
"""

STUDY = """\
title = "Pair of 2 and 3 storeys: {nr} records x {nl} laws x {ng} gaps x {ns} storey stiffnesses of A"
model = "pair.toml"

[records]
bundled = {records}

[[axis]]
name = "law"
zip = [{{ path = "contact.law", values = {laws} }},
       {{ path = "contact.stiffness", values = {stiff} }}]

[[axis]]
name = "gap_size"
path = "gap.*.size"
range = {{ start = 0.004, stop = 0.2, num = {ng} }}

[[axis]]
name = "stiffness_A"
path = "building.A.storey_stiffness"
range = {{ start = 0.75e8, stop = 3.0e8, num = {ns} }}
"""


CHECK = """\
title = "Contact substeps: {check} on a sample of the study"
model = "pair.toml"

[records]
bundled = {records}

[[axis]]
name = "law"
zip = [{{ path = "contact.law", values = {laws} }},
       {{ path = "contact.stiffness", values = {stiff} }}]

[[axis]]
name = "gap_size"
path = "gap.*.size"
values = {gaps}

[[axis]]
name = "stiffness_A"
path = "building.A.storey_stiffness"
values = {stiffness}

[[axis]]
name = "substeps"
path = "analysis.contact_substeps"
values = {check}
"""
CHECKED = ("max_pounding_force", "max_amplification", "max_peak_acceleration", "max_peak_drift_ratio")


def shape_for(runs: int) -> tuple[int, int]:
    """(gap sizes, stiffnesses) giving about ``runs`` runs with 4 records and 5 laws."""
    if runs >= 1000:
        return 50, max(1, round(runs / 1000))
    return max(1, round(runs / 20)), 1


def write_study(folder: Path, runs: int, substeps: bool = True) -> Path:
    """The study file (and its model, pair.toml) in ``folder``; ``substeps=False``: the model leaves the
    contact substeps to the default tolerance."""
    from seispound.motion.catalogue import bundled_path

    folder.mkdir(parents=True, exist_ok=True)
    model = MODEL.format(dt=DT, duration=DURATION, substeps=SUBSTEPS, record=Path(bundled_path(RECORDS[0])).as_posix())
    if not substeps:
        model = re.sub(r"(?m)^contact_substeps = .*\n", "", model)
    (folder / "pair.toml").write_text(model, encoding="utf-8")
    ng, ns = shape_for(runs)
    path = folder / "study.toml"
    path.write_text(STUDY.format(records=json.dumps(RECORDS), laws=json.dumps([l for l, _ in LAWS]),
                                 stiff=json.dumps([k for _, k in LAWS]), nr=len(RECORDS), nl=len(LAWS), ng=ng,
                                 ns=ns), encoding="utf-8")
    return path


def substeps_check(folder: Path, runs: int, workers: int) -> dict:
    """The study's peaks at 8, 16 and 32 contact substeps against 256, on a sample of its cube.

    Every record and law, gaps of 4, 10, 20, 50 and 100 mm, A's storey stiffness at both ends and the
    middle of its range (a smoke run: 10 and 50 mm, the middle stiffness).  Returns, per substep count and
    quantity, the largest and the median relative difference from 256 substeps (the largest pounding force
    where the reference pounds).
    """
    import numpy as np

    from seispound.study import load_study, run_study
    from seispound.study.query import open_study

    gaps, stiffness = ([0.004, 0.01, 0.02, 0.05, 0.1], [0.75e8, 1.5e8, 3.0e8]) if runs >= 1000 else \
        ([0.01, 0.05], [1.5e8])
    path = folder / "substeps_check.toml"
    path.write_text(CHECK.format(records=json.dumps(RECORDS), laws=json.dumps([l for l, _ in LAWS]),
                                 stiff=json.dumps([k for _, k in LAWS]), gaps=json.dumps(gaps),
                                 stiffness=json.dumps(stiffness), check=json.dumps(list(CHECK_SUBSTEPS))),
                    encoding="utf-8")
    study = load_study(path)
    out = folder / "substeps_check.h5"
    res = run_study(study, out, scheduler="local", workers=workers, progress=False, snapshot=0, overwrite=True)
    rows = {}
    with open_study(out) as ds:
        ref = ds.sel(substeps=CHECK_SUBSTEPS[-1]).load()
        for n in CHECK_SUBSTEPS[:-1]:
            x = ds.sel(substeps=n).load()
            for v in CHECKED:
                keep = (ref[v] > 0) & (ref.total_impacts > 0 if v == "max_pounding_force" else True)
                err = np.abs(x[v] / ref[v] - 1).where(keep).values
                rows.setdefault(str(n), {})[v] = {"max": float(np.nanmax(err)), "median": float(np.nanmedian(err))}
    return dict(runs=study.n_runs, done=res["done"], reference_substeps=CHECK_SUBSTEPS[-1], gaps=gaps,
                stiffness_A=stiffness, errors=rows)


def single_run(study, repeat: int = 201) -> dict:
    """Median and mean time of one run in this process (``repeat`` runs spread over the study, twins computed
    outside), the contact substeps they ran with (count of runs per number), and a journal frame's size."""
    from seispound.study.worker import run_one, twin_task

    idx = list(range(0, study.n_runs, max(1, study.n_runs // repeat)))[:repeat]
    twins, times, impacts, substeps = {}, [], [], {}
    r = run_one(study, idx[0], twin_task(study, idx[0]))  # numba's cache, the record reader
    t_twin = []
    for i in idx:
        key = study.twin_key(i)
        if key not in twins:
            t0 = time.perf_counter()
            twins[key] = twin_task(study, i)
            t_twin.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        r = run_one(study, i, twins[key])
        times.append(time.perf_counter() - t0)
        impacts.append(r["total_impacts"])
        substeps[r["contact_substeps"]] = substeps.get(r["contact_substeps"], 0) + 1
    frame = len(pickle.dumps(r, protocol=pickle.HIGHEST_PROTOCOL)) + 16  # journal: 16-byte frame head
    return dict(run_s=statistics.median(times), run_mean_s=statistics.mean(times), twin_s=statistics.median(t_twin),
                runs_timed=len(times), impacts_median=statistics.median(impacts),
                substeps={str(k): v for k, v in sorted(substeps.items())}, frame_bytes=frame), r


def store_rewrite(study, template: dict, folder: Path) -> float:
    """Seconds to rebuild the store from a journal of every run (what each snapshot and the end do)."""
    from seispound.study.journal import Journal
    from seispound.study.store import write_store

    out = folder / "rewrite.h5"
    journal = Journal(out, study.hash()).open()
    try:
        for i in range(study.n_runs):
            journal.append(dict(template, index=i))
        journal.sync()
        t0 = time.perf_counter()
        write_store(study, journal.records, out)
        return time.perf_counter() - t0
    finally:
        journal.remove()
        out.unlink(missing_ok=True)


# the study command, in a process that reports its own and its workers' peak RSS when it exits
_CHILD = """
import json, resource, sys
from seispound.cli import main
if __name__ == "__main__":
    rc = main(sys.argv[2:])
    me, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(sys.argv[1], "w") as fh:
        json.dump({"rc": rc, "main_mb": me.ru_maxrss / 1024,
                   "main_cpu_s": me.ru_utime + me.ru_stime, "workers_cpu_s": kids.ru_utime + kids.ru_stime}, fh)
    sys.exit(rc)
"""


def _hwm_mb(pid: int) -> float:
    try:
        with open(f"/proc/{pid}/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def _group(pgid: int, live: bool = False) -> list[int]:
    """The processes of group ``pgid`` (``live``: leaving out zombies)."""
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                if os.getpgid(int(d)) != pgid:
                    continue
                if live:
                    with open(f"/proc/{d}/stat") as fh:
                        if fh.read().rsplit(")", 1)[1].split()[0] == "Z":
                            continue
                out.append(int(d))
            except OSError:
                pass
    return out


def _left(pgid: int, timeout: float = 10.0) -> list[int]:
    """Live processes of the group once they had ``timeout`` seconds to die."""
    t0 = time.monotonic()
    while (left := _group(pgid, live=True)) and time.monotonic() - t0 < timeout:
        time.sleep(0.05)
    return left


class StudyProcess:
    """``seispound study`` in its own process group, its memory sampled from /proc."""

    def __init__(self, folder: Path, study: Path, out: Path, workers: int, scheduler: str | None = None):
        self.rusage = folder / f"rusage-{out.stem}-{time.monotonic_ns()}.json"
        script = folder / "study_child.py"
        script.write_text(_CHILD)
        self.cmd = [sys.executable, str(script), str(self.rusage), "study", str(study), "-o", str(out)]
        self.cmd += ["--workers", str(workers)] if scheduler is None else ["--scheduler", scheduler]
        self.peak, self.samples, self.exe = {}, {}, {}  # pid -> largest VmHWM seen [MB], samples, executable
        self.t0 = time.perf_counter()
        self.proc = subprocess.Popen(self.cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                     start_new_session=True)
        self._stop = threading.Event()
        self._sampler = threading.Thread(target=self._sample, daemon=True)
        self._sampler.start()

    def _sample(self):
        exe = {}
        while not self._stop.is_set():
            for pid in _group(self.proc.pid):
                try:
                    exe.setdefault(pid, os.readlink(f"/proc/{pid}/exe"))
                except OSError:
                    continue
                self.peak[pid] = max(self.peak.get(pid, 0.0), _hwm_mb(pid))
                self.samples[pid] = self.samples.get(pid, 0) + 1
            self.exe = exe
            time.sleep(0.1)

    def _worker_peak(self) -> float:
        """The largest VmHWM of the workers: Python processes of the group other than the study process,
        seen in two samples at least (not a helper forked to exec a program, such as obspy's import-time
        ``git rev-parse``, whose RUSAGE_CHILDREN peak is the study process's size when it forked)."""
        main_exe = self.exe.get(self.proc.pid)
        return max((v for p, v in self.peak.items() if p != self.proc.pid and self.samples.get(p, 0) >= 2
                    and self.exe.get(p) == main_exe), default=0.0)

    def kill(self) -> None:
        os.killpg(self.proc.pid, signal.SIGKILL)  # the study process and its workers, no clean-up

    def wait(self) -> dict:
        out, err = self.proc.communicate()
        wall = time.perf_counter() - self.t0
        self._stop.set()
        self._sampler.join()
        main = self.peak.get(self.proc.pid, 0.0)
        r = dict(rc=self.proc.returncode, wall_s=wall, stdout=out, stderr=err, maxrss_main_mb=main,
                 maxrss_worker_mb=self._worker_peak(), survivors=_left(self.proc.pid))
        if self.rusage.exists():  # exited normally: getrusage of the study process, exact
            ru = json.loads(self.rusage.read_text())
            r["maxrss_main_mb"] = max(main, ru["main_mb"])
            r["main_cpu_s"], r["workers_cpu_s"] = ru["main_cpu_s"], ru["workers_cpu_s"]
        m = re.search(r"(\d+) runs in ([0-9.]+) s", out)
        if m:
            r["ran"], r["run_study_s"] = int(m.group(1)), float(m.group(2))
        return r


def check_store(out: Path, n_runs: int) -> dict:
    import numpy as np
    import xarray as xr

    from seispound.study.journal import journal_path

    with xr.open_dataset(out, engine="h5netcdf") as ds:
        s = np.asarray(ds.status)
        impacts = np.asarray(ds.total_impacts)
    return dict(done=int((s == 1).sum()), failed=int((s == 0).sum()), pending=int((s < 0).sum()),
                pounding=int((impacts > 0).sum()), impacts_median_pounding=float(np.median(impacts[impacts > 0]))
                if (impacts > 0).any() else 0.0,
                complete=bool((s == 1).sum() == n_runs), journal_left=journal_path(out).exists(),
                tmp_left=bool(list(out.parent.glob(f".{out.name}.tmp-*"))), store_bytes=out.stat().st_size)


def run_uninterrupted(folder, study_file, out, workers) -> dict:
    out.unlink(missing_ok=True)
    r = StudyProcess(folder, study_file, out, workers).wait()
    if r["rc"] != 0:
        raise RuntimeError(f"the study failed: {r['stderr'][-2000:]}")
    return r


# a dask.distributed scheduler and its workers on loopback, standing in for a cluster
_CLUSTER = """
import sys
from dask.distributed import Client, LocalCluster
if __name__ == "__main__":
    cluster = LocalCluster(n_workers=int(sys.argv[1]), threads_per_worker=1, processes=True, host="127.0.0.1",
                           dashboard_address=None)
    client = Client(cluster)
    client.wait_for_workers(int(sys.argv[1]))
    print(cluster.scheduler_address, flush=True)
    sys.stdin.readline()  # the study is done: which worker ran how many tasks
    print(sorted(client.run(lambda dask_worker: dask_worker.state.executed_count).values()), flush=True)
    client.close()
    cluster.close()
"""


def run_on_cluster(folder, study_file, out, n_workers) -> dict:
    """The same study file against the address of a dask.distributed scheduler with ``n_workers`` workers."""
    out.unlink(missing_ok=True)
    script = folder / "cluster.py"
    script.write_text(_CLUSTER)
    cluster = subprocess.Popen([sys.executable, str(script), str(n_workers)], stdin=subprocess.PIPE,
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        address = cluster.stdout.readline().strip()
        if not address.startswith("tcp://"):
            raise RuntimeError(f"the LocalCluster did not start: {address!r}")
        r = StudyProcess(folder, study_file, out, 0, scheduler=address).wait()
        if r["rc"] != 0:
            raise RuntimeError(f"the study on {address} failed: {r['stderr'][-2000:]}")
        cluster.stdin.write("done\n")
        cluster.stdin.flush()
        tasks = json.loads(cluster.stdout.readline())
    finally:
        cluster.stdin.close()
        cluster.wait(timeout=120)
    return dict(wall_s=r["wall_s"], ran=r.get("ran"), workers=n_workers, tasks_per_worker=tasks,
                maxrss_main_mb=r["maxrss_main_mb"])


def run_killed_and_resumed(folder, study, study_file, out, workers, kill_at, frame_bytes) -> dict:
    """Kill -9 (the whole process group) once the journal holds ``kill_at`` of the runs; rerun the command."""
    from seispound.study.journal import Journal, journal_path

    out.unlink(missing_ok=True)
    journal_path(out).unlink(missing_ok=True)
    target = int(kill_at * study.n_runs)
    jpath = journal_path(out)
    sp = StudyProcess(folder, study_file, out, workers)
    while True:
        size = jpath.stat().st_size if jpath.exists() else 0
        if size >= target * frame_bytes:
            sp.kill()
            break
        if sp.proc.poll() is not None:
            raise RuntimeError("the study ended before it could be killed: lower --kill-at")
        time.sleep(0.02)
    first = sp.wait()
    h = study.hash()
    stored = sum(1 for _ in Journal(out, h).records())
    snapshot = out.exists()
    second = StudyProcess(folder, study_file, out, workers).wait()
    if second["rc"] != 0:
        raise RuntimeError(f"the resumed study failed: {second['stderr'][-2000:]}")
    return dict(killed=dict(rc=first["rc"], wall_s=first["wall_s"], maxrss_main_mb=first["maxrss_main_mb"],
                            maxrss_worker_mb=first["maxrss_worker_mb"], survivors=first["survivors"]),
                stored_at_kill=stored, snapshot_store_at_kill=snapshot,
                resumed=dict(rc=second["rc"], wall_s=second["wall_s"], ran=second.get("ran"),
                             main_cpu_s=second.get("main_cpu_s"), workers_cpu_s=second.get("workers_cpu_s"),
                             maxrss_main_mb=second["maxrss_main_mb"], maxrss_worker_mb=second["maxrss_worker_mb"]),
                ran_twice=None if second.get("ran") is None else second["ran"] - (study.n_runs - stored))


def identical(a: Path, b: Path) -> bool:
    import xarray as xr

    with xr.open_dataset(a, engine="h5netcdf") as da, xr.open_dataset(b, engine="h5netcdf") as db:
        return bool(da.load().identical(db.load()))


def query_commands(store: Path, folder: Path) -> dict:
    s = str(store)
    return {
        "overview": ["query", s],
        "max amplification per law and gap size": ["query", s, "--reduce", "record,stiffness_A=max"],
        "safe gap per law and stiffness": ["query", s, "--reduce", "record=q90", "--where", "<1.2",
                                           "--smallest", "gap_size", "--strict"],
        "one record's runs, as CSV": ["query", s, "--sel", "record=elcentro_180",
                                      "-o", str(folder / "elcentro_180.csv")],
    }


def python_queries() -> dict:
    """The Python equivalents of the commands (:mod:`seispound.study.query` on an open store)."""
    from seispound.study import query as q

    def overview(ds):
        return q.overview(ds)

    def amp(ds):
        return q.to_table(q.reduce(q.done(ds, "max_amplification"), ["record", "stiffness_A"], "max"))

    def safe(ds):
        return q.to_table(q.smallest_passing(ds, "gap_size", 1.2, over="record", q=0.9))

    def one_record(ds):
        return q.to_csv(q.select(q.done(ds, "max_amplification"), {"record": "elcentro_180"}))

    return {"overview": overview, "max amplification per law and gap size": amp,
            "safe gap per law and stiffness": safe, "one record's runs, as CSV": one_record}


def time_queries(store: Path, folder: Path, repeat: int) -> dict:
    from seispound.study import query as q

    seispound = Path(sys.executable).parent / "seispound"
    out = {}
    for name, args in query_commands(store, folder).items():
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            res = subprocess.run([str(seispound), *args], capture_output=True, text=True)
            times.append(time.perf_counter() - t0)
            if res.returncode != 0:
                raise RuntimeError(f"seispound {' '.join(args)}: {res.stderr}")
        out[name] = {"cli_s": statistics.median(times), "command": "seispound " + " ".join(args)}
    q.open_study(store).close()  # the first open imports the netCDF reader
    opens = []
    for name, fn in python_queries().items():
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            with q.open_study(store) as ds:  # each time from the file: nothing cached between repeats
                t1 = time.perf_counter()
                fn(ds)
                times.append(time.perf_counter() - t1)
            opens.append(t1 - t0)
        out[name]["python_s"] = statistics.median(times)
    out["open_study_s"] = statistics.median(opens)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.study_scale", description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100_000, help="about this many runs (default 100000)")
    ap.add_argument("--workers", type=int, default=os.cpu_count(), help="worker processes (default: the CPUs)")
    ap.add_argument("--kill-at", type=float, default=0.4,
                    help="kill -9 the second study once its journal holds this fraction of the runs (default 0.4)")
    ap.add_argument("--cluster-workers", type=int, default=3,
                    help="run the study file once more against a dask.distributed LocalCluster of this many "
                         "workers, by its tcp:// address (default 3; 0: skip)")
    ap.add_argument("--repeat", type=int, default=5, help="times each query is timed (median; default 5)")
    ap.add_argument("--folder", help="where the study, its stores and outputs go (default: a new temporary folder)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    args = ap.parse_args(argv)
    if not 0 < args.kill_at < 1:
        ap.error("--kill-at must be between 0 and 1")
    from seispound.study import load_study

    folder = Path(args.folder) if args.folder else Path(tempfile.mkdtemp(prefix="seispound-study-scale-"))
    study_file = write_study(folder, args.runs)
    study = load_study(study_file)
    n = study.n_runs
    print(f"study: {n} runs = {' x '.join(map(str, study.shape))} ({', '.join(study.run_dims)}); "
          f"{study.shape[0] * study.shape[3]} no-pounding twins; {args.workers} workers; {DURATION:g} s at "
          f"dt = {DT:g} s, {SUBSTEPS} contact substeps; folder {folder}", flush=True)
    one, template = single_run(study)
    print(f"one run ({one['runs_timed']} spread over the study, this process): median {one['run_s'] * 1e3:.2f} ms, "
          f"mean {one['run_mean_s'] * 1e3:.2f} ms (a no-pounding twin {one['twin_s'] * 1e3:.2f} ms; median impacts "
          f"per run {one['impacts_median']:g})", flush=True)
    default, _ = single_run(load_study(write_study(folder / "default_tolerance", args.runs, substeps=False)))
    one["run_default_tolerance_s"], one["run_mean_default_tolerance_s"] = default["run_s"], default["run_mean_s"]
    one["substeps_default_tolerance"] = default["substeps"]
    chosen = ", ".join(f"{k} for {v}" for k, v in default["substeps"].items())
    print(f"the same runs without contact_substeps (the default tolerance chooses them and checks each run "
          f"that pounds): median {default['run_s'] * 1e3:.2f} ms, mean {default['run_mean_s'] * 1e3:.2f} ms; "
          f"substeps chosen: {chosen} runs", flush=True)

    check = substeps_check(folder, args.runs, args.workers)
    print(f"contact substeps against {check['reference_substeps']} on {check['runs']} runs "
          f"(largest relative difference of {', '.join(CHECKED)}):", flush=True)
    for n_, errs in check["errors"].items():
        largest = ", ".join(f"{e['max'] * 100:.2f} %" for e in errs.values())
        medians = ", ".join(f"{e['median'] * 100:.3f} %" for e in errs.values())
        print(f"  {n_:>3} substeps: {largest} (medians {medians})", flush=True)

    rewrite = store_rewrite(study, template, folder)
    print(f"the store rebuilt from a journal of all {n} runs (each snapshot, and the end): {rewrite:.1f} s",
          flush=True)

    ref = folder / "uninterrupted.h5"
    a = run_uninterrupted(folder, study_file, ref, args.workers)
    ca = check_store(ref, n)
    print(f"uninterrupted: wall {a['wall_s']:.1f} s (run_study {a['run_study_s']:.1f} s), "
          f"{n / a['wall_s']:.0f} runs/s; peak RSS main {a['maxrss_main_mb']:.0f} MB, largest worker "
          f"{a['maxrss_worker_mb']:.0f} MB; store {ca['store_bytes'] / 1e6:.1f} MB; {ca['done']} done, "
          f"{ca['failed']} failed; {ca['pounding']} runs pound (median {ca['impacts_median_pounding']:g} impacts)",
          flush=True)
    print(f"  CPU: main {a['main_cpu_s']:.1f} s, workers {a['workers_cpu_s']:.1f} s "
          f"({a['workers_cpu_s'] / n * 1e3:.2f} ms per run, twins included); workers' CPU / (workers x wall) = "
          f"{a['workers_cpu_s'] / args.workers / a['wall_s']:.2f}", flush=True)

    res = folder / "killed.h5"
    k = run_killed_and_resumed(folder, study, study_file, res, args.workers, args.kill_at, one["frame_bytes"])
    ck = check_store(res, n)
    same = identical(ref, res)
    wall_kr = k["killed"]["wall_s"] + k["resumed"]["wall_s"]
    print(f"kill -9 at {k['stored_at_kill']} runs stored ({k['stored_at_kill'] / n:.0%}, after "
          f"{k['killed']['wall_s']:.1f} s; a snapshot store {'was' if k['snapshot_store_at_kill'] else 'was not'} "
          f"there; processes left {len(k['killed']['survivors'])}); resume ran {k['resumed']['ran']} runs in "
          f"{k['resumed']['wall_s']:.1f} s (computed twice: {k['ran_twice']}); killed + resumed wall {wall_kr:.1f} s",
          flush=True)
    print(f"resumed store: {ck['done']} done, {ck['failed']} failed, {ck['pending']} pending, journal left: "
          f"{ck['journal_left']}, temporary files left: {ck['tmp_left']}; identical to the uninterrupted store: "
          f"{same}", flush=True)

    cl = None
    if args.cluster_workers:
        cl = run_on_cluster(folder, study_file, folder / "cluster.h5", args.cluster_workers)
        cl["store"] = check_store(folder / "cluster.h5", n)
        cl["identical_to_uninterrupted"] = identical(ref, folder / "cluster.h5")
        print(f"on a dask.distributed scheduler's address (LocalCluster of {args.cluster_workers} workers, tasks per "
              f"worker {cl['tasks_per_worker']}): wall {cl['wall_s']:.1f} s, {n / cl['wall_s']:.0f} runs/s; "
              f"{cl['store']['done']} done, {cl['store']['failed']} failed; identical to the local scheduler's "
              f"store: {cl['identical_to_uninterrupted']}", flush=True)

    qt = time_queries(ref, folder, args.repeat)
    print(f"queries on the {n}-run store, median of {args.repeat} (command: process start to exit; Python: on a store "
          f"opened by open_study, which takes {qt['open_study_s'] * 1e3:.1f} ms):")
    for name, v in qt.items():
        if isinstance(v, dict):
            py = f", Python {v['python_s'] * 1e3:.1f} ms" if "python_s" in v else ""
            print(f"  {name}: command {v['cli_s']:.2f} s{py}\n    {v['command'].replace(str(folder) + '/', '')}")
    ok = ca["complete"] and ck["complete"] and same and not ck["journal_left"] and k["ran_twice"] == 0 and \
        (cl is None or (cl["store"]["complete"] and cl["identical_to_uninterrupted"]))
    if args.json:
        drop = ("stdout", "stderr")
        Path(args.json).write_text(json.dumps(dict(
            runs=n, shape=list(study.shape), run_dims=list(study.run_dims), twins=study.shape[0] * study.shape[3],
            workers=args.workers, duration_s=DURATION, dt_s=DT, contact_substeps=SUBSTEPS, single_run=one,
            store_rewrite_s=rewrite, substeps_check=check,
            uninterrupted=dict({k_: v for k_, v in a.items() if k_ not in drop}, runs_per_s=n / a["wall_s"],
                               store=ca),
            kill_and_resume=dict(k, store=ck, identical_to_uninterrupted=same, wall_s=wall_kr),
            cluster=cl, queries=qt, ok=ok), indent=1))
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
