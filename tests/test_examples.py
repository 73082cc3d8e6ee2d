"""The bundled examples (``examples/``) run as the README shows and find what they were made to show.

The README's own blocks are run by ``test_documented_commands.py``; here the results are checked.
The recordings are synthetic (``examples/make_examples.py``): what a method is worth is verified on
recordings made by independent solvers elsewhere; these check that the examples stay true.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

EX = Path(__file__).resolve().parents[1] / "examples"


def _run(args, cwd):
    return subprocess.run([sys.executable, "-m", "seispound", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=600)


def test_calibrate_example_recovers_the_storeys_and_the_gap(tmp_path):
    p = _run(["calibrate", str(EX / "calibrate/model.toml"), str(EX / "calibrate/recording.mseed"), "--channels",
              str(EX / "calibrate/channels.toml"), "-o", str(tmp_path / "cal.toml"), "--fit",
              "building.A.storey_stiffness", "--fit", "building.B.storey_stiffness", "--fit", "gap.1.size"], tmp_path)
    assert p.returncode == 0, p.stderr
    lines = {ln.split()[0]: ln.split() for ln in p.stdout.splitlines() if ln.startswith("  building.") or
             ln.startswith("  gap.")}
    # made with kA 1.2e8, kB 1.0e8 N/m and a 2 cm gap (measured: within 3e-5 of each)
    assert float(lines["building.A.storey_stiffness"][2]) == pytest.approx(1.2e8, rel=1e-3)
    assert float(lines["building.B.storey_stiffness"][2]) == pytest.approx(1.0e8, rel=1e-3)
    assert float(lines["gap.1.size"][2]) == pytest.approx(0.02, rel=1e-3)


def test_impact_example_names_hd_and_gives_units(tmp_path):
    p = _run(["impact", str(EX / "impact/model.toml"), "--trials", str(EX / "impact/trials.toml"), "--channels",
              str(EX / "impact/channels.toml"), "-o", str(tmp_path / "t.md"), "-q"], tmp_path)
    assert p.returncode == 0, p.stderr
    table = (tmp_path / "t.md").read_text()
    assert "k LVe [N/m]" in table and "k Hd [N/m^1.5]" in table and "k NIVe [N/m^1.5]" in table
    rows = [ln for ln in table.splitlines() if ln.startswith("| 0.")]
    assert [r.rstrip(" |").split("|")[-1].strip() for r in rows[:2]] == ["Hd", "Hd"]  # made with Hd


def test_diagnose_example_names_velocity_dependent_restitution(tmp_path):
    p = _run(["diagnose", str(EX / "diagnose/model.toml"), str(EX / "diagnose/recording.mseed"), "--channels",
              str(EX / "diagnose/channels.toml"), "--report", str(tmp_path / "r.json"), "-q"], tmp_path)
    assert p.returncode == 0, p.stderr
    r = json.loads((tmp_path / "r.json").read_text())
    assert [x["physics"] for x in r["left_out"]] == ["velocity-dependent-restitution"]
    assert r["fit"]["after"] < 1.5 * r["noise_ne"] < r["fit"]["before"]  # measured 0.0170 against 0.0124 noise
