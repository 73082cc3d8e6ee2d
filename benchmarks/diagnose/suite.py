"""The held-out ("outside") suite: concealed physics in forms the hypothesis library does not hold.

``python -m benchmarks.diagnose.generate OUT --suite outside --seed S --instances K --jobs 2``
(or ``python -m benchmarks.diagnose.suite OUT ...``) writes shuffled case folders
``OUT/case-NNN/{model.toml, ground_motion.mseed, recording.mseed, channels.toml}`` (impact
tests: ``trial-N.mseed`` and ``trials.toml`` instead of the recording) and the answers in
``OUT/key.json``.  Recordings come from ``outside.py`` (an independent solve_ivp solver), never
from the package.  The families, forms and draws are listed in ``docs/diagnose_generator.md``;
``FORMS`` below is the table.  ``K`` instances of every form; every other instance weak (strength
0.3-0.5, else 0.7-1.0): strength scales each form's departure from the base model.

The default forms are ``DEFAULT_FORMS``: every form but those whose storey law the package's library now holds
(the keys of ``LIBRARY_HELD``: "takeda", "clough-pinched", "rocking-cone+takeda", "stratum+clough-pinched",
"flag", "rocking-cone+flag", made only with ``--forms``), each replaced, at the end of its chain of replacements,
by "braced" (tension-only X-braced storeys, ``braced.py``: in the place of "takeda", through "flag"), "masing"
(Ramberg-Osgood storeys with Masing's rules, ``masing.py``), "rocking-cone+braced" and "stratum+masing".
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from . import soil as soil_mod
from .outside import Bldg, Row, first_axial_hz, linear_periods, simulate

REPO = Path(__file__).resolve().parents[2]
G = 9.80665
RATES = (100, 200, 250, 500, 1000)  # Hz, drawn per case whatever the family
CONTROLS = ("noise-only", "wrong-e", "wrong-damping", "wrong-mass", "wrong-contact-stiffness", "soft-first-storey",
            "stiffness-distribution", "wrong-storey-height")
# form -> (family, labels)
FORMS = {
    "chain-3": ("distributed-mass", ["distributed-mass"]),
    "chain-6": ("distributed-mass", ["distributed-mass"]),
    "chain-9": ("distributed-mass", ["distributed-mass"]),
    "attachment": ("distributed-mass", ["distributed-mass"]),
    "rocking-cone": ("soil-structure-interaction", ["soil-structure-interaction"]),
    "stratum": ("soil-structure-interaction", ["soil-structure-interaction"]),
    "takeda": ("inelastic-storey", ["inelastic-storey"]),
    "clough-pinched": ("inelastic-storey", ["inelastic-storey"]),
    "flag": ("inelastic-storey", ["inelastic-storey"]),
    "masing": ("inelastic-storey", ["inelastic-storey"]),
    "braced": ("inelastic-storey", ["inelastic-storey"]),
    "reciprocal": ("velocity-dependent-restitution", ["velocity-dependent-restitution"]),
    "johnson": ("velocity-dependent-restitution", ["velocity-dependent-restitution"]),
    "tanh": ("velocity-dependent-restitution", ["velocity-dependent-restitution"]),
    "piecewise": ("velocity-dependent-restitution", ["velocity-dependent-restitution"]),
    "incoherent": ("spatially-varying-input", ["spatially-varying-input"]),
    "incoherent-lowpass": ("spatially-varying-input", ["spatially-varying-input"]),
    "rocking-cone+takeda": ("two-effects", ["soil-structure-interaction", "inelastic-storey"]),
    "chain-6+johnson": ("two-effects", ["distributed-mass", "velocity-dependent-restitution"]),
    "incoherent+reciprocal": ("two-effects", ["spatially-varying-input", "velocity-dependent-restitution"]),
    "stratum+clough-pinched": ("two-effects", ["soil-structure-interaction", "inelastic-storey"]),
    "rocking-cone+flag": ("two-effects", ["soil-structure-interaction", "inelastic-storey"]),
    "stratum+masing": ("two-effects", ["soil-structure-interaction", "inelastic-storey"]),
    "rocking-cone+braced": ("two-effects", ["soil-structure-interaction", "inelastic-storey"]),
    "attachment+tanh": ("two-effects", ["distributed-mass", "velocity-dependent-restitution"]),
    **{c: ("control", ["none"]) for c in CONTROLS},
    "fault-gain": ("instrument-fault", ["instrument-fault"]),
    "fault-drift": ("instrument-fault", ["instrument-fault"]),
    "impact-chain": ("impact", ["distributed-mass"]),
    "impact-ev": ("impact", ["velocity-dependent-restitution"]),
}
EV_FORMS = ("reciprocal", "johnson", "tanh", "piecewise")
# The package's hypothesis library now holds a peak-oriented storey law (Clough / Takeda, with optional pinching), so
# Takeda and pinched-Clough storeys are no longer outside it: the default draw conceals yielding storeys as flag-shaped
# self-centring storeys and Ramberg-Osgood / Masing storeys instead, each in the place of the form it replaces (so
# that every family keeps its number of cases, and every other form its seeds and case numbers).  The library has
# since gained a flag-shaped law (the flag's parametrisation), so the flag forms are replaced in turn, by tension-only
# X-braced storeys: a chain takeda -> flag -> braced, followed to its end (``replacement``).  The replaced forms stay
# in FORMS, to be generated with --forms.
LIBRARY_HELD = {"takeda": "flag", "clough-pinched": "masing", "rocking-cone+takeda": "rocking-cone+flag",
                "stratum+clough-pinched": "stratum+masing", "flag": "braced", "rocking-cone+flag": "rocking-cone+braced"}


def replacement(form):
    """The form that takes ``form``'s place in the default draw: LIBRARY_HELD followed to the end of its chain."""
    seen = {form}
    while form in LIBRARY_HELD:
        form = LIBRARY_HELD[form]
        if form in seen:
            raise ValueError(f"LIBRARY_HELD has a cycle through {form}")
        seen.add(form)
    return form


# every form that is not itself a replacement, in FORMS' order, replaced: so each replacement sits in the place of the
# first form of its chain, and the seeds and case numbers of every other form are those they had before
DEFAULT_FORMS = [replacement(f) for f in FORMS if f not in LIBRARY_HELD.values()]


# ---------------------------------------------------------------------------------------------- inputs
def record(rng, duration):
    """A bundled El Centro component, 200 Hz, its first ``duration`` s, 1 s cosine taper, PGA 0.3-0.45 g."""
    import obspy

    names = sorted(p.name for p in (REPO / "ground_motions").glob("*.AT2"))
    tr = obspy.read(str(REPO / "ground_motions" / names[int(rng.integers(len(names)))]))[0]
    a = tr.data.astype(float) * G
    t0 = np.arange(a.size) * tr.stats.delta
    t = np.arange(round(duration / 0.005) + 1) * 0.005
    x = np.interp(t, t0, a, right=0.0) * np.where(t < 1.0, 0.5 - 0.5 * np.cos(np.pi * np.minimum(t, 1.0)), 1.0)
    return t, x * (rng.uniform(0.3, 0.45) * G / np.abs(x).max())


def draw_svi(rng, strength, lowpass):
    """The parameters of the motion along the row (``varied_inputs``), scaled by the strength."""
    return {"v_app": float(rng.uniform(250.0, 700.0)), "kappa": float(rng.uniform(0.05, 0.2) * strength),
            "vs_coherency": float(rng.uniform(200.0, 500.0)), "strength": strength,
            "fc": float(rng.uniform(5.0, 12.0) / strength) if lowpass else None}


def varied_inputs(rng, ag, dt, xs, par):
    """Ground accelerations along the row: delay + partial incoherence (+ a zero-phase low-pass).

    Building b at distance ``xs[b]`` from A: its motion's Fourier transform is
    gamma A0(w) exp(-i w tau_b) + sqrt(1 - gamma^2) N_b(w), tau_b = strength x_b / V_app, with the
    Luco-Wong coherency gamma = exp(-(kappa w x_b / Vs)^2) (Luco & Wong 1986) and N_b an independent
    noise with A0's amplitude spectrum: random phases, then multiplied by A0's smoothed envelope and
    shaped back to |A0| once.  With ``par["fc"]``: every building's motion (A's too) through a
    second-order Butterworth filter run forwards and backwards (zero phase; base-slab averaging).
    Returns (motions [nb x n], the delays)."""
    from scipy.signal import butter, sosfiltfilt

    n = ag.size
    nf = 2 * n
    A0 = np.fft.rfft(ag, nf)
    w = 2 * np.pi * np.fft.rfftfreq(nf, dt)
    env = np.convolve(np.abs(ag), np.ones(200) / 200, mode="same")
    env /= max(np.sqrt(np.mean(env ** 2)), 1e-30)
    taper = np.where(np.arange(n) * dt < 1.0, 0.5 - 0.5 * np.cos(np.pi * np.minimum(np.arange(n) * dt, 1.0)), 1.0)
    out, delays = [], []
    for x in xs:
        tau = x / par["v_app"] * par["strength"]
        gam = np.exp(-(par["kappa"] * w * x / par["vs_coherency"]) ** 2)
        noise = np.fft.irfft(np.abs(A0) * np.exp(1j * rng.uniform(0, 2 * np.pi, w.size)), nf)[:n] * env
        Nb = np.fft.rfft(noise, nf)
        Nb *= np.abs(A0) / np.maximum(np.abs(Nb), 1e-30)
        # the noise's share tapered like the record (it would otherwise start mid-shaking); the coherent share is
        # the tapered record delayed, so that the motion tends to A's as the strength tends to zero
        ab = np.fft.irfft(gam * A0 * np.exp(-1j * w * tau), nf)[:n] + \
            np.fft.irfft(np.sqrt(1 - gam ** 2) * Nb, nf)[:n] * taper
        if par["fc"] and par["fc"] < 0.45 / dt:
            ab = sosfiltfilt(butter(2, par["fc"], fs=1.0 / dt, output="sos"), ab)
        out.append(ab)
        delays.append(tau)
    return np.array(out), delays


# ------------------------------------------------------------------------------------------- the row
def base_row(rng):
    """Two or three buildings, 3-10 storeys, tapered storey stiffness, 3 m storeys, gaps 1-2 cm, constant e."""
    nb = int(rng.integers(2, 4))
    bs = []
    for i in range(nb):
        n = int(rng.integers(3, 11))
        m = float(rng.uniform(0.8e5, 1.4e5))
        k = float(rng.uniform(1.0e8, 2.2e8))
        bs.append(Bldg("ABC"[i], [m] * (n - 1) + [0.85 * m], list(np.linspace(k, 0.6 * k, n)), [3.0] * n, ratio=0.05))
    gaps = [(i, i + 1, float(rng.uniform(0.01, 0.02))) for i in range(nb - 1)]
    row = Row(bs, gaps, k_contact=2.75e9, restitution=float(rng.uniform(0.55, 0.75)))
    row.extra["plan"] = [(float(rng.uniform(12, 30)), float(rng.uniform(10, 30))) for _ in bs]  # L along the row, B
    return row


def ev_law(form, rng):
    """An e(v0) law outside the library: (function, parameters)."""
    if form == "reciprocal":
        e0, a = rng.uniform(0.85, 0.95), rng.uniform(1.5, 4.0)
        return (lambda v: e0 / (1.0 + a * v)), {"law": "e0/(1+a v)", "e0": e0, "a": a}
    if form == "johnson":
        e1, cap = rng.uniform(0.6, 0.8), rng.uniform(0.85, 0.95)
        c = e1 * 0.1 ** 0.25
        return (lambda v: min(cap, max(0.2, c * max(v, 1e-9) ** -0.25))), {"law": "min(cap, c v^-1/4)", "c": c,
                                                                              "cap": cap}
    if form == "tanh":
        hi, lo, vs = rng.uniform(0.85, 0.95), rng.uniform(0.3, 0.5), rng.uniform(0.15, 0.4)
        return (lambda v: lo + (hi - lo) * (1.0 - math.tanh(v / vs))), {"law": "lo+(hi-lo)(1-tanh(v/vs))", "hi": hi,
                                                                           "lo": lo, "vs": vs}
    if form == "piecewise":
        hi, lo, v1, v2 = rng.uniform(0.85, 0.95), rng.uniform(0.35, 0.5), rng.uniform(0.05, 0.15), rng.uniform(0.3, 0.6)
        return (lambda v: hi if v <= v1 else lo if v >= v2 else hi + (lo - hi) * (v - v1) / (v2 - v1)), \
            {"law": "flat-ramp-flat", "hi": hi, "lo": lo, "v1": v1, "v2": v2}
    raise ValueError(form)


def chain_weights(rng, p):
    """A non-uniform mass profile over p nodes: tributary lengths times 1 + g (x - 1/2) + h sin(pi x)."""
    x = np.linspace(0, 1, p)
    trib = np.r_[0.5, np.ones(p - 2), 0.5] if p > 2 else np.ones(p)
    g = rng.choice([-1, 1]) * rng.uniform(0.5, 1.4)
    h = rng.uniform(-0.5, 0.8)
    return list(trib * np.maximum(1 + g * (x - 0.5) + h * np.sin(np.pi * x), 0.15)), {"g": g, "h": h}


def apply_form(form, row, rng, s, info):
    """Put one form's effect into the generating row at strength s; returns the e(v) law if any."""
    q = info.setdefault("quantities", {})
    if form.startswith("chain-"):
        p = int(form.split("-")[1])
        f1 = rng.uniform(20.0, 60.0) / math.sqrt(s)
        zeta1 = rng.uniform(0.005, 0.06)
        w, prof = chain_weights(rng, p)
        for b in row.buildings:
            ch = {"nodes": p, "weights": w, "k_link": 1.0, "beta_link": 0.0}
            b.chain = ch
            ch["k_link"] = (f1 / first_axial_hz(b)) ** 2  # scaled so that floor 1's first axial mode is at f1
            ch["beta_link"] = 2 * zeta1 / (2 * math.pi * f1)
            per = q.setdefault("buildings", {}).setdefault(b.name, {})
            per["first_axial_hz"] = first_axial_hz(b)
            per["centre_of_mass"] = float(np.dot(w, np.linspace(0.0, 1.0, p)) / np.sum(w))  # of the length
        q["chain"] = {"nodes": p, "mass_profile": prof, "first_mode_damping": zeta1, "stiffness_proportional": True}
    elif form == "attachment":
        mr, fj, zj = rng.uniform(0.02, 0.06), rng.uniform(15.0, 40.0) / math.sqrt(s), rng.uniform(0.05, 0.2)
        for b in row.buildings:
            m = mr * float(np.mean(b.masses))
            k = m * (2 * math.pi * fj) ** 2
            b.attachment = {"mass": m, "k": k, "c": 2 * zj * math.sqrt(k * m)}
        q["attachment"] = {"mass_ratio": mr, "joint_hz": fj, "joint_damping_ratio": zj}
    elif form in ("rocking-cone", "stratum"):
        nu, rho = rng.uniform(0.25, 0.45), rng.uniform(1700.0, 2100.0)
        for b, (L, Bw) in zip(row.buildings, row.extra["plan"]):
            vs = rng.uniform(120.0, 250.0) / math.sqrt(s)
            mt = sum(b.masses)
            m0 = rng.uniform(0.1, 0.4) * mt
            if form == "rocking-cone":
                sm = soil_mod.rocking_cone(L, Bw, nu, vs, rho)
                geo = {"L": L, "B": Bw}
            else:
                r = math.sqrt(L * Bw / math.pi)
                D, H = rng.uniform(0.0, 0.6) * r, rng.uniform(1.5, 4.0) * r
                sm = soil_mod.stratum(r, D, H, nu, vs, rho)
                geo = {"r": r, "embedment": D, "layer_depth": H}
            sm["m0"], sm["I0"] = m0, m0 * (L ** 2 + 1.5 ** 2) / 12.0
            b.soil = sm
            q.setdefault("buildings", {}).setdefault(b.name, {}).update(
                {"soil_vs": vs, "soil_nu": nu, "soil_rho": rho, "foundation_mass": m0, **geo,
                 "sway_stiffness": float(sm["K"][0, 0]), "rocking_stiffness": float(sm["K"][1, 1])})
    elif form in ("takeda", "clough-pinched"):
        alpha = rng.uniform(0.02, 0.1)
        beta = rng.uniform(0.3, 0.5) if form == "takeda" else 0.0
        pinch = None if form == "takeda" else rng.uniform(0.2, 0.5)
        for b in row.buildings:
            dy = float(rng.uniform(0.008, 0.02) / s)
            b.takeda = {"dy": [dy] * b.n, "alpha": alpha, "beta": beta, "pinch": pinch}
            q.setdefault("buildings", {}).setdefault(b.name, {}).update(
                {"yield_drift": dy, "post_yield_ratio": alpha, "unloading_exponent": beta, "pinch": pinch})
    elif form in ("flag", "masing", "braced"):
        if form == "flag":
            # flag-shaped self-centring storeys (flag.py): a post-tensioned connection's stiffness after
            # decompression alpha 0.03-0.15 of the initial; the flag's height beta_f 0.4-0.9 of Fy (below 1:
            # self-centring; the loop then holds about beta_f / 2 of a bilinear loop's energy)
            alpha, beta_f = rng.uniform(0.03, 0.15), rng.uniform(0.4, 0.9)
            law = {"kind": "flag", "alpha": alpha, "beta_f": beta_f}
            key = {"storey_law": "flag", "post_yield_ratio": alpha, "beta_f": beta_f}
        elif form == "masing":
            # Ramberg-Osgood / Masing storeys (masing.py), d = f / k0 (1 + a |f / Fy|^(r - 1)): a 0.3-1.0 (the
            # drift at Fy is 1.3-2 dy), r 4-12 (a gradual knee, as of concrete frames, to a sharp one, as of steel
            # frames)
            a, r = rng.uniform(0.3, 1.0), rng.uniform(4.0, 12.0)
            law = {"kind": "masing", "a": a, "r": r}
            key = {"storey_law": "ramberg-osgood-masing", "ramberg_osgood_a": a, "ramberg_osgood_r": r}
        else:
            # tension-only X-braced storeys (braced.py): an elastic frame of r_f 0.1-0.3 of the initial stiffness, the
            # rest two slender braces that carry tension only, each yielding at the storey's yield drift, hardening a_h
            # 0-0.03 of their elastic stiffness (the storey's post-yield ratio r_f + a_h (1 - r_f))
            r_f, a_h = rng.uniform(0.1, 0.3), rng.uniform(0.0, 0.03)
            law = {"kind": "braced", "r_f": r_f, "a_h": a_h}
            key = {"storey_law": "tension-only-braced", "frame_ratio": r_f, "brace_hardening": a_h,
                   "post_yield_ratio": r_f + a_h * (1.0 - r_f)}
        for b in row.buildings:  # the yield drift (Fy / k0) as the takeda branch draws it
            dy = float(rng.uniform(0.008, 0.02) / s)
            b.hysteresis = {**law, "dy": [dy] * b.n}
            q.setdefault("buildings", {}).setdefault(b.name, {}).update({**key, "yield_drift": dy})
    elif form in EV_FORMS:
        law, par = ev_law(form, rng)
        e_base = law(0.25)  # the base model's constant e: the law's value at 0.25 m/s
        row.restitution = lambda v, law=law, eb=e_base: eb + s * (law(v) - eb)
        row.extra["base_e"] = e_base
        q["restitution_law"] = {**par, "blend": f"e_base + {s:.3f} (law - e_base)", "e_base": e_base}
    elif form in ("incoherent", "incoherent-lowpass"):
        row.extra["svi"] = {"lowpass": form.endswith("lowpass")}
    else:
        raise ValueError(form)


def positions(row):
    xs, x = [0.0], 0.0
    for i in range(1, len(row.buildings)):
        x += 0.5 * (row.extra["plan"][i - 1][0] + row.extra["plan"][i][0]) + row.gaps[i - 1][2]
        xs.append(x)
    return xs


# ------------------------------------------------------------------------------------------ base models
def model_text(row, dt, duration, e, edit=None, impact=None):
    edit = edit or {}
    lines = [f'title = "Row of {len(row.buildings)} buildings, recorded response"', "", "[analysis]", f"dt = {dt}",
             f"duration = {duration}", "newmark = { beta = 0.25, gamma = 0.5 }"]
    if impact:
        lines += [f"contact_substeps = {impact['substeps']}"]
    else:
        lines += ["", "[ground_motion]", 'file = "ground_motion.mseed"', "trace = 0", 'units = "m/s2"', "scale = 1.0"]
    lines += ["", "[contact]", 'law = "Hd"', f"stiffness = {edit.get('k_contact', row.k_contact)}",
              f"restitution = {round(float(edit.get('e', e)), 4)}", ""]
    for i, b in enumerate(row.buildings):
        masses = [m * edit.get("mass_factor", {}).get(b.name, 1.0) for m in b.masses]
        ks = edit.get("stiffness", {}).get(b.name, b.stiffness)
        hs = edit.get("heights", {}).get(b.name, b.heights)
        lines += ["[[building]]", f'name = "{b.name}"', f"floor_masses = {[round(float(m), 3) for m in masses]}",
                  f"storey_stiffness = {[round(float(k), 3) for k in ks]}",
                  f"storey_heights = {[float(h) for h in hs]}"]
        if impact:
            lines += ['damping = { kind = "none" }']
            if b.v0:
                lines += [f"initial_velocity = [{b.v0}]"]
        else:
            lines += [f'damping = {{ kind = "rayleigh", ratio = {edit.get("ratio", b.ratio)}, modes = [1, 2] }}']
        lines += [""]
    for li, ri, size in row.gaps:
        lines += ["[[gap]]", f'between = ["{row.buildings[li].name}", "{row.buildings[ri].name}"]',
                  f"size = {round(float(size), 6)}", ""]
    return "\n".join(lines)


def control_edit(kind, row, rng, s):
    """The base model's error for a control (the truth is ``row``; the edit describes the base model), or an
    edit of the truth itself (key "truth"): (edit, description)."""
    b = row.buildings[int(rng.integers(len(row.buildings)))]
    if kind == "noise-only":
        return {}, {}
    if kind == "wrong-e":
        de = float(rng.choice([-1, 1]) * rng.uniform(0.15, 0.25) * s)
        return {"e": min(max(row.restitution + de, 0.2), 0.95)}, {"true_e": row.restitution, "base_e_offset": de}
    if kind == "wrong-damping":
        true = float(rng.choice([rng.uniform(0.015, 0.03), rng.uniform(0.07, 0.09)]))
        for bb in row.buildings:
            bb.ratio = true
        return {"ratio": 0.05}, {"true_ratio": true, "base_ratio": 0.05}
    if kind == "wrong-mass":
        f = {bb.name: float(rng.choice([rng.uniform(0.8, 0.9), rng.uniform(1.1, 1.25)])) for bb in row.buildings}
        return {"mass_factor": f}, {"base_mass_factor": f}
    if kind == "wrong-contact-stiffness":
        f = float(rng.choice([rng.uniform(0.15, 0.4), rng.uniform(2.5, 6.0)]))
        return {"k_contact": row.k_contact * f}, {"true_k_contact": row.k_contact, "base_factor": f}
    if kind == "soft-first-storey":
        f = float(rng.uniform(0.5, 0.7))
        base = list(b.stiffness)
        b.stiffness = [base[0] * f] + base[1:]
        return {"stiffness": {b.name: base}}, {"building": b.name, "true_first_storey_factor": f}
    if kind == "stiffness-distribution":
        # base uniform and truth tapered (or the reverse), equal total flexibility sum(1/k)
        flex = sum(1.0 / k for k in b.stiffness)
        n = b.n
        taper = np.linspace(1.0, float(rng.uniform(0.4, 0.6)), n)
        taper *= np.sum(1.0 / taper) / flex
        uniform = [n / flex] * n
        if rng.random() < 0.5:
            b.stiffness = list(taper)
            return {"stiffness": {b.name: uniform}}, {"building": b.name, "truth": "linear taper", "base": "uniform"}
        b.stiffness = uniform
        return {"stiffness": {b.name: list(taper)}}, {"building": b.name, "truth": "uniform", "base": "linear taper"}
    if kind == "wrong-storey-height":
        h = float(rng.uniform(3.3, 3.8))
        for bb in row.buildings:
            bb.heights = [h] * bb.n
        return {"heights": {bb.name: [3.0] * bb.n for bb in row.buildings}}, {"true_storey_height": h, "base": 3.0}
    raise ValueError(kind)


# ---------------------------------------------------------------------------------------------- cases
def _trace(cid, x, delta):
    import obspy

    net, sta, loc, cha = cid.split(".")
    return obspy.Trace(np.asarray(x, np.float64), header={"network": net, "station": sta, "location": loc,
                                                          "channel": cha, "delta": delta,
                                                          "starttime": obspy.UTCDateTime(2021, 3, 1)})


def _channels_toml(chans):
    out = ["# channel map for the recording file(s) of this case", ""]
    for c in chans:
        out += ["[[channel]]", f'id = "{c["id"]}"', f'quantity = "{c["quantity"]}"']
        if "gap" in c:
            out += [f"gap = {c['gap']}"]
        else:
            out += [f'building = "{c["building"]}"', f"floor = {c['floor']}"]
        out += [""]
    return "\n".join(out)


def _ne(a, b):
    return float(np.linalg.norm(a - b) / max(np.linalg.norm(a), 1e-30))


def write_case(folder, form, seed, weak=False, duration=20.0, search=True):
    """One case of the outside suite into ``folder``; returns its key entry (with the seconds it took).

    ``weak``: an effect scaled down, by the strength whose effect NE over 8 s is nearest 3.5 % (``search``)
    or by the strength drawn (0.3-0.5, without ``search``)."""
    import time

    t0 = time.perf_counter()
    family = FORMS[form][0]
    refused = []
    for attempt in range(MAX_DRAWS):
        key = write_impact_case(folder, form, seed, weak) if family == "impact" else _write_case(
            folder, form, seed, weak, duration, search)
        why = invisible(key)
        if why is None or attempt == MAX_DRAWS - 1:
            break
        refused.append({"seed": seed, "why": why})
        seed = int(np.random.default_rng(seed).integers(1 << 30))  # a fresh draw of the same form
    if refused:
        key["refused_draws"] = refused
    if why is not None:
        key["invisible"] = why
    key["generator_seconds"] = round(time.perf_counter() - t0, 1)
    return key


NOISE = 0.01  # the instruments' noise: 1 % of each channel's RMS
VISIBLE = 2 * NOISE  # an effect case must depart from its reference by this NE, or it is drawn again
MAX_DRAWS = 5
NEEDS_IMPACTS = ("velocity-dependent-restitution", "distributed-mass", "impact")


def invisible(key) -> str | None:
    """Why a drawn effect case conceals nothing the data can show, or None: its effect NE (recording against
    the row without the effect, noise-free) under VISIBLE, or no impact where the effect acts only in impacts
    (a restitution law, a floor's axial modes).  Such a case tests nothing: a method that names nothing is
    right by the data and wrong by the key.  Controls and instrument faults are never refused."""
    labels = FORMS[key["form"]][1]
    if key["family"] in ("control", "instrument-fault"):
        return None
    if key["impacts"] == 0 and any(lab in NEEDS_IMPACTS for lab in labels + [key["family"]]):
        return "no impact, and the effect acts only in impacts"
    if key["effect_ne"] < VISIBLE:
        return f"effect NE {key['effect_ne']:.4f} < {VISIBLE}"
    return None


EFFECT_FAMILIES = ("distributed-mass", "soil-structure-interaction", "inelastic-storey", "velocity-dependent-restitution",
                   "spatially-varying-input", "two-effects")


def _setup(form, seed, weak, duration, s_override=None):
    """The case's draws, in a fixed order from ``seed`` (the strength only scales, so ``s_override`` changes
    nothing else): the rng (to draw on from), strength, rate, record, the generating row and its inputs, the
    base model's edit, the base model's e."""
    from types import SimpleNamespace

    family, labels = FORMS[form]
    rng = np.random.default_rng(seed)
    s = float(rng.uniform(0.3, 0.5) if weak else rng.uniform(0.7, 1.0))
    if family == "control":
        s = float(rng.uniform(0.5, 1.0))
    if s_override is not None:
        s = float(s_override)
    fs = int(rng.choice(RATES))
    t_ag, ag = record(rng, duration)
    row = base_row(rng)
    info, edit = {}, {}
    law_e = row.restitution
    ag_rows = ag[None, :]
    if family in EFFECT_FAMILIES:
        for part in (form.split("+") if family == "two-effects" else [form]):
            apply_form(part, row, rng, s, info)
        if "svi" in row.extra:
            par = draw_svi(rng, s, row.extra["svi"]["lowpass"])
            ag_rows, delays = varied_inputs(rng, ag, 0.005, positions(row), par)
            info.setdefault("quantities", {})["input"] = {**par, "delays": delays, "positions_m": positions(row)}
    elif family == "control":
        edit, ctrl = control_edit(form, row, rng, s)
        info.setdefault("quantities", {})["control"] = ctrl
    return SimpleNamespace(family=family, labels=labels, rng=rng, s=s, fs=fs, dt=1.0 / fs, t_ag=t_ag, ag=ag, row=row,
                           ag_rows=ag_rows, info=info, edit=edit, law_e=law_e,
                           base_e=row.extra.get("base_e", law_e))


def _run_pair(c, duration):
    """The recording's row and the reference row (without the effect, or the base model's) simulated."""
    t = np.arange(round(duration / c.dt) + 1) * c.dt
    res = simulate(c.row, c.t_ag, c.ag_rows, t, max_step=min(1e-3, c.dt))
    ref = None
    if c.family != "instrument-fault":
        ref = simulate(_reference_row(c.row, c.family, c.edit, c.base_e), c.t_ag, c.ag, t, max_step=min(1e-3, c.dt))
    return t, res, ref


def _pair_ne(res, ref):
    return float(np.mean([_ne(res[q][k], ref[q][k]) for q in ("acc", "roof") for k in res[q]]))


def weak_strength(form, seed, duration, target=0.035, lo=0.02, hi=0.05):
    """A weak instance's strength: the one whose effect NE over the first 8 s is nearest ``target`` (a secant
    search on log NE against log strength, at most 7 runs, from 0.3, as the classic generator does; once the
    target is bracketed, a secant step outside the bracket is replaced by the bracket's geometric mean)."""
    d = min(8.0, duration)
    tried, s = [], 0.3
    for _ in range(7):
        c = _setup(form, seed, True, d, s_override=s)
        ne = max(_pair_ne(*_run_pair(c, d)[1:]), 1e-6)
        tried.append((abs(math.log(ne / target)), s, ne))
        if lo <= ne <= hi:
            break
        slope = 1.0
        if len(tried) > 1:
            (_, s0, n0), (_, s1, n1) = tried[-2], tried[-1]
            slope = math.log(n1 / n0) / math.log(s1 / s0) if s1 != s0 and n1 != n0 else 1.0
            slope = slope if slope > 0.2 else 1.0
        s = float(np.clip(s * (target / ne) ** (1.0 / slope), 1e-3, 1.0))
        below = [x for _, x, n in tried if n < target]
        above = [x for _, x, n in tried if n > target]
        if below and above:  # a threshold (a storey that starts to yield): bisect in log s within the bracket
            a, b = max(below), min(above)
            if not min(a, b) < s < max(a, b):
                s = math.sqrt(a * b)
    return min(tried)[1]


def _write_case(folder, form, seed, weak, duration, search=True):
    import obspy

    s_weak = weak_strength(form, seed, duration) if (weak and search and FORMS[form][0] in EFFECT_FAMILIES) else None
    c = _setup(form, seed, weak, duration, s_override=s_weak)
    family, labels, rng, s, fs, dt = c.family, c.labels, c.rng, c.s, c.fs, c.dt
    row, info, edit, law_e, base_e, t_ag, ag = c.row, c.info, c.edit, c.law_e, c.base_e, c.t_ag, c.ag
    t, res, ref = _run_pair(c, duration)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    nrng = np.random.default_rng(seed + 7)
    noisy = lambda x: x + NOISE * np.sqrt(np.mean(x * x)) * nrng.standard_normal(x.size)
    ag_rec = noisy(ag)
    obspy.Stream([_trace("XX.FF.00.HNX", ag_rec, 0.005)]).write(str(folder / "ground_motion.mseed"), format="MSEED",
                                                                 encoding="FLOAT64")
    chans, data, clean = _instrument(rng, row, res, t, t_ag, ag_rec)
    fault = {}
    if family == "instrument-fault":
        k = int(rng.integers(1, len(chans)))  # never the free field
        x = data[k]
        if form == "fault-gain":
            g = float(rng.choice([rng.uniform(0.7, 0.85), rng.uniform(1.2, 1.4)]))
            data[k] = x * g
            fault = {"channel": chans[k]["id"], "kind": "gain", "gain": g}
        else:
            rms = float(np.sqrt(np.mean(clean[k] ** 2)))
            a0, slope = rng.uniform(0.03, 0.08) * rms, rng.uniform(0.03, 0.08) * rms / duration
            data[k] = x + a0 * np.sign(rng.standard_normal()) + slope * t
            fault = {"channel": chans[k]["id"], "kind": "offset+drift", "offset": a0, "drift_per_s": slope}
        info.setdefault("quantities", {})["fault"] = fault
    st = obspy.Stream([_trace(c["id"], x, dt) for c, x in zip(chans, data)])
    st.write(str(folder / "recording.mseed"), format="MSEED", encoding="FLOAT64")
    (folder / "channels.toml").write_text(_channels_toml(chans))
    (folder / "model.toml").write_text(model_text(row, dt, duration, base_e, edit))
    if family == "instrument-fault":
        effect_ne = float(np.mean([_ne(cl, d) for cl, d in zip(clean, data)]))
    else:
        effect_ne = _pair_ne(res, ref)
    return _key(form, family, labels, seed, s, effect_ne, res, fs, duration, row, info, chans, law_e, base_e)


def _reference_row(row, family, edit, base_e):
    """The row without the concealed effect(s) (effect cases) or the base model's row (controls)."""
    import copy

    ref = copy.deepcopy(row)
    for b in ref.buildings:
        b.chain = b.attachment = b.takeda = b.hysteresis = b.soil = None
    ref.restitution = base_e if callable(row.restitution) else row.restitution
    if family == "control":
        ref.k_contact = edit.get("k_contact", ref.k_contact)
        ref.restitution = edit.get("e", ref.restitution)
        for b in ref.buildings:
            b.masses = [m * edit.get("mass_factor", {}).get(b.name, 1.0) for m in b.masses]
            b.stiffness = list(edit.get("stiffness", {}).get(b.name, b.stiffness))
            b.heights = list(edit.get("heights", {}).get(b.name, b.heights))
            b.ratio = edit.get("ratio", b.ratio)
    return ref


def _instrument(rng, row, res, t, t_ag, ag_rec):
    """Channels like a real deployment: the free field; per building either every floor (and the roof
    displacement) or only base, mid-height and roof (sparse), drawn; 1 % noise."""
    nrng = np.random.default_rng(int(rng.integers(1 << 30)))
    noisy = lambda x: x + NOISE * np.sqrt(np.mean(x * x)) * nrng.standard_normal(x.size)
    chans = [{"id": "XX.FF.00.HNX", "quantity": "acceleration", "building": row.buildings[0].name, "floor": 0}]
    data = [np.interp(t, t_ag, ag_rec)]
    clean = [np.interp(t, t_ag, ag_rec)]
    for b in row.buildings:
        sparse = bool(rng.random() < 0.5)
        floors = sorted({b.n // 2 if b.n > 2 else 1, b.n}) if sparse else list(range(1, b.n + 1))
        with_base = sparse or rng.random() < 0.3
        if with_base:
            x = res["base"][b.name]
            chans.append({"id": f"XX.{b.name}.00.HNX", "quantity": "acceleration", "building": b.name, "floor": 0})
            clean.append(x)
            data.append(noisy(x))
        for f in floors:
            x = res["acc"][(b.name, f)]
            chans.append({"id": f"XX.{b.name}.{f:02d}.HNX", "quantity": "acceleration", "building": b.name,
                          "floor": f})
            clean.append(x)
            data.append(noisy(x))
        if not sparse or rng.random() < 0.5:
            x = res["roof"][b.name]
            chans.append({"id": f"XX.{b.name}.{b.n:02d}.HYX", "quantity": "displacement", "building": b.name,
                          "floor": b.n})
            clean.append(x)
            data.append(noisy(x))
        if sparse:
            row.extra.setdefault("sparse", []).append(b.name)
    return chans, data, clean


def _key(form, family, labels, seed, s, effect_ne, res, fs, duration, row, info, chans, law_e, base_e):
    q = info.get("quantities", {})
    per = q.setdefault("buildings", {})
    for i, b in enumerate(row.buildings):
        d = per.setdefault(b.name, {})
        d["first_period_s"] = linear_periods(row, i)
        d["first_period_fixed_base_s"] = linear_periods(row, i, fixed_base=True)
        d["storeys"] = b.n
        if "input" in q:
            d["delay_s"] = q["input"]["delays"][i]
        else:
            d.setdefault("delay_s", 0.0)
        if b.name in res["peak_drift"]:
            d["peak_drift"] = res["peak_drift"][b.name]
    e = row.restitution
    q["e_at_0.1"] = float(e(0.1)) if callable(e) else float(e)
    q["e_at_0.5"] = float(e(0.5)) if callable(e) else float(e)
    q["base_model_e"] = float(base_e) if not callable(base_e) else None
    q["channels"] = [c["id"] for c in chans]
    q["sparse_buildings"] = row.extra.get("sparse", [])
    return {"family": family, "form": form, "label": labels[0], "labels": labels, "seed": seed,
            "strength": round(s, 4), "effect_ne": effect_ne, "impacts": res["impacts"], "sampling_hz": fs,
            "duration": duration, "quantities": _jsonable(q)}


def _jsonable(x):
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return x


# ------------------------------------------------------------------------------------------ impact tests
def write_impact_case(folder, form, seed, weak=False):
    """Two pendulum slabs (no structural damping), 4-5 trials of different initial velocity, one effect concealed."""
    import obspy

    rng = np.random.default_rng(seed)
    s = float(rng.uniform(0.3, 0.5) if weak else rng.uniform(0.7, 1.0))
    L = 1.5
    ms = [float(rng.uniform(95, 115)), float(rng.uniform(95, 115))]
    row = Row([Bldg("S", [ms[0]], [ms[0] * G / L], [L], ratio=0.0), Bldg("T", [ms[1]], [ms[1] * G / L], [L], ratio=0.0)],
              [(0, 1, 0.0)], k_contact=float(rng.uniform(2.5e9, 5e9)), restitution=float(rng.uniform(0.6, 0.75)))
    info = {"quantities": {}}
    base_e = row.restitution
    if form == "impact-chain":
        p = int(rng.choice([6, 9]))
        w, prof = chain_weights(rng, p)
        f1 = rng.uniform(400.0, 1200.0) / math.sqrt(s)
        zeta1 = rng.uniform(0.01, 0.05)
        for b in row.buildings:
            b.chain = {"nodes": p, "weights": w, "k_link": 1.0, "beta_link": 0.0}
            b.chain["k_link"] = (f1 / first_axial_hz(b)) ** 2
            b.chain["beta_link"] = 2 * zeta1 / (2 * math.pi * f1)
        info["quantities"]["chain"] = {"nodes": p, "mass_profile": prof, "first_axial_hz": f1,
                                       "first_mode_damping": zeta1}
    else:
        law, par = ev_law(str(rng.choice(EV_FORMS)), rng)
        base_e = law(0.25)
        row.restitution = lambda v, law=law, eb=base_e: eb + s * (law(v) - eb)
        info["quantities"]["restitution_law"] = {**par, "e_base": base_e}
    vs = sorted(float(v) for v in rng.uniform(0.05, 0.5, int(rng.integers(4, 6))))
    fs, duration = 10000, 0.03
    dt = 1.0 / fs
    t = np.arange(round(duration / dt) + 1) * dt
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    nrng = np.random.default_rng(seed + 7)
    noisy = lambda x: x + NOISE * np.sqrt(np.mean(x * x)) * nrng.standard_normal(x.size)
    chans = [{"id": "XX.S.01.HNX", "quantity": "acceleration", "building": "S", "floor": 1},
             {"id": "XX.T.01.HNX", "quantity": "acceleration", "building": "T", "floor": 1},
             {"id": "XX.S.01.HYX", "quantity": "displacement", "building": "S", "floor": 1},
             {"id": "XX.T.01.HYX", "quantity": "displacement", "building": "T", "floor": 1},
             {"id": "XX.ST.00.HFX", "quantity": "force", "gap": 1}]
    trials, nes, impacts, e_meas = [], [], 0, []
    import copy

    for k, v in enumerate(vs, 1):
        row.buildings[0].v0 = v
        res = simulate(row, np.array([0.0, 1.0]), np.zeros((2, 2)), t, max_step=2e-5, forces=True)
        ref_row = copy.deepcopy(row)
        for b in ref_row.buildings:
            b.chain = None
        ref_row.restitution = base_e
        ref = simulate(ref_row, np.array([0.0, 1.0]), np.zeros((2, 2)), t, max_step=2e-5, forces=True)
        xs = [res["acc"][("S", 1)], res["acc"][("T", 1)], res["roof"]["S"], res["roof"]["T"], res["force"]]
        rs = [ref["acc"][("S", 1)], ref["acc"][("T", 1)], ref["roof"]["S"], ref["roof"]["T"], ref["force"]]
        nes.append(float(np.mean([_ne(a, b) for a, b in zip(xs, rs)])))
        impacts += res["impacts"]
        if res["v_out"]:
            e_meas.append(-res["v_out"][0] / res["v_in"][0])
        obspy.Stream([_trace(c["id"], noisy(x), dt) for c, x in zip(chans, xs)]).write(
            str(folder / f"trial-{k}.mseed"), format="MSEED", encoding="FLOAT64")
        trials += ["[[trial]]", f'recording = "trial-{k}.mseed"', f'name = "v{k} = {v:.3f} m/s"',
                   f"initial_velocity = {{ S = [{v:.5f}] }}", ""]
    row.buildings[0].v0 = vs[0]
    (folder / "trials.toml").write_text("\n".join(trials))
    (folder / "channels.toml").write_text(_channels_toml(chans))
    (folder / "model.toml").write_text(model_text(row, dt, duration, base_e, impact={"substeps": 64}))
    e = row.restitution
    q = info["quantities"]
    q["e_at_0.1"] = float(e(0.1)) if callable(e) else float(e)
    q["e_at_0.5"] = float(e(0.5)) if callable(e) else float(e)
    q["base_model_e"] = float(base_e)
    q["trial_velocities"] = vs
    q["e_measured_first_impact"] = e_meas
    q["pendulum_period_s"] = 2 * math.pi * math.sqrt(L / G)
    return {"family": "impact", "form": form, "label": FORMS[form][1][0], "labels": FORMS[form][1], "seed": seed,
            "strength": round(s, 4), "effect_ne": float(np.mean(nes)), "impacts": impacts, "sampling_hz": fs,
            "duration": duration, "trials": len(vs), "quantities": _jsonable(q)}


# ------------------------------------------------------------------------------------------------ main
def tasks_for(forms, instances, seed, controls=None):
    """(case name, form, seed, weak) with the case numbers shuffled: the folder number says nothing.

    ``controls``: instances of each control form (default ``instances``)."""
    rng = np.random.default_rng(seed)
    tasks = []
    for form in forms:
        for i in range(controls if (controls is not None and FORMS[form][0] == "control") else instances):
            tasks.append((form, int(rng.integers(1 << 30)), i % 2 == 1))
    order = rng.permutation(len(tasks))
    return [(f"case-{k + 1:03d}", *tasks[j]) for k, j in enumerate(order)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out")
    ap.add_argument("--suite", default="outside")
    ap.add_argument("--instances", type=int, default=2, help="instances of every form")
    ap.add_argument("--forms", default=",".join(DEFAULT_FORMS),
                    help="comma-separated forms (default: all but those the library now holds, LIBRARY_HELD, "
                         "each replaced)")
    ap.add_argument("--controls", type=int, default=None,
                    help="instances of each of the 8 control forms (default --instances; 5 gives 40 controls)")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--duration", type=float, default=20.0, help="seconds of record (earthquake cases)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--no-search", action="store_true",
                    help="weak instances at their drawn strength (0.3-0.5), without the search for a 3.5 %% effect NE")
    args = ap.parse_args(argv)
    forms = [f for f in args.forms.split(",") if f]
    bad = [f for f in forms if f not in FORMS]
    if bad:
        ap.error(f"unknown forms {bad}; known: {', '.join(FORMS)}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tasks = tasks_for(forms, args.instances, args.seed, args.controls)
    keys = {}

    def done(name, key):
        keys[name] = key
        print(name, key["form"], f"strength {key['strength']}, effect NE {key['effect_ne']:.4f}, impacts "
              f"{key['impacts']}, {key['sampling_hz']} Hz, {key['generator_seconds']} s", flush=True)
        (out / "key.json").write_text(json.dumps(dict(sorted(keys.items())), indent=1))

    if args.jobs <= 1:
        for name, form, seed, weak in tasks:
            done(name, write_case(out / name, form, seed, weak, args.duration, not args.no_search))
    else:
        from concurrent.futures import ProcessPoolExecutor, as_completed

        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            futs = {pool.submit(write_case, out / name, form, seed, weak, args.duration, not args.no_search): name
                    for name, form, seed, weak in tasks}
            for fut in as_completed(futs):
                done(futs[fut], fut.result())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
