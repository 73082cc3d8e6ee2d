"""``seispound diagnose --hypotheses``: the registry's names, one line and exit 2 for any other, nothing written."""

import pytest

from seispound import cli
from seispound.diagnose.hypotheses import HYPOTHESES


@pytest.mark.parametrize("given,says", [
    ("rocking-walls", "--hypotheses: unknown hypothesis 'rocking-walls'; one of: distributed-mass"),
    ("soil-structure-interaction,rocking-walls", "--hypotheses: unknown hypothesis 'rocking-walls'"),
    (",", "--hypotheses: give one or more of: distributed-mass"),
])
def test_an_unknown_hypothesis_is_one_line_and_exit_2(tmp_path, capsys, given, says):
    report = tmp_path / "out" / "report.json"
    report.parent.mkdir()
    rc = cli.main(["diagnose", str(tmp_path / "model.toml"), str(tmp_path / "rec.mseed"), "--channels",
                   str(tmp_path / "channels.toml"), "--report", str(report), "--hypotheses", given])
    lines = capsys.readouterr().err.strip().splitlines()
    assert rc == 2
    assert len(lines) == 1 and says in lines[0], lines
    assert not any(report.parent.iterdir())


def test_the_help_names_every_registered_physics(capsys):
    with pytest.raises(SystemExit):
        cli.main(["diagnose", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for name in HYPOTHESES:
        assert name in text
