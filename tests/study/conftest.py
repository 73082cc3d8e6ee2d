"""A small study on a copy of models/two_buildings.toml (shortened), written into tmp folders."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from tests._models import short_copy

REPO = Path(__file__).resolve().parents[2]
SEISPOUND = Path(sys.executable).parent / "seispound"


def model_copy(folder: Path, duration: float) -> Path:
    """models/two_buildings.toml as folder/two.toml, record path absolute, duration shortened."""
    return short_copy(folder, duration, as_name="two.toml")


STUDY = """\
title = "test study"
model = "two.toml"

[records]
bundled = {records}

[[axis]]
name = "law"
zip = [{{ path = "contact.law", values = ["Hd", "LVe"] }},
       {{ path = "contact.stiffness", values = [2.75e9, 1.6e8] }}]

[[axis]]
name = "gap_size"
path = "gap.*.size"
values = {gaps}
{extra}"""


def write_study(folder: Path, duration=8.0, records=("elcentro_180", "elcentro_270"),
                gaps=(0.005, 0.01, 0.02), extra="") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    model_copy(folder, duration)
    path = folder / "study.toml"
    path.write_text(STUDY.format(records=list(records), gaps=list(gaps), extra=extra), encoding="utf-8")
    return path


def cli(args, cwd=None, timeout=300, **kw):
    return subprocess.run([str(SEISPOUND), *map(str, args)], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout, **kw)


@pytest.fixture(scope="session")
def reference_store(tmp_path_factory):
    """The small study run serially in one go: (study file, store)."""
    folder = tmp_path_factory.mktemp("ref")
    study = write_study(folder)
    out = folder / "ref.h5"
    res = cli(["study", study, "-o", out, "--scheduler", "serial", "-q"])
    assert res.returncode == 0, res.stderr
    return study, out
