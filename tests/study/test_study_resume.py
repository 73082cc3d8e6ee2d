"""Interrupted studies: a real SIGKILL (and a SIGINT) at a random moment, then the same command resumes.

The resumed store must equal the store of an uninterrupted study, and no run
may be computed twice.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time

import pytest
import xarray as xr

from seispound.motion.catalogue import bundled_records
from seispound.study import load_study
from seispound.study.journal import Journal, journal_path

from .conftest import SEISPOUND, cli, write_study

RECORDS = tuple(r["name"] for r in bundled_records())  # the four bundled records
GAPS = (0.005, 0.01, 0.02, 0.04)  # 4 records x 2 laws x 4 gaps = 32 runs


def stored_runs(out, h) -> int:
    return sum(1 for _ in Journal(out, h).records())


def start(study_file, out, scheduler="serial"):
    return subprocess.Popen([str(SEISPOUND), "study", str(study_file), "-o", str(out), "--scheduler", scheduler,
                             "--workers", "2", "--chunk", "1", "--snapshot", "0.1"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)


def wait_for_runs(proc, out, h, n, timeout=120.0):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        if journal_path(out).exists() and stored_runs(out, h) >= n:
            return
        if proc.poll() is not None:
            pytest.fail(f"the study ended before it could be interrupted: {proc.stderr.read()}")
        time.sleep(0.005)
    pytest.fail("no runs stored in time")


@pytest.fixture(scope="module")
def study_and_reference(tmp_path_factory):
    folder = tmp_path_factory.mktemp("kill")
    study_file = write_study(folder, duration=30.0, records=RECORDS, gaps=GAPS)
    ref = folder / "reference.h5"
    res = cli(["study", study_file, "-o", ref, "--scheduler", "serial", "-q"])
    assert res.returncode == 0, res.stderr
    return study_file, xr.open_dataset(ref, engine="h5netcdf").load()


@pytest.mark.parametrize("after, scheduler", [(3, "serial"), (11, "serial"), (5, "local")])
def test_sigkill_then_resume_equals_uninterrupted(study_and_reference, tmp_path, after, scheduler):
    study_file, reference = study_and_reference
    h = load_study(study_file).hash()
    out = tmp_path / "killed.h5"
    proc = start(study_file, out, scheduler)  # local: the forked workers die with it
    wait_for_runs(proc, out, h, after)
    os.killpg(proc.pid, signal.SIGKILL)  # the whole process group, no chance to clean up
    proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    n_before = stored_runs(out, h)
    assert after <= n_before < 32
    if out.exists():  # a snapshot, if one was taken, is a whole file with runs still pending
        snap = xr.open_dataset(out, engine="h5netcdf").load()
        assert int((snap.status == -1).sum()) > 0
    res = cli(["study", study_file, "-o", out, "--scheduler", scheduler, "--workers", "2"])
    assert res.returncode == 0, res.stderr
    ran = int(re.search(r"(\d+) runs in", res.stdout).group(1))
    assert ran == 32 - n_before  # what was stored is not computed again
    assert not journal_path(out).exists()
    assert not list(tmp_path.glob(".killed.h5.tmp-*"))
    resumed = xr.open_dataset(out, engine="h5netcdf").load()
    assert resumed.identical(reference)


@pytest.mark.parametrize("scheduler", ["serial", "local"])
def test_sigint_keeps_the_finished_runs(study_and_reference, tmp_path, scheduler):
    """Ctrl-C reaches every process of the group, at whatever the study is doing (reading a record ...)."""
    study_file, reference = study_and_reference
    h = load_study(study_file).hash()
    out = tmp_path / "interrupted.h5"
    proc = start(study_file, out, scheduler)
    wait_for_runs(proc, out, h, 5)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "rerun the same command to resume" in err
    assert "Traceback" not in err
    snap = xr.open_dataset(out, engine="h5netcdf").load()  # written on the way out
    done = int((snap.status == 1).sum())
    assert 5 <= done < 32
    res = cli(["study", study_file, "-o", out, "--scheduler", "serial", "-q"])
    assert res.returncode == 0, res.stderr
    assert xr.open_dataset(out, engine="h5netcdf").load().identical(reference)


def test_a_torn_journal_frame_is_cut_off(tmp_path):
    j = Journal(tmp_path / "x.h5", "abc").open()
    for i in range(3):
        j.append({"index": i, "status": 1, "error": "", "payload": list(range(100 * i))})
    j.append({"index": 1, "status": 0, "error": "twice"})  # a second result for run 1 is ignored
    j.close()
    path = journal_path(tmp_path / "x.h5")
    whole = path.read_bytes()
    j = Journal(tmp_path / "x.h5", "abc").open()
    j.append({"index": 3, "status": 1, "error": ""})
    j.close()
    torn = path.read_bytes()
    path.write_bytes(torn[:len(whole) + (len(torn) - len(whole)) // 2])  # killed mid-append
    j = Journal(tmp_path / "x.h5", "abc").open()
    assert j.done == {0: 1, 1: 1, 2: 1}
    assert [r["index"] for r in j.records()] == [0, 1, 2]
    assert path.stat().st_size == len(whole)  # the torn frame is gone
    j.append({"index": 3, "status": 1, "error": ""})
    j.close()
    assert [r["index"] for r in Journal(tmp_path / "x.h5", "abc").records()] == [0, 1, 2, 3]


def test_a_journal_of_another_study_is_refused(tmp_path):
    Journal(tmp_path / "x.h5", "abc").open().close()
    with pytest.raises(Exception, match="another study"):
        Journal(tmp_path / "x.h5", "xyz").open()
