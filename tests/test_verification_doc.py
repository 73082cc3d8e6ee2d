"""docs/verification.md says what kind of check each row is, from a fixed vocabulary."""

from pathlib import Path

KINDS = {"closed form", "published result", "independent solver", "self-consistency", "regression",
         "closed form; independent solver", "closed form (known truth, Monte Carlo)"}


def test_every_verification_row_names_its_kind():
    text = (Path(__file__).resolve().parents[1] / "docs" / "verification.md").read_text(encoding="utf-8")
    lines = text.splitlines()
    head = lines.index("| check (test file) | reference | kind | measured |")
    rows = []
    for line in lines[head + 2:]:
        if not line.startswith("|"):
            break
        rows.append([c.strip() for c in line.strip("|").split(" | ")])
    assert len(rows) > 50
    assert {r[2] for r in rows} <= KINDS, {r[2] for r in rows} - KINDS
    for r in rows:  # what the package pins or compares with itself is never presented as independent
        if "pinned" in r[1] or "regression guard" in r[0]:
            assert r[2] == "regression", r[0]
        if "general driver" in r[1] or "fast one" in r[0] or "each pair alone" in r[1]:
            assert r[2] == "self-consistency", r[0]
