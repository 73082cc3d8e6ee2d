"""Write concealed-effect cases in the form of ``../shared/concealed``: ``python -m benchmarks.diagnose.generate OUT``.

Each case is a neutral folder (``case-001`` ...) with ``model.toml`` (the base model: lumped,
fixed-base, elastic, constant e, one input), ``ground_motion.mseed`` (the input with 1 % noise),
``recording.mseed`` (every floor's absolute acceleration, the free field and the roofs'
displacements, 1 % noise) and ``channels.toml``; the answers go to ``OUT/key.json`` only.
Recordings come from ``twin.py`` (an independent solve_ivp solver), never from the package.

Families: ``none`` (noise only), ``wrong-parameters`` (a storey stiffness and a gap size off
in the base model; the label is none), and one per effect; ``--instances`` random draws each,
every other one weak: the effect's size scaled down (a search over a strength factor on the
first 8 s) until the effect's own NE, between the row with and without it, is 2-5 times the
1 % noise (target 3.5 %).  The key records each case's effect NE over the whole record.
Inputs: the bundled El Centro components, 20 s, scaled to a PGA of 0.35-0.45 g; 200 Hz, or
1 kHz where floors ring.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from .twin import Building, Row, simulate

REPO = Path(__file__).resolve().parents[2]
BASE_E = 0.65  # the coefficient of restitution of every base model (and of the rows without e(v))
FAMILIES = ("none", "wrong-parameters", "distributed-mass", "velocity-dependent-restitution",
            "soil-structure-interaction", "inelastic-storey", "spatially-varying-input")


def _record(rng, dt, duration=20.0):
    """A bundled El Centro component, its first ``duration`` s, scaled to PGA 0.35-0.45 g, on the grid dt.

    Processed as a record is before use: a 1 s cosine taper at the start, so that the motion
    starts from rest (a record that starts mid-shaking puts a velocity step into a delayed copy).
    """
    import obspy

    name = rng.choice(["RSN6_IMPVALL.I_I-ELC180-hor1.AT2", "RSN6_IMPVALL.I_I-ELC270-hor2.AT2"])
    path = REPO / "ground_motions" / name
    if not path.exists():
        path = REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    tr = obspy.read(str(path))[0]
    a = tr.data.astype(float) * 9.80665
    t0 = np.arange(a.size) * tr.stats.delta
    t = np.arange(round(duration / dt) + 1) * dt
    x = np.interp(t, t0, a) * np.where(t < 1.0, 0.5 - 0.5 * np.cos(np.pi * np.minimum(t, 1.0)), 1.0)
    return x * (rng.uniform(0.35, 0.45) * 9.80665 / np.abs(x).max())


def _row(rng, nb):
    """Two or three uniform-ish buildings of 4-10 storeys, 3 m storeys, gaps 1-2 cm."""
    bs = []
    for i in range(nb):
        n = int(rng.integers(4, 11))
        m = float(rng.uniform(0.8e5, 1.4e5))
        k = float(rng.uniform(1.0e8, 2.2e8))
        bs.append(Building("ABC"[i], [m] * (n - 1) + [0.85 * m], list(np.linspace(k, 0.6 * k, n)), ratio=0.05))
    gaps = [(i, i + 1, float(rng.uniform(0.01, 0.02))) for i in range(nb - 1)]
    return Row(bs, gaps)


def _apply(family, row, rng, strength):
    """Put the family's effect into the generating row (and, for wrong-parameters, the base model's error)."""
    base_edit = {}
    if family == "wrong-parameters":
        b = rng.integers(len(row.buildings))
        base_edit = {"building": int(b), "stiffness_factor": 1.0 + strength * float(rng.choice([-0.2, 0.2])),
                     "gap_factor": 1.0 + strength * float(rng.choice([-0.3, 0.4]))}
    elif family == "inelastic-storey":
        for b in row.buildings:
            b.yield_drift = [float(rng.uniform(0.004, 0.01) / strength)] * b.n
    elif family == "spatially-varying-input":
        for b in row.buildings[1:]:
            b.delay = float(rng.uniform(0.02, 0.08) * strength)
    elif family == "velocity-dependent-restitution":
        # e(v0) = 0.9 - slope v0 at full strength; scaled towards the base model's constant e (BASE_E), so that
        # a weak instance differs from the base model by its slope, not by a constant e recalibration would absorb
        slope = float(rng.uniform(0.8, 2.0))
        row.restitution = lambda v, s=strength, k=slope: min(max(BASE_E + s * (0.9 - BASE_E - k * v), 0.2), 0.95)
    elif family == "soil-structure-interaction":
        for b in row.buildings:
            mt = sum(b.masses)
            it = sum(m * (3.0 * (f + 1)) ** 2 for f, m in enumerate(b.masses))  # the floors' rocking inertia
            kx = float(rng.uniform(2.0, 6.0) * 1e8 / strength)
            kt = kx * 60.0
            b.foundation = {"kx": kx, "cx": 0.1 * math.sqrt(kx * mt), "kt": kt, "ct": 0.1 * math.sqrt(kt * it),
                                "m0": 0.2 * mt, "I0": 0.2 * mt * 15.0 ** 2 / 12.0}
    elif family == "distributed-mass":
        for b in row.buildings:
            k_link = float(rng.uniform(2e9, 6e9) / strength)
            w1 = _first_axial(b.masses[0], k_link, 5)
            b.chain = {"nodes": 5, "axial_stiffness": k_link, "axial_damping": 2 * 0.02 / w1 * k_link}  # 2 % in mode 1
    return base_edit


def _first_axial(m, k, nodes):
    """First nonzero free-free circular frequency of a chain of ``nodes`` lumped masses (half at the ends)."""
    from scipy.linalg import eigh

    w = np.full(nodes, m / (nodes - 1))
    w[[0, -1]] *= 0.5
    K = np.zeros((nodes, nodes))
    for p in range(nodes - 1):
        K[p:p + 2, p:p + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    return math.sqrt(eigh(K, np.diag(w), eigvals_only=True)[1])


def _model_text(row, base_edit, dt, e, duration=20.0):
    lines = ['title = "Row of %d buildings, recorded earthquake response"' % len(row.buildings), "",
             "[analysis]", f"dt = {dt}", f"duration = {duration}", "newmark = { beta = 0.25, gamma = 0.5 }", "",
             "[ground_motion]", 'file = "ground_motion.mseed"', "trace = 0", 'units = "m/s2"', "scale = 1.0", "",
             "[contact]", 'law = "Hd"', f"stiffness = {row.k_contact}", f"restitution = {e}", ""]
    for i, b in enumerate(row.buildings):
        f = base_edit.get("stiffness_factor", 1.0) if base_edit.get("building") == i else 1.0
        lines += ["[[building]]", f'name = "{b.name}"', f"floor_masses = {list(map(float, b.masses))}",
                  f"storey_stiffness = {[float(k * f) for k in b.stiffness]}", f"storey_heights = {[3.0] * b.n}",
                  'damping = { kind = "rayleigh", ratio = 0.05, modes = [1, 2] }', ""]
    for li, ri, size in row.gaps:
        size *= base_edit.get("gap_factor", 1.0)
        lines += ["[[gap]]", f'between = ["{row.buildings[li].name}", "{row.buildings[ri].name}"]', f"size = {size}",
                  ""]
    return "\n".join(lines)


def _draw(family, seed, strength, buildings=None):
    """The generating row and the base model's edit; the same draws whatever the strength."""
    rng = np.random.default_rng(seed)
    nb = int(rng.integers(2, 4))
    row = _row(rng, buildings or nb)
    return row, _apply(family, row, rng, strength)


def _base_row(family, seed, strength, buildings=None):
    """The row the base model describes: no effect, and for wrong-parameters its wrong stiffness and gap sizes."""
    row = _draw("none", seed, 1.0, buildings)[0]
    edit = _draw(family, seed, strength, buildings)[1]
    if edit:
        b = row.buildings[edit["building"]]
        b.stiffness = [k * edit["stiffness_factor"] for k in b.stiffness]
        row.gaps = [(li, ri, size * edit["gap_factor"]) for li, ri, size in row.gaps]
    return row


def _effect_ne(family, seed, strength, t_ag, ag, t, with_effect=None, buildings=None, base=None):
    """Mean NE over the recorded channels between the row with the effect and the base model's row (no noise).

    ``with_effect``, ``base``: their simulations if already run.
    """
    if with_effect is None:
        with_effect = simulate(_draw(family, seed, strength, buildings)[0], t_ag, ag, t)
    if base is None:
        base = simulate(_base_row(family, seed, strength, buildings), t_ag, ag, t)
    ne = [np.linalg.norm(with_effect[q][k] - base[q][k]) / np.linalg.norm(with_effect[q][k])
          for q in ("acc", "roof") for k in with_effect[q]]
    return float(np.mean(ne))


def _weak_strength(family, seed, t_ag, ag, dt, buildings=None, target=0.035, lo=0.02, hi=0.05):
    """The strength in (0, 1] whose effect NE over the first 8 s is nearest ``target``: a secant search on
    log NE against log strength (at most 5 runs), from strength 0.1."""
    t = np.arange(round(8.0 / dt) + 1) * dt
    # one side does not depend on the strength: the true row (wrong-parameters) or the base model's row
    fixed = {"with_effect": simulate(_draw(family, seed, 1.0, buildings)[0], t_ag, ag, t)} \
        if family == "wrong-parameters" else {"base": simulate(_base_row(family, seed, 1.0, buildings), t_ag, ag, t)}
    tried = []
    s = 0.1
    for _ in range(5):
        ne = max(_effect_ne(family, seed, s, t_ag, ag, t, buildings=buildings, **fixed), 1e-6)
        tried.append((abs(math.log(ne / target)), s, ne))
        if lo <= ne <= hi:
            break
        if len(tried) == 1:
            slope = 1.0
        else:
            (_, s0, n0), (_, s1, n1) = tried[-2], tried[-1]
            slope = math.log(n1 / n0) / math.log(s1 / s0) if s1 != s0 and n1 != n0 else 1.0
            slope = slope if slope > 0.2 else 1.0  # a non-monotone step: fall back to proportional
        s = float(np.clip(s * (target / ne) ** (1.0 / slope), 1e-4, 1.0))
    return min(tried)[1]


def write_case(folder: Path, family: str, seed: int, weak: bool = False, duration: float = 20.0,
               buildings: int | None = None) -> dict:
    """Generate one case into ``folder``; return its key (family, label, seed, strength, effect NE, impacts).

    ``buildings``: the row's size (default: drawn, 2 or 3); ``duration``: seconds of record.
    """
    import obspy

    dt = 0.001 if family == "distributed-mass" else 0.005
    ag = _record(np.random.default_rng(seed + 1), 0.005, duration)
    t_ag = np.arange(ag.size) * 0.005
    strength = _weak_strength(family, seed, t_ag, ag, dt, buildings) if weak and family not in ("none",) else 1.0
    row, base_edit = _draw(family, seed, strength, buildings)
    rng = np.random.default_rng(seed + 2)  # the noise
    t = np.arange(round(duration / dt) + 1) * dt
    res = simulate(row, t_ag, ag, t)
    effect_ne = 0.0 if family == "none" else _effect_ne(family, seed, strength, t_ag, ag, t, res, buildings)
    folder.mkdir(parents=True, exist_ok=True)
    noisy = lambda x: x + 0.01 * np.sqrt(np.mean(x * x)) * rng.standard_normal(x.size)
    ag_rec = noisy(ag)

    def trace(cid, x, delta):
        net, sta, loc, cha = cid.split(".")
        return obspy.Trace(np.asarray(x, np.float64), header={"network": net, "station": sta, "location": loc, "channel": cha,
                                                                  "delta": delta,
                                                                  "starttime": obspy.UTCDateTime(2021, 3, 1)})

    obspy.Stream([trace("XX.A.00.HNX", ag_rec, 0.005)]).write(str(folder / "ground_motion.mseed"), format="MSEED",
                                                               encoding="FLOAT64")
    chans, st = [], obspy.Stream()
    free = np.interp(t, t_ag, ag_rec)
    st += trace("XX.A.00.HNX", free, dt)
    chans.append(("XX.A.00.HNX", "acceleration", "A", 0))
    for b in row.buildings:
        for f in range(1, b.n + 1):
            cid = f"XX.{b.name}.{f:02d}.HNX"
            st += trace(cid, noisy(res["acc"][(b.name, f)]), dt)
            chans.append((cid, "acceleration", b.name, f))
        cid = f"XX.{b.name}.{b.n:02d}.HYX"
        st += trace(cid, noisy(res["roof"][b.name]), dt)
        chans.append((cid, "displacement", b.name, b.n))
    st.write(str(folder / "recording.mseed"), format="MSEED", encoding="FLOAT64")
    (folder / "channels.toml").write_text("\n".join(
        f'[[channel]]\nid = "{c}"\nquantity = "{q}"\nbuilding = "{b}"\nfloor = {f}\n' for c, q, b, f in chans))
    e = row.restitution if not callable(row.restitution) else BASE_E
    (folder / "model.toml").write_text(_model_text(row, base_edit, dt, e, duration))
    label = "none" if family in ("none", "wrong-parameters") else family
    return {"family": family, "label": label, "seed": seed, "strength": round(strength, 4), "effect_ne": effect_ne,
                "impacts": res["impacts"]}


def main(argv=None) -> int:
    import sys

    argv = sys.argv[1:] if argv is None else list(argv)
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--suite", default="classic")
    if pre.parse_known_args(argv)[0].suite == "outside":  # the held-out suite: suite.py (docs/diagnose_generator.md)
        from .suite import main as outside_main

        return outside_main(argv)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--suite", default="classic", choices=("classic", "outside"),
                    help="classic: the families above; outside: held-out forms (benchmarks/diagnose/suite.py)")
    ap.add_argument("--instances", type=int, default=2)
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--first", type=int, default=1, help="the first case's number")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--jobs", type=int, default=1, help="cases generated at once, in separate processes")
    args = ap.parse_args(argv)
    out = Path(args.out)
    rng = np.random.default_rng(args.seed)
    out.mkdir(parents=True, exist_ok=True)
    key_file = out / ("key.json" if args.first == 1 else f"key-{args.first:03d}.json")
    tasks, k = [], args.first - 1  # seeds drawn in order: the same cases whatever --jobs
    for fam in args.families.split(","):
        for i in range(args.instances):
            k += 1
            tasks.append((f"case-{k:03d}", fam, int(rng.integers(1 << 30)), i % 2 == 1))
    keys = {}

    def done(name, key):
        keys[name] = key
        print(name, key, flush=True)
        key_file.write_text(json.dumps(dict(sorted(keys.items())), indent=2))  # as it goes: a run can start early

    if args.jobs <= 1:
        for name, fam, seed, weak in tasks:
            done(name, write_case(out / name, fam, seed, weak=weak))
    else:
        from concurrent.futures import ProcessPoolExecutor, as_completed

        slow_first = sorted(tasks, key=lambda t: t[1] != "distributed-mass")  # the 1 kHz rod cases take longest
        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            futures = {pool.submit(write_case, out / name, fam, seed, weak): name for name, fam, seed, weak in slow_first}
            for fut in as_completed(futures):
                done(futures[fut], fut.result())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
