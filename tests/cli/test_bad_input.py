"""Bad input: one line naming the file and the key, exit code 2, nothing written.

Each case starts from a valid model text (``BASE``) and breaks one thing.  The
same case is checked through the CLI (a real subprocess) and the Python API.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

import seispound
from seispound import InputError

REPO = Path(__file__).resolve().parents[2]
RECORD = REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
SEISPOUND = Path(sys.executable).parent / "seispound"

FLOORS_A = "[3.0, 3.0, 3.0, 3.0]"
BASE = f'''\
title = "bad-input base"

[analysis]
dt = 0.005
duration = 0.2

[ground_motion]
file = "rec.AT2"
units = "g"

[contact]
law = "Hd"
stiffness = 2.75e9
restitution = 0.65

[[building]]
name = "A"
floor_masses = [1.0e5, 1.0e5, 1.0e5, 1.0e5]
storey_stiffness = [1.3092e8, 1.3092e8, 1.3092e8, 1.3092e8]
storey_heights = {FLOORS_A}
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}

[[building]]
name = "B"
floors = 8
floor_masses = 1.0e5
storey_stiffness = 1.1593e8
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}

[[gap]]
between = ["A", "B"]
size = 0.02
'''

THIRD = '''
[[building]]
name = "C"
floors = 2
floor_masses = 1.0e5
storey_stiffness = 1.0e8
storey_heights = 3.0
'''


def sub(old, new):
    def edit(text):
        assert text.count(old) == 1, f"{old!r} must occur once in the base model"
        return text.replace(old, new)
    return edit


def _b_motion(table):
    """Give building B the ground motion ``table``."""
    return sub('name = "B"\nfloors = 8\n', f'name = "B"\nfloors = 8\nground_motion = {table}\n')


def _b_law(table):
    """Give building B the storey law ``table``."""
    return sub('name = "B"\nfloors = 8\n', f'name = "B"\nfloors = 8\nstorey_law = {table}\n')


def nan_record(folder: Path):
    """Replace sample 102 (0-based; line 25, third value) of the copied record with NaN."""
    lines = (folder / "rec.AT2").read_text().splitlines(keepends=True)
    tokens = lines[24].split()
    tokens[2] = "NaN"
    lines[24] = "   " + "   ".join(tokens) + "\n"
    (folder / "rec.AT2").write_text("".join(lines))


# id: (edit of the model text, edit of the record copy, file the message names, expected key)
CASES = {
    "malformed_toml": (sub("size = 0.02\n", "size = 0.02 0.03\n"), None, "model", "(syntax)"),
    "missing_model_file": (None, None, "model", None),
    "unknown_law": (sub('law = "Hd"', 'law = "Hdx"'), None, "model", "contact.law"),
    "zero_mass": (sub("floor_masses = [1.0e5, 1.0e5, 1.0e5, 1.0e5]",
                      "floor_masses = [1.0e5, 0.0, 1.0e5, 1.0e5]"), None, "model", "building.A.floor_masses"),
    "negative_mass_scalar": (sub("floor_masses = 1.0e5", "floor_masses = -1.0e5"), None, "model",
                             "building.B.floor_masses"),
    "zero_storey_stiffness": (sub("storey_stiffness = 1.1593e8", "storey_stiffness = 0.0"), None, "model",
                              "building.B.storey_stiffness"),
    "negative_contact_stiffness": (sub("stiffness = 2.75e9", "stiffness = -2.75e9"), None, "model",
                                   "contact.stiffness"),
    "lengths_disagree": (sub("storey_stiffness = [1.3092e8, 1.3092e8, 1.3092e8, 1.3092e8]",
                             "storey_stiffness = [1.3092e8, 1.3092e8, 1.3092e8]"), None, "model",
                         "building.A.storey_stiffness"),
    "list_vs_floors": (sub("floor_masses = 1.0e5", "floor_masses = [1.0e5, 1.0e5]"), None, "model",
                       "building.B.floor_masses"),
    "negative_gap": (sub("size = 0.02", "size = -0.01"), None, "model", "gap.1.size"),
    "gap_size_list_length": (sub("size = 0.02", "size = [0.02, 0.02]"), None, "model", "gap.1.size"),
    "nan_in_record": (None, nan_record, "record", "data"),
    "units_unparseable": (sub('units = "g"', 'units = "furlongs/fortnight"'), None, "model",
                          "ground_motion.units"),
    "units_contradict_record": (sub('units = "g"', 'units = "m/s2"'), None, "model", "ground_motion.units"),
    "missing_record_file": (sub('file = "rec.AT2"', 'file = "no_such_record.AT2"'), None, "model",
                            "ground_motion.file"),
    "unknown_key_typo": (sub("floor_masses = [1.0e5, 1.0e5, 1.0e5, 1.0e5]",
                             "floor_mass = [1.0e5, 1.0e5, 1.0e5, 1.0e5]"), None, "model",
                         "building.A.floor_mass"),
    "gap_between_non_neighbours": (lambda t: t + THIRD + '\n[[gap]]\nbetween = ["A", "C"]\nsize = 0.02\n',
                                   None, "model", "gap.2.between"),
    "gap_unknown_building": (sub('between = ["A", "B"]', 'between = ["A", "Q"]'), None, "model",
                             "gap.1.between"),
    "damping_modes_out_of_range": (sub("modes = [1, 2] }\n\n[[building]]\nname = \"B\"",
                                       "modes = [1, 5] }\n\n[[building]]\nname = \"B\""), None, "model",
                                   "building.A.damping.modes"),
    "damping_mode_zero": (sub('storey_heights = 3.0\ndamping = { kind = "rayleigh", ratio = 0.05, modes = [1, 2] }',
                              'storey_heights = 3.0\ndamping = { kind = "rayleigh", ratio = 0.05, modes = [0, 2] }'),
                          None, "model", "building.B.damping.modes"),
    "dt_zero": (sub("dt = 0.005", "dt = 0.0"), None, "model", "analysis.dt"),
    "dt_negative": (sub("dt = 0.005", "dt = -0.005"), None, "model", "analysis.dt"),
    "motion_lowpass_above_nyquist": (_b_motion("{ delay = 0.01, lowpass = 150.0 }"), None, "model",
                                     "building.B.ground_motion.lowpass"),
    "motion_delay_not_a_number": (_b_motion('{ delay = "0.1" }'), None, "model", "building.B.ground_motion.delay"),
    "motion_unknown_key": (_b_motion("{ dely = 0.1 }"), None, "model", "building.B.ground_motion.dely"),
    "motion_own_record_missing": (_b_motion('{ file = "no_such.AT2", units = "g" }'), None, "model",
                                  "building.B.ground_motion.file"),
    "motion_order_zero": (_b_motion("{ lowpass = 5.0, lowpass_order = 0 }"), None, "model",
                          "building.B.ground_motion.lowpass_order"),
    "scheme_unknown": (sub("dt = 0.005", 'dt = 0.005\nscheme = "rk4"'), None, "model", "analysis.scheme"),
    "restitution_form_unknown": (sub("restitution = 0.65", 'restitution = { form = "cubic", e0 = 0.9 }'), None,
                                 "model", "contact.restitution.form"),
    "restitution_table_not_increasing": (
        sub("restitution = 0.65", 'restitution = { form = "table", velocity = [0.5, 0.1], e = [0.8, 0.9] }'), None,
        "model", "contact.restitution.velocity"),
    "hunt_crossley_negative_damping": (sub('law = "Hd"\nstiffness = 2.75e9\nrestitution = 0.65',
                                           'law = "HC"\nstiffness = 2.75e9\ndamping_constant = -0.2'), None,
                                       "model", "contact.damping_constant"),
    "hunt_crossley_takes_no_restitution": (sub('law = "Hd"', 'law = "HC"'), None, "model", "contact.restitution"),
    "storey_law_unknown_kind": (_b_law('{ kind = "trilinear", yield_drift = 0.01 }'), None, "model",
                                "building.B.storey_law.kind"),
    "storey_law_both_yields": (_b_law('{ kind = "bilinear", yield_drift = 0.01, yield_force = 1e6 }'), None,
                               "model", "building.B.storey_law.yield_drift"),
    "storey_law_no_yield": (_b_law('{ kind = "bilinear", post_yield_ratio = 0.1 }'), None, "model",
                            "building.B.storey_law.yield_drift"),
    "storey_law_ratio_one": (_b_law('{ kind = "bilinear", yield_drift = 0.01, post_yield_ratio = 1.0 }'), None,
                             "model", "building.B.storey_law.post_yield_ratio"),
    "storey_law_per_storey_length": (_b_law('{ kind = "bilinear", yield_force = [1e6, 1e6] }'), None, "model",
                                     "building.B.storey_law.yield_force"),
    "storey_law_negative_yield": (_b_law('{ kind = "bilinear", yield_drift = -0.01 }'), None, "model",
                                  "building.B.storey_law.yield_drift"),
    "bouc_wen_without_n": (_b_law('{ kind = "bouc-wen", yield_drift = 0.01 }'), None, "model",
                           "building.B.storey_law.n"),
    "bouc_wen_unbounded": (_b_law('{ kind = "bouc-wen", yield_drift = 0.01, n = 2, beta = -0.5, gamma = 0.2 }'),
                           None, "model", "building.B.storey_law.gamma"),
    "bouc_wen_beta_below_gamma": (_b_law('{ kind = "bouc-wen", yield_drift = 0.01, n = 2, beta = 0.2, gamma = 0.5 }'),
                                  None, "model", "building.B.storey_law.beta"),
    "study_file_given_to_run": (lambda t: 'model = "model.toml"\n[records]\nbundled = ["elcentro_180"]\n'
                                          '[[axis]]\npath = "gap.1.size"\nvalues = [0.01]\n', None, "model", "model"),
    "storey_law_unknown_key": (_b_law('{ kind = "bilinear", yield_drif = 0.01 }'), None, "model",
                               "building.B.storey_law.yield_drif"),
    "apparent_velocity_without_position": (sub('units = "g"\n', 'units = "g"\napparent_velocity = 300.0\n'),
                                           None, "model", "building.A.position"),
    "apparent_velocity_negative": (lambda t: _b_motion("{ lowpass = 5.0 }")(t).replace(
        'units = "g"\n', 'units = "g"\napparent_velocity = -300.0\n'), None, "model",
        "ground_motion.apparent_velocity"),
}

# the cases run through the CLI as subprocesses (start-up costs 1.5-2.5 s each); the
# variants left out here are checked through the Python API only
CLI_CASES = ["malformed_toml", "missing_model_file", "unknown_law", "zero_mass", "zero_storey_stiffness",
             "lengths_disagree", "negative_gap", "nan_in_record", "units_unparseable", "missing_record_file",
             "unknown_key_typo", "gap_between_non_neighbours", "damping_modes_out_of_range", "dt_zero",
             "motion_lowpass_above_nyquist", "apparent_velocity_without_position", "restitution_form_unknown",
             "storey_law_both_yields", "study_file_given_to_run"]

# cases whose problem lies in the record's content: found when the record is read (simulate)
RECORD_CONTENT = {"nan_in_record", "units_contradict_record"}


def make_case(folder: Path, case: str) -> Path:
    edit, rec_edit, _, _ = CASES[case]
    shutil.copyfile(RECORD, folder / "rec.AT2")
    model = folder / "model.toml"
    if case == "missing_model_file":
        return folder / "no_such_model.toml"
    model.write_text(edit(BASE) if edit else BASE, encoding="utf-8")
    if rec_edit:
        rec_edit(folder)
    return model


def test_base_model_is_valid(tmp_path):
    model = seispound.load_model(_base(tmp_path))
    assert [b.name for b in model.buildings] == ["A", "B"]
    assert [b.n_floors for b in model.buildings] == [4, 8]
    ds = seispound.simulate(model, twin=False)
    assert ds.sizes["time"] == 41 and ds.sizes["gap"] == 4


def write_model(folder, text=BASE):
    """``text`` (default: the base model) as folder/model.toml, next to a copy of the record it reads."""
    shutil.copyfile(RECORD, folder / "rec.AT2")
    (folder / "model.toml").write_text(text, encoding="utf-8")
    return folder / "model.toml"


_base = write_model


def _check_line(line: str, folder: Path, model: Path, case: str):
    _, _, named, key = CASES[case]
    assert "\n" not in line
    assert "Traceback" not in line
    fname = model.name if named == "model" else "rec.AT2"
    assert fname in line, line
    if key is not None:
        # str(InputError) is "FILE: KEY: message"
        assert f"{fname}: {key}: " in line, line
    else:
        assert "not found" in line


def _run_cli(folder: Path, case: str):
    model = make_case(folder, case)
    before = sorted(p.name for p in folder.iterdir())
    out = folder / "result.h5"
    proc = subprocess.run([str(SEISPOUND), "run", str(model), "-o", str(out)], cwd=folder,
                          capture_output=True, text=True, timeout=120)
    after = sorted(p.name for p in folder.iterdir())
    return model, out, before, after, proc


@pytest.fixture(scope="module")
def cli_outcomes(tmp_path_factory):
    """Run the CLI on every case, a few processes at a time (start-up dominates)."""
    folders = {case: tmp_path_factory.mktemp(f"bad_{case}") for case in CLI_CASES}
    with ThreadPoolExecutor(max_workers=4) as pool:
        futures = {case: pool.submit(_run_cli, folder, case) for case, folder in folders.items()}
        return {case: (folders[case], *fut.result()) for case, fut in futures.items()}


@pytest.mark.parametrize("case", CLI_CASES)
def test_cli_one_line_exit_2_nothing_written(cli_outcomes, case):
    folder, model, out, before, after, proc = cli_outcomes[case]
    assert proc.returncode == 2, (proc.stdout, proc.stderr)
    assert proc.stdout == ""
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1, proc.stderr
    assert proc.stderr.endswith("\n") and proc.stderr.count("\n") == 1
    assert lines[0].startswith("seispound: error: ")
    _check_line(lines[0], folder, model, case)
    assert not out.exists()
    assert after == before, f"stray files: {set(after) - set(before)}"
    assert not list(folder.glob(".*.tmp"))


@pytest.mark.parametrize("case", list(CASES))
def test_api_raises_input_error(tmp_path, case):
    model = make_case(tmp_path, case)
    with pytest.raises(InputError) as info:
        loaded = seispound.load_model(model)
        if case in RECORD_CONTENT:
            seispound.simulate(loaded)
        else:
            pytest.fail(f"load_model accepted the bad model ({case})")
    msg = str(info.value)
    assert len(msg.splitlines()) == 1
    _check_line(msg, tmp_path, model, case)
    named, key = CASES[case][2], CASES[case][3]
    assert info.value.key == key
    assert Path(info.value.file).name == (model.name if named == "model" else "rec.AT2")


def test_output_folder_missing(tmp_path):
    model = _base(tmp_path)
    out = tmp_path / "nope" / "x.h5"
    proc = subprocess.run([str(SEISPOUND), "run", str(model), "-o", str(out)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and ": --output: " in lines[0] and "x.h5" in lines[0]
    assert not (tmp_path / "nope").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["model.toml", "rec.AT2"]
