"""dask: the local scheduler, a LocalCluster started by the CLI, and an existing LocalCluster of two workers
reached over loopback all give the store of the serial run."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest
import xarray as xr

from .conftest import cli

CLUSTER = textwrap.dedent("""
    import sys
    from dask.distributed import LocalCluster
    if __name__ == "__main__":
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None)
        print(cluster.scheduler_address, flush=True)
        sys.stdin.read()  # until the test closes our stdin
        cluster.close()
""")


@pytest.mark.parametrize("scheduler", ["local", "cluster"])
def test_local_scheduler_and_local_cluster_give_the_serial_store(reference_store, tmp_path, scheduler):
    study_file, ref = reference_store
    out = tmp_path / f"{scheduler}.h5"
    res = cli(["study", study_file, "-o", out, "--scheduler", scheduler, "--workers", "2", "--chunk", "2"])
    assert res.returncode == 0, res.stderr
    assert "12 runs in" in res.stdout
    a = xr.open_dataset(ref, engine="h5netcdf").load()
    b = xr.open_dataset(out, engine="h5netcdf").load()
    assert a.identical(b)


def test_existing_cluster_on_loopback_gives_the_local_scheduler_store(reference_store, tmp_path):
    study_file, ref = reference_store
    local = tmp_path / "local.h5"
    assert cli(["study", study_file, "-o", local, "--workers", "2", "-q"]).returncode == 0  # the default: local
    script = tmp_path / "cluster.py"
    script.write_text(CLUSTER)
    proc = subprocess.Popen([sys.executable, str(script)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    try:
        address = proc.stdout.readline().strip()
        assert address.startswith("tcp://127.0.0.1:"), address
        out = tmp_path / "remote.h5"
        res = cli(["study", study_file, "-o", out, "--scheduler", address])
        assert res.returncode == 0, res.stderr
        a = xr.open_dataset(local, engine="h5netcdf").load()
        assert a.identical(xr.open_dataset(ref, engine="h5netcdf").load())
        b = xr.open_dataset(out, engine="h5netcdf").load()
        assert a.identical(b)
    finally:
        proc.stdin.close()
        proc.wait(timeout=60)


def test_unreachable_scheduler_is_one_line_exit_2(reference_store, tmp_path):
    study_file, _ = reference_store
    out = tmp_path / "none.h5"
    res = cli(["study", study_file, "-o", out, "--scheduler", "tcp://127.0.0.1:9"], timeout=120)
    assert res.returncode == 2
    assert res.stderr.count("\n") == 1 and "--scheduler" in res.stderr and "Traceback" not in res.stderr
    assert not out.exists()
