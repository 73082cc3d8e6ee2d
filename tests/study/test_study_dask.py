"""dask: the local scheduler, a LocalCluster started by the CLI, and an existing LocalCluster of three workers
reached over loopback (its tasks spread over several of them) all give the store of the serial run."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest
import xarray as xr

from .conftest import cli

N_WORKERS = 3
CLUSTER = textwrap.dedent(f"""
    import json, sys
    from dask.distributed import Client, LocalCluster
    if __name__ == "__main__":
        cluster = LocalCluster(n_workers={N_WORKERS}, threads_per_worker=1, processes=True, host="127.0.0.1",
                               dashboard_address=None)
        client = Client(cluster)
        client.wait_for_workers({N_WORKERS})
        print(cluster.scheduler_address, flush=True)
        sys.stdin.readline()  # the test's study is done: say which worker ran how many tasks
        counts = client.run(lambda dask_worker: dask_worker.state.executed_count)
        print(json.dumps(counts), flush=True)
        sys.stdin.read()  # until the test closes our stdin
        client.close()
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
        proc.stdin.write("done\n")
        proc.stdin.flush()
        executed = json.loads(proc.stdout.readline())
        assert len(executed) == N_WORKERS
        assert sum(n > 0 for n in executed.values()) >= 2, executed  # the runs went to several workers
        assert sum(executed.values()) == 12 + 2  # 12 chunks of one run (12 runs, 3 workers) and the 2 twins
        a = xr.open_dataset(local, engine="h5netcdf").load()
        assert a.identical(xr.open_dataset(ref, engine="h5netcdf").load())
        b = xr.open_dataset(out, engine="h5netcdf").load()
        assert a.identical(b)  # every variable, coordinate and attribute
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
