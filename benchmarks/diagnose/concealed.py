"""Diagnose the cases made elsewhere: ``python -m benchmarks.diagnose.concealed [FOLDER] [--markdown F]``.

FOLDER (default ``../shared/concealed``) holds ``case-*`` folders (model, recording, channel map).
Each is copied to a temporary folder and diagnosed as a user would, one after another; no answer
is read (there is none in the folder).  Printed: a markdown table of what was named, with its
probability and quantities, the NE as given and after against the noise's NE, the verdict and
the time.
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def run(folder: Path) -> list[dict]:
    from seispound.diagnose import diagnose

    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for case in sorted(folder.glob("case-*")):
            f = Path(tmp) / case.name
            shutil.copytree(case, f)
            t0 = time.perf_counter()
            d = diagnose(f / "model.toml", [f / "recording.mseed"], channels=f / "channels.toml",
                         report=f / "report.json", progress=False)
            out.append({"case": case.name, "named": [(x["physics"], x["probability"], x["quantities"])
                                                     for x in d.left_out],
                        "ne_before": d.ne_before, "ne_after": d.ne_after, "noise": d.noise_ne, "verdict": d.verdict,
                        "fault": (d.instrument_fault or {}).get("channel"), "seconds": time.perf_counter() - t0})
            print(out[-1]["case"], out[-1]["named"] and [n for n, _, _ in out[-1]["named"]], f"{d.ne_after:.4f}",
                  flush=True)
    return out


def markdown(rows) -> str:
    lines = ["| case | named (probability) | NE as given -> after | noise alone | time |", "|---|---|---|---|---|"]
    for r in rows:
        named = ", ".join(f"{n} ({p:.2f})" for n, p, _ in r["named"]) or "nothing"
        if r["fault"]:
            named += f"; instrument fault on {r['fault']}"
        lines.append(f"| {r['case']} | {named} | {r['ne_before']:.3f} -> {r['ne_after']:.3f} | {r['noise']:.3f} | "
                     f"{r['seconds']:.0f} s |")
    lines.append("")
    for r in rows:
        lines.append(f"- **{r['case']}**: {r['verdict']}.")
        for n, _, qs in r["named"]:
            for q in qs:
                val = (f"{q['value']:.4g} +- {q['stderr']:.2g} {q['units']}" if q.get("stderr") is not None
                       else f"{q['value']:.4g} {q['units']} (not identified: {q.get('reason')})")
                if q.get("form_limited"):
                    val += f" (its form's value: the fit leaves {q['form_limited']:.1f} times the noise)"
                lines.append(f"  - {n}: {q['name']}: {val}")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", nargs="?", default=str(REPO.parent / "shared" / "concealed"))
    ap.add_argument("--markdown", default="")
    args = ap.parse_args(argv)
    text = markdown(run(Path(args.folder)))
    print(text)
    if args.markdown:
        Path(args.markdown).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
