"""Output paths that cannot be written, and the permissions of what is written.

An unwritable output (a directory given as the file, a missing folder, a
read-only or virtual file system, no permission) is one line naming the path
and the reason, exit 2, reported before any computation, with nothing written.
Written files get ``0o666 & ~umask`` like any Unix tool.
"""

from __future__ import annotations

import errno
import os
import stat
import tempfile
import time
from pathlib import Path

import pytest

from seispound import cli
from seispound._output import atomic_output, check_writable, default_file_mode
from seispound.errors import InputError
from tests._models import short_copy
from tests.study.conftest import write_study


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    """A short single-run result (0.6 s of El Centro) for the plot commands."""
    folder = tmp_path_factory.mktemp("run")
    model = short_copy(folder, 0.6)
    assert cli.main(["run", str(model), "-o", str(folder / "r.h5"), "-q"]) == 0
    return folder / "r.h5"


@pytest.fixture(scope="module")
def store_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    study = write_study(folder, duration=0.5, records=("elcentro_180",), gaps=(0.01, 0.02))
    assert cli.main(["study", str(study), "-o", str(folder / "s.h5"), "--scheduler", "serial", "-q"]) == 0
    return folder / "s.h5"


def _one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("seispound: error: ")
    return err[0]


def _bad_outputs(tmp_path):
    """(output path, words the error must contain) for the cases every machine can produce."""
    folder = tmp_path / "a_folder.h5"
    folder.mkdir()
    return [(folder, "is a directory"), (tmp_path / "missing" / "x.h5", "output folder does not exist"),
            (Path("/proc/seispound-test.h5"), "cannot write here")]


def test_run_refuses_unwritable_output_before_computing(tmp_path, capsys, monkeypatch):
    model = short_copy(tmp_path, 30.0)  # a run that would take seconds: the refusal must not
    monkeypatch.setattr("seispound.simulation.simulate", lambda *a, **k: pytest.fail("computed anyway"))
    for out, words in _bad_outputs(tmp_path):
        t0 = time.perf_counter()
        assert cli.main(["run", str(model), "-o", str(out)]) == 2
        line = _one_error_line(capsys)
        assert str(out) in line and words in line and "--output" in line
        assert time.perf_counter() - t0 < 1.0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_folder.h5", "two_buildings.toml"]
    assert list((tmp_path / "a_folder.h5").iterdir()) == []


def test_study_refuses_unwritable_store_before_any_run(tmp_path, capsys):
    study = write_study(tmp_path / "s", duration=0.5, records=("elcentro_180",), gaps=(0.01,))
    for out, words in _bad_outputs(tmp_path):
        assert cli.main(["study", str(study), "-o", str(out), "--scheduler", "serial", "-q"]) == 2
        line = _one_error_line(capsys)
        assert str(out) in line and words in line
    assert not list(tmp_path.glob("**/*.journal"))


def test_study_refuses_when_the_journal_cannot_be_written(tmp_path, capsys):
    study = write_study(tmp_path / "s", duration=0.5, records=("elcentro_180",), gaps=(0.01,))
    out = tmp_path / "s" / "store.h5"
    (tmp_path / "s" / "store.h5.journal").mkdir()  # the journal's name is taken by a folder
    assert cli.main(["study", str(study), "-o", str(out), "--scheduler", "serial", "-q"]) == 2
    line = _one_error_line(capsys)
    assert "store.h5.journal" in line and "is a directory" in line
    assert not out.exists()


def test_plot_refuses_unwritable_output(result_file, tmp_path, capsys):
    folder = tmp_path / "figs.png"  # OUT.png exists as a folder
    folder.mkdir()
    for out, words in [(tmp_path / "figs", "is a directory"), (tmp_path / "nope" / "f", "does not exist"),
                       (Path("/proc/seispound-fig"), "cannot write here")]:
        assert cli.main(["plot", str(result_file), "-o", str(out)]) == 2
        line = _one_error_line(capsys)
        assert words in line and "--output" in line
    assert not (tmp_path / "figs.svg").exists()


def test_query_refuses_unwritable_output(store_file, tmp_path, capsys):
    (tmp_path / "q.csv").mkdir()
    for out, words in [(tmp_path / "q.csv", "is a directory"), (tmp_path / "nope" / "q.csv", "does not exist"),
                       (Path("/proc/seispound-q.csv"), "cannot write here")]:
        assert cli.main(["query", str(store_file), "-o", str(out)]) == 2
        line = _one_error_line(capsys)
        assert str(out) in line and words in line and "-o" in line


@pytest.mark.parametrize("code, words", [(errno.EROFS, "read-only file system"),
                                         (errno.EACCES, "permission denied"),
                                         (errno.ENOSPC, "no space left")])
def test_reasons_named(tmp_path, monkeypatch, code, words):
    """The errno of the probe file becomes the reason (root cannot be denied by chmod, so it is simulated)."""
    def refuse(*args, **kwargs):
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with pytest.raises(InputError) as info:
        check_writable(tmp_path / "x.h5", key="--output")
    assert str(info.value).startswith(f"{tmp_path / 'x.h5'}: --output: cannot write here: {words}")


@pytest.mark.parametrize("mask", [0o022, 0o002, 0o077])
def test_written_files_follow_the_umask(result_file, store_file, tmp_path, mask):
    """Result HDF5, PNG, SVG and CSV get 0o666 & ~umask, not mkstemp's 0600."""
    old = os.umask(mask)
    try:
        assert default_file_mode() == 0o666 & ~mask
        assert cli.main(["run", str(short_copy(tmp_path, 0.2)), "-o", str(tmp_path / "r.h5"), "-q"]) == 0
        assert cli.main(["plot", str(result_file), "-o", str(tmp_path / "fig")]) == 0
        assert cli.main(["query", str(store_file), "-o", str(tmp_path / "q.csv")]) == 0
        with atomic_output(tmp_path / "plain.txt") as tmp:
            Path(tmp).write_text("x")
        study = write_study(tmp_path / "st", duration=0.3, records=("elcentro_180",), gaps=(0.01,))
        assert cli.main(["study", str(study), "-o", str(tmp_path / "store.h5"), "--scheduler", "serial",
                         "--snapshot", "0", "-q"]) == 0
        from seispound.study.journal import Journal

        Journal(tmp_path / "j.h5", "hash").open().close()  # a journal, as a study in progress leaves it
    finally:
        os.umask(old)
    for name in ("r.h5", "fig.png", "fig.svg", "q.csv", "plain.txt", "store.h5", "j.h5.journal"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o666 & ~mask, name
    assert not list(tmp_path.glob(".*.tmp"))


def test_atomic_output_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "keep.csv"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_output(target) as tmp:
            Path(tmp).write_text("half")
            raise RuntimeError("interrupted")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.csv"]
