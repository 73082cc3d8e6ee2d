"""Write ``restitution_table.md``: simulated restitution of the laws whose e differs from the target.

Not run at test time.  Usage, from the repository root::

    python tests/verification/make_tables.py

Same set-up as ``test_impact_restitution.py`` (the seed's pendulum slabs, 110 kg
striker at 0.1 m/s against 109 kg, gap 0, dt = 1 ms, 64 contact substeps).  For
two free bodies the restitution of all three laws depends on e only (not on the
velocity, the stiffness or the masses: the equations of motion become
parameter-free when scaled by delta* = (m_eff v0^2 / k)^(1/(n+1))), so the table
holds for any impact.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from tests.verification.test_impact_restitution import (  # noqa: E402
    E_TARGETS,
    K_HERTZ,
    K_LINEAR,
    e_lve_clamped,
    e_mlve,
    restitution,
    simulate,
    twin_restitution,
)

OUT = Path(__file__).resolve().parent / "restitution_table.md"


def main():
    exact_err = max(abs(restitution(simulate(law, e)) / e - 1.0)
                    for law in ("LVe", "Hd", "LHC") for e in E_TARGETS)
    rows = []
    for e in E_TARGETS:
        rows.append((
            e,
            restitution(simulate("MLVe", e)), e_mlve(e),
            restitution(simulate("NIVe", e)), twin_restitution("NIVe", e),
            restitution(simulate("Hertzdamp", e)), twin_restitution("Hertzdamp", e),
            restitution(simulate("LVe", e, tension=False)), e_lve_clamped(e),
        ))
    lines = [
        "Simulated coefficient of restitution vout/v0 against the target e of the law",
        "(two-body impact: seed pendulum slabs 110 kg / 109 kg, v0 = 0.1 m/s, "
        f"k = {K_LINEAR:.0e} N/m (linear laws), {K_HERTZ:.0e} N/m^1.5 (Hertz-type laws);",
        "seispound kernel with dt = 1 ms and 64 contact substeps; 'exact' = closed form "
        "(MLVe, clamped LVe) or reference twin, solve_ivp with event location, rtol 1e-10).",
        f"LVe (with tension), Hd and LHC reproduce e itself (largest error {100 * exact_err:.3f} %).",
        "",
        "| target e | MLVe | MLVe exact | NIVe | NIVe exact | Hertzdamp | Hertzdamp exact "
        "| LVe no tension | LVe no tension exact |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        lines.append("| " + " | ".join(f"{x:.2f}" if i == 0 else f"{x:.4f}" for i, x in enumerate(row)) + " |")
    OUT.write_text("\n".join(lines) + "\n")
    print(OUT.read_text())


if __name__ == "__main__":
    main()
