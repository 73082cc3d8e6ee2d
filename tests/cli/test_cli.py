"""The ``seispound`` command line: run, laws, --version (run as real subprocesses)."""

from __future__ import annotations

import re
import subprocess
import sys
from importlib.metadata import version as dist_version
from pathlib import Path

import numpy as np
import pytest

import seispound
from tests._models import short_copy as _short_copy

REPO = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
SEISPOUND = BIN / "seispound"
DURATION = 3.0


def short_copy(folder: Path, name="two_buildings.toml", duration=DURATION) -> Path:
    return _short_copy(folder, duration, name)


def run(args, cwd):
    return subprocess.run([str(SEISPOUND), *args], cwd=cwd, capture_output=True, text=True, timeout=120)


_GAP_ROW = re.compile(r"^\s+(\d+)\s+(\S+)\|(\S+)\s+(\d+)\|(\d+)\s+([0-9.]+)\s+(\d+)\s+([0-9.]+)$")
_AMP = re.compile(r"largest displacement amplification \(peak floor displacement with / without pounding\) "
                  r"([0-9.]+) at building (\S+), floor (\d+) \(([0-9.]+) cm with pounding, ([0-9.]+) cm without\)")


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cli")
    model = short_copy(folder)
    (folder / "out").mkdir()
    proc = run(["run", model.name, "-o", "out/x.h5"], cwd=folder)
    return folder, model, proc


def test_run_exits_zero_and_writes_a_readable_result(cli_run):
    folder, model, proc = cli_run
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    out = folder / "out" / "x.h5"
    assert out.is_file()
    # only the result file, no temporary left behind
    assert sorted(p.name for p in (folder / "out").iterdir()) == ["x.h5"]
    ds = seispound.open_result(out)
    assert ds.attrs["schema"] == "seispound-result"
    assert ds.attrs["model_text"] == model.read_text(encoding="utf-8")
    assert float(ds.time[-1]) == pytest.approx(DURATION, abs=1e-12)
    assert ds.sizes["time"] == round(DURATION / 0.005) + 1
    assert list(ds.building.values) == ["A", "B"]
    assert "written to out/x.h5" in proc.stdout


def test_summary_matches_the_dataset(cli_run):
    folder, model, proc = cli_run
    ds = seispound.open_result(folder / "out" / "x.h5")
    lines = proc.stdout.splitlines()
    assert lines[0] == "Two buildings of different height, El Centro 1940, Hd contact"
    ni = ds.sizes["impact"]
    assert lines[1].strip() == (f"2 buildings, 4 gap elements, {ni} impacts, "
                                f"{DURATION:.3g} s at dt = 0.005 s (exact scheme)")
    rows = [m.groups() for m in map(_GAP_ROW.match, lines) if m]
    assert len(rows) == 4 == ds.sizes["gap"]
    counts = [int(r[6]) for r in rows]
    # the printed impact counts are the Dataset's, and they add up to the impact dimension
    assert counts == [int(c) for c in ds.impact_count.values]
    assert sum(counts) == ni
    assert ni > 0  # 3 s of El Centro with 2 cm gaps: the buildings do pound
    for g, r in enumerate(rows):
        assert int(r[0]) == g
        assert (r[1], r[2]) == ("A", "B")
        assert (int(r[3]), int(r[4])) == (g + 1, g + 1)
        assert float(r[5]) == pytest.approx(0.02)
        assert float(r[7]) == pytest.approx(float(ds.peak_pounding_force[g]) / 1e3, abs=0.051)
    amp_lines = [ln for ln in lines if "largest displacement amplification" in ln]
    assert len(amp_lines) == 1
    m = _AMP.search(amp_lines[0])
    assert m, amp_lines[0]
    amp, b, f, pk, pk0 = m.groups()
    a = ds.amplification.values
    ib, jf = np.unravel_index(np.nanargmax(a), a.shape)
    assert (b, int(f)) == (str(ds.building.values[ib]), int(ds.floor.values[jf]))
    assert float(amp) == pytest.approx(np.nanmax(a), abs=5e-4)
    assert float(pk) == pytest.approx(100 * float(ds.peak_displacement[ib, jf]), abs=0.0051)
    assert float(pk0) == pytest.approx(100 * float(ds.peak_displacement_no_pounding[ib, jf]), abs=0.0051)


def test_quiet_run_prints_nothing(tmp_path):
    model = short_copy(tmp_path, duration=0.5)
    proc = run(["run", model.name, "-q", "--no-twin"], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (proc.stdout, proc.stderr) == ("", "")
    ds = seispound.open_result(tmp_path / "two_buildings.h5")  # default output: model name with .h5
    assert bool(ds.amplification.isnull().all())
    assert ds.sizes["time"] == 101


def test_laws_lists_every_law_with_its_stiffness_units():
    proc = run(["laws"], cwd=REPO)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    units = {}
    current = None
    for line in proc.stdout.splitlines():
        if line and not line[0].isspace():
            current = line.split()[0]
            units[current] = None
        m = re.match(r"^\s+stiffness\s+\[([^\]]+)\]", line)
        if m:
            units[current] = m.group(1)
    assert units == {"LVe": "N/m", "MLVe": "N/m", "NIVe": "N/m^1.5", "Hd": "N/m^1.5",
                     "LHC": "N/m", "Hertz": "N/m^1.5", "Hertzdamp": "N/m^1.5", "HC": "N/m^n"}
    assert "seed Eq" in proc.stdout


def test_python_m_version():
    proc = subprocess.run([sys.executable, "-m", "seispound", "--version"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0
    assert proc.stdout.strip() == seispound.__version__ == dist_version("seispound")
    assert re.fullmatch(r"\d+\.\d+\.\d+\S*", proc.stdout.strip())
