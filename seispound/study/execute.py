"""Run a study: tasks on dask (local processes, a LocalCluster, an existing cluster) or in-process.

Runs that share a no-pounding twin (same record and structure; only the gaps
or the contact law differ) form a group: the twin is one task, and the group's
runs are split into chunks that wait for it.  Finished chunks stream into the
journal (:mod:`.journal`) as they complete; the HDF5 store is rebuilt from the
journal every ``snapshot`` seconds and at the end, when the journal is removed.
Rerunning the same command after an interruption skips every stored run.
"""

from __future__ import annotations

import logging
import math
import os
import sys
import time
from collections import OrderedDict
from pathlib import Path

from ..errors import InputError
from .journal import Journal, journal_path
from .schema import STATUS_DONE, STATUS_FAILED
from .store import write_store
from .worker import chunk_task, run_one, twin_task

__all__ = ["run_study", "plan", "default_scheduler"]


def plan(study, todo, n_workers: int, chunk: int | None = None) -> list:
    """Group the runs ``todo`` by twin and split each group into chunks.

    Returns [(first index of the group, [chunks of indices])].  Chunks are at
    most ``chunk`` runs; by default small enough to give every worker about
    sixteen chunks (so that the last ones do not hold the study up) and at most 10.
    """
    groups: OrderedDict = OrderedDict()
    for i in todo:
        groups.setdefault(study.twin_key(i), []).append(i)
    if chunk is None:
        chunk = max(1, min(10, math.ceil(len(todo) / max(1, 16 * n_workers))))
    out = []
    for runs in groups.values():
        out.append((runs[0], [runs[k:k + chunk] for k in range(0, len(runs), chunk)]))
    return out


class Progress:
    """done/total, runs per second and time left, on one line of stderr (rewritten on a terminal)."""

    def __init__(self, total: int, already: int, enabled: bool, stream=None):
        self.total, self.start_done, self.done, self.failed = total, already, already, 0
        self.enabled = enabled
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.t0 = time.perf_counter()
        self.last = 0.0

    def update(self, n_done: int, n_failed: int, force: bool = False) -> None:
        self.done += n_done
        self.failed += n_failed
        if not self.enabled:
            return
        now = time.perf_counter()
        if not force and now - self.last < (0.2 if self.tty else 5.0):
            return
        self.last = now
        rate = (self.done - self.start_done) / max(now - self.t0, 1e-9)
        left = (self.total - self.done) / rate if rate > 0 else float("nan")
        line = (f"study: {self.done}/{self.total} runs ({self.failed} failed) | {rate:.1f} runs/s | "
                f"{_fmt_time(left)} left")
        if self.tty:
            print("\r" + line.ljust(78), end="", file=self.stream, flush=True)
        else:
            print(line, file=self.stream, flush=True)

    def close(self) -> None:
        if self.enabled and self.tty:
            print(file=self.stream, flush=True)


def _fmt_time(s: float) -> str:
    if not math.isfinite(s):
        return "?"
    if s < 60:
        return f"{s:.0f} s"
    if s < 3600:
        return f"{s / 60:.1f} min"
    return f"{s / 3600:.1f} h"


def run_study(study, out, *, scheduler: str | None = None, workers: int | None = None, chunk: int | None = None,
              progress: bool = True, snapshot: float = 30.0, overwrite: bool = False, force: bool = False) -> dict:
    """Run every run of ``study`` not yet in the store ``out``; write the store; return counts.

    Parameters
    ----------
    study : Study
    out : path
        The store (.h5).  Its journal ``out.journal`` holds finished runs until
        the study is complete.
    scheduler : str, optional
        "local" (dask's local multiprocessing scheduler, ``workers``
        processes forked from this one; the default when dask is installed,
        else "serial"), "cluster" (a dask.distributed
        LocalCluster of ``workers`` processes, one thread each),
        "tcp://HOST:PORT" (an existing dask.distributed scheduler: the way to
        more machines), or "serial" (in this process, no dask).
    workers : int, optional
        Worker processes for "local" and "cluster" (default: the CPU count).
    chunk : int, optional
        Runs per task (default: see :func:`plan`).
    progress : bool
        Print progress to stderr.
    snapshot : float
        Seconds between rewrites of the store while the study runs (0: only at the end).
    overwrite : bool
        Discard a store or journal of another study at ``out`` instead of refusing.
    force : bool
        Run records that a plausibility guard refuses (a PGA above 3 g: see
        :func:`check_records`).

    Returns
    -------
    dict with done, failed, pending, ran (runs computed now), seconds.
    """
    out = Path(out)
    if scheduler is None:
        scheduler = default_scheduler()
    if out.suffix.lower() not in (".h5", ".hdf5", ".nc"):
        raise InputError("the store must end in .h5, .hdf5 or .nc", file=out, key="-o")
    from .._output import check_writable

    check_writable(out, key="-o")  # the store and, next to it, the journal: before any run
    check_writable(journal_path(out), key="-o (its journal)")
    check_records(study, force=force, progress=progress)
    for stale in out.parent.glob(f".{out.name}.tmp-*"):  # left by a kill during a store rewrite
        stale.unlink(missing_ok=True)
    h = study.hash()
    jpath = journal_path(out)
    if overwrite:
        jpath.unlink(missing_ok=True)
        out.unlink(missing_ok=True)
    if out.exists() and not jpath.exists():
        existing = _store_hash(out)
        if existing != h:
            raise InputError("holds another study (different model, records, axes or version); "
                             "choose another output file or pass --overwrite", file=out, key="-o")
        counts = _store_counts(out)
        if counts["pending"] == 0:
            return dict(counts, ran=0, seconds=0.0)
        # an incomplete store without its journal (deleted by hand): its runs are lost, rerun them
    created = not jpath.exists()
    journal = Journal(out, h).open()
    try:
        return _execute(study, out, journal, scheduler, workers, chunk, progress, snapshot)
    except InputError:
        if created and not journal.done:  # refused before any run (scheduler ...): leave nothing behind
            journal.remove()
        raise
    finally:
        journal.close()


def check_records(study, *, force: bool = False, progress: bool = True) -> None:
    """Refuse a study one of whose records a plausibility guard refuses (PGA above 3 g), unless ``force``.

    Each record is read and prepared once, with the base model's settings, in
    this process (the prepared records are cached, and forked workers inherit
    the cache).  A record that cannot be read is left to its runs, which fail
    with its error while the study goes on.  Other findings go to stderr.
    """
    import warnings

    from ..plausibility import PlausibilityWarning, check_before_run
    from ..simulation import prepare_ground_motion

    per_record = math.prod(study.shape[1:])
    for r, rec in enumerate(study.records):
        model = study.model_for(r * per_record)
        try:
            ag, prov = prepare_ground_motion(model)
        except InputError:
            continue
        for f in check_before_run(model, prov, ag):
            if f.code in ("coarse_step", "floor_levels") and r > 0:
                continue  # the structure's findings, said once
            if f.refuse and not force:
                raise InputError(f"record {rec.name} ({rec.file.name}): {f.message}", file=study.path,
                                 key="records")
            if progress:
                print(f"seispound: warning: record {rec.name}: {f.message}", file=sys.stderr)
            else:
                warnings.warn(f"record {rec.name}: {f.message}", PlausibilityWarning, stacklevel=3)


def default_scheduler() -> str:
    """"local" (every core, through dask) when dask is installed, else "serial"."""
    import importlib.util

    return "local" if importlib.util.find_spec("dask") else "serial"


def _execute(study, out, journal, scheduler, workers, chunk, progress, snapshot) -> dict:
    t0 = time.perf_counter()
    todo = [i for i in range(study.n_runs) if i not in journal.done]
    already = study.n_runs - len(todo)
    n_failed0 = sum(1 for s in journal.done.values() if s == STATUS_FAILED)
    prog = Progress(study.n_runs, already, progress)
    prog.failed = n_failed0
    state = {"last_snapshot": time.perf_counter()}
    stop = _StopOnInterrupt()

    def collect(results):
        nd = nf = 0
        for r in results:
            journal.append(r)
            nd += 1
            nf += r["status"] == STATUS_FAILED
        prog.update(nd, nf)
        if snapshot and time.perf_counter() - state["last_snapshot"] >= snapshot:
            journal.sync()
            write_store(study, journal.records, out)
            state["last_snapshot"] = time.perf_counter()
        stop.check()

    try:
        with stop:
            if todo:
                if scheduler == "serial":
                    _run_serial(study, todo, chunk, collect)
                elif scheduler == "local":
                    _run_local(study, todo, workers, chunk, collect)
                else:
                    _run_distributed(study, todo, scheduler, workers, chunk, collect)
    except KeyboardInterrupt:
        prog.close()
        journal.sync()
        write_store(study, journal.records, out)
        raise
    prog.update(0, 0, force=True)
    prog.close()
    journal.sync()
    counts = write_store(study, journal.records, out)
    if counts["pending"] == 0:
        journal.remove()  # the store is complete: it alone is the result now
    return dict(counts, ran=len(todo), seconds=time.perf_counter() - t0)


class _StopOnInterrupt:
    """Ctrl-C (SIGINT) while a study runs: finish collecting what is done, then stop.

    The handler only raises a flag, checked after each collected result, so
    that the interrupt does not depend on a KeyboardInterrupt finding its way
    out of library code (one was lost once in CI: the study ran to its end).
    A second Ctrl-C interrupts at once.  Outside the main thread nothing is
    installed and Python's own handling applies.
    """

    def __init__(self):
        self.requested = False
        self._previous = None

    def __enter__(self):
        import signal
        import threading

        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._handler)
        return self

    def _handler(self, signum, frame):
        import signal

        self.requested = True
        signal.signal(signal.SIGINT, signal.default_int_handler)  # a second Ctrl-C: at once

    def check(self) -> None:
        if self.requested:
            raise KeyboardInterrupt

    def __exit__(self, *exc):
        import signal

        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
        return False


def _ignore_sigint() -> None:
    """Pool workers leave Ctrl-C to the main process, which stops them after their task."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run_serial(study, todo, chunk, collect) -> None:
    for first, chunks in plan(study, todo, 1, chunk):
        twin = twin_task(study, first)
        for c in chunks:
            for i in c:  # run by run: an interrupt waits for one run at most
                collect([run_one(study, i, twin)])


def _run_local(study, todo, workers, chunk, collect) -> None:
    """dask's local multiprocessing scheduler on a pool of forked workers.

    The workers are forked from this process after it has loaded the compiled
    kernel and read a record, so they start in milliseconds with everything
    imported (spawned workers would each spend seconds importing and loading
    numba's cache).  Finished chunks are collected as they complete (a posttask
    callback), and dropped from the scheduler's cache at once so that memory
    does not grow with the number of runs.
    """
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    try:
        from dask.callbacks import Callback
        from dask.multiprocessing import get as mp_get
    except ImportError:
        raise InputError("dask is needed: pip install 'seispound[dask]' (or use --scheduler serial)",
                         key="--scheduler") from None
    n = workers or os.cpu_count() or 1
    groups = plan(study, todo, n, chunk)
    dsk, keys = {}, []
    for g, (first, chunks) in enumerate(groups):
        # the first twin here: it warms this process (kernel, record reader) before the fork
        twin = twin_task(study, first) if g == 0 else (twin_task, study, first)
        tkey = f"twin-{g}"
        dsk[tkey] = twin
        for k, c in enumerate(chunks):
            key = f"chunk-{g}-{k}"
            dsk[key] = (chunk_task, study, c, tkey)
            keys.append(key)

    prefetch = []

    def posttask(key, result, dsk_, state, worker_id):
        if not prefetch:  # the workers are forked by now: a thread is safe
            prefetch.append(_prefetch_store(study))
        if key.startswith("chunk-"):
            collect(result)
            state["cache"][key] = None  # collected: do not keep it until the end

    try:
        ctx = multiprocessing.get_context("fork")
    except ValueError:  # pragma: no cover - no fork on this platform
        ctx = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(n, mp_context=ctx, initializer=_ignore_sigint)
    try:
        with Callback(posttask=posttask):
            mp_get(dsk, keys, num_workers=n, pool=pool, chunksize=1, optimize_graph=False)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        for t in prefetch:
            t.join()


def _prefetch_store(study):
    """Import the store writer's libraries and read the records' provenance in a thread.

    This process would otherwise wait idle on its workers and then spend a
    second or more on these at the end, alone; a thread does it meanwhile.
    """
    import threading

    def work():
        try:
            from .store import prefetch

            prefetch(study)
        except Exception:  # only a head start: write_store does (and reports) it all again
            pass

    t = threading.Thread(target=work, name="seispound-store-prefetch", daemon=True)
    t.start()
    return t


def _run_distributed(study, todo, scheduler, workers, chunk, collect) -> None:
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError("dask.distributed is needed: pip install 'seispound[dask]' "
                         "(or use --scheduler serial)", key="--scheduler") from None
    cluster = None
    if scheduler == "cluster":
        n = workers or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR)
        client = Client(cluster)
    elif scheduler.startswith("tcp://") or scheduler.startswith("tls://"):
        try:
            client = Client(scheduler, timeout=10)
        except OSError as exc:
            raise InputError(f"cannot reach the dask scheduler ({exc})", key="--scheduler") from None
        n = max(1, len(client.scheduler_info().get("workers", {})))
    else:
        raise InputError(f'must be "local", "cluster", "serial" or tcp://HOST:PORT, got {scheduler!r}',
                         key="--scheduler")
    prefetch = _prefetch_store(study)  # no fork here: start at once
    try:
        study_f = client.scatter(study, broadcast=True)
        runs_of = {}
        for first, chunks in plan(study, todo, n, chunk):
            twin = client.submit(twin_task, study_f, first, pure=False)
            for c in chunks:
                runs_of[client.submit(chunk_task, study_f, c, twin, pure=False)] = c
        for fut in as_completed(list(runs_of)):
            try:
                results = fut.result()
            except Exception as exc:  # the task itself died (a worker lost twice ...): its runs fail
                msg = " ".join(f"{type(exc).__name__}: {exc}".split())
                results = [{"index": i, "status": STATUS_FAILED, "error": f"task failed: {msg}"}
                           for i in runs_of[fut]]
            collect(results)
            fut.release()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
        prefetch.join()


def _store_hash(path: Path) -> str | None:
    import h5py

    try:
        with h5py.File(path, "r") as f:
            v = f.attrs.get("study_hash")
            return v.decode() if isinstance(v, bytes) else (None if v is None else str(v))
    except OSError:
        return None


def _store_counts(path: Path) -> dict:
    import h5py
    import numpy as np

    with h5py.File(path, "r") as f:
        s = np.asarray(f["status"])
    return {"done": int((s == STATUS_DONE).sum()), "failed": int((s == STATUS_FAILED).sum()),
            "pending": int((s < 0).sum())}
