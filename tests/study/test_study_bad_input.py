"""Bad study files: one line naming the study file and the key, exit code 2, nothing written."""

from __future__ import annotations

import pytest

from seispound.errors import InputError
from seispound.study import load_study

from .conftest import cli, model_copy

GOOD = """\
model = "two.toml"
[records]
bundled = ["elcentro_180"]
[[axis]]
name = "gap_size"
path = "gap.*.size"
values = [0.01, 0.02]
"""

# (what is wrong, study text, key expected in the message, words expected in the message)
CASES = [
    ("malformed TOML", GOOD.replace("[[axis]]", "[[axis]"), "(syntax)", "malformed TOML"),
    ("unknown top key", "colour = 1\n" + GOOD, "colour", "unknown key"),
    ("unknown axis key", GOOD + "colour = 1\n", "axis.1.colour", "unknown key"),
    ("no model", GOOD.replace('model = "two.toml"', ""), "model", "required"),
    ("missing model file", GOOD.replace("two.toml", "nope.toml"), "model", "not found"),
    ("no records", GOOD.replace('[records]\nbundled = ["elcentro_180"]\n', ""), "records", "required"),
    ("unknown bundled record", GOOD.replace("elcentro_180", "kobe"), "records.bundled", "kobe"),
    ("record file missing", GOOD.replace('bundled = ["elcentro_180"]', 'files = ["x.AT2"]'), "records.files",
     "not found"),
    ("glob matches nothing", GOOD.replace('bundled = ["elcentro_180"]', 'glob = "*.AT2"'), "records.glob",
     "matches no file"),
    ("path into no table", GOOD.replace("gap.*.size", "roof.size"), "axis.1.path", "no table"),
    ("gap index out of range", GOOD.replace("gap.*.size", "gap.3.size"), "axis.1.path", "1-based"),
    ("unknown building", GOOD.replace("gap.*.size", "building.Z.storey_stiffness"), "axis.1.path",
     "no building named 'Z'"),
    ("negative gap", GOOD.replace("[0.01, 0.02]", "[0.01, -0.02]"), "axis.1", "gap.1.size"),
    ("unknown law", GOOD.replace('path = "gap.*.size"\nvalues = [0.01, 0.02]',
                                 'path = "contact.law"\nvalues = ["Hd", "Stiff"]'), "axis.1", "Stiff"),
    ("unknown model key", GOOD.replace("gap.*.size", "contact.colour"), "axis.1", "contact.colour"),
    ("two value kinds", GOOD.replace("values = [0.01, 0.02]", "values = [0.01]\nfactors = [1.0]"), "axis.1",
     "exactly one"),
    ("empty values", GOOD.replace("[0.01, 0.02]", "[]"), "axis.1.values", "non-empty"),
    ("bad range", GOOD.replace("values = [0.01, 0.02]", "range = {start = 0.01, stop = 0.05}"),
     "axis.1.range.num", "required"),
    ("log range through zero", GOOD.replace("values = [0.01, 0.02]",
                                            'range = {start = 0.0, stop = 0.05, num = 3, spacing = "log"}'),
     "axis.1.range.spacing", "start > 0"),
    ("factor on a law name", GOOD.replace('path = "gap.*.size"\nvalues = [0.01, 0.02]',
                                          'path = "contact.law"\nfactors = [2.0]'), "axis.1.factors", "numbers"),
    ("zip lengths differ", GOOD.replace('path = "gap.*.size"\nvalues = [0.01, 0.02]',
                                        'zip = [{path = "gap.1.size", values = [0.01, 0.02]}, '
                                        '{path = "contact.restitution", values = [0.5]}]'), "axis.1.zip",
     "as many values"),
    ("reserved axis name", GOOD.replace('name = "gap_size"', 'name = "gap"'), "axis.1.name", "dimension"),
    ("records as an axis", GOOD.replace("gap.*.size", "ground_motion.file"), "axis.1.path", "[records]"),
    ("structure change", GOOD.replace('path = "gap.*.size"\nvalues = [0.01, 0.02]',
                                      'path = "building.A.floors"\nvalues = [4, 5]'), "axis.1",
     "changes the buildings"),
    ("unknown history", GOOD + '[output]\nhistories = ["temperature"]\n', "output.histories", "temperature"),
    ("bad decimate", GOOD + "[output]\ndecimate = 0\n", "output.decimate", ">= 1"),
    ("histories with a varying dt", GOOD.replace('path = "gap.*.size"\nvalues = [0.01, 0.02]',
                                                 'path = "analysis.dt"\nvalues = [0.005, 0.01]')
     + '[output]\nhistories = ["displacement"]\n', "output.histories", "analysis.dt"),
]


@pytest.mark.parametrize("what, text, key, words", CASES, ids=[c[0] for c in CASES])
def test_bad_study_file(tmp_path, what, text, key, words):
    model_copy(tmp_path, 5.0)
    study = tmp_path / "study.toml"
    study.write_text(text)
    with pytest.raises(InputError) as exc:
        load_study(study)
    msg = str(exc.value)
    assert msg.startswith(f"{study}: {key}"), msg
    assert words in msg, msg
    assert "\n" not in msg


def test_cli_bad_study_is_one_line_exit_2_and_writes_nothing(tmp_path):
    model_copy(tmp_path, 5.0)
    study = tmp_path / "study.toml"
    study.write_text(GOOD.replace("[0.01, 0.02]", "[0.01, -0.02]"))
    out = tmp_path / "s.h5"
    res = cli(["study", study, "-o", out, "--scheduler", "serial"])
    assert res.returncode == 2
    assert res.stderr.startswith(f"seispound: error: {study}: axis.1") and res.stderr.count("\n") == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml", "two.toml"]


def test_a_store_of_another_study_is_refused(tmp_path):
    model_copy(tmp_path, 3.0)
    study = tmp_path / "study.toml"
    study.write_text(GOOD)
    out = tmp_path / "s.h5"
    assert cli(["study", study, "-o", out, "--scheduler", "serial", "-q"]).returncode == 0
    before = out.read_bytes()
    study.write_text(GOOD.replace("[0.01, 0.02]", "[0.01, 0.03]"))
    res = cli(["study", study, "-o", out, "--scheduler", "serial"])
    assert res.returncode == 2 and "another study" in res.stderr and "-o" in res.stderr
    assert out.read_bytes() == before
    res = cli(["study", study, "-o", out, "--scheduler", "serial", "--overwrite", "-q"])
    assert res.returncode == 0, res.stderr
    assert out.read_bytes() != before
