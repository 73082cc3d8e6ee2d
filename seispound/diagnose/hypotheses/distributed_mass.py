"""Distributed mass: the floors' axial waves and internal vibration at impacts (rod floors, or a body on a joint)."""

from __future__ import annotations

import math

from ._hypothesis import Hypothesis, needs_gaps

# the rod form's segments: SEGMENTS to fit (cheap), refined up to MAX_SEGMENTS where the recording's band holds
# higher axial modes, so that each lies within SEGMENT_ERROR of k times the first (``segments_for``)
SEGMENTS = 4
MAX_SEGMENTS = 8
SEGMENT_ERROR = 0.025


def _distributed_mass(d):
    # every floor an axial rod, 20 m long in the line of impact (assumed), 4 segments; EA fitted per building
    # (the first axial frequency sees EA / L, so the assumed length costs nothing), and the floors' centre of
    # mass per building (a floor heavier toward one face strikes with more or less of its mass); the damping
    # ratio of the first axial mode one value for the row
    specs, null = ["building.*.floor_model.axial_damping=0.002:0.3"], {"building.*.floor_model.axial_damping": 0.02}
    for b in d["building"]:
        b["floor_model"] = {"kind": "rod", "segments": SEGMENTS, "length": 20.0, "axial_stiffness": 1e10,
                            "axial_damping": 0.02, "centre_of_mass": 0.5}
        rod = f"building.{b['name']}.floor_model"
        specs += [f"{rod}.axial_stiffness=1e8:1e13", f"{rod}.centre_of_mass=0.34:0.66"]
        null.update({f"{rod}.axial_stiffness": 1e13, f"{rod}.centre_of_mass": 0.5})
    return specs, null


def segments_for(band_top_hz: float, first_axial_hz: float) -> int:
    """The segments a rod floor needs so that each axial mode below ``band_top_hz`` [Hz] lies within
    SEGMENT_ERROR of k times the first (``first_axial_hz`` [Hz]), as a continuous rod's modes do.

    A uniform rod of N lumped segments has its k-th free-free mode at omega_k = 2 (N c / L) sin(k pi / (2 N))
    (the lumped chain's dispersion relation; derived, and checked against the assembled chain's eigenvalues in
    ``tests/diagnose/test_rod_refine.py``), so with the first fitted, mode k stands at
    sin(k x) / (k sin x) of k f1, x = pi / (2 N): two modes in the band need 8 segments, three 12.  At least
    SEGMENTS (one mode in the band: the fit sets f1 itself), at most MAX_SEGMENTS (each segment adds a DOF per
    floor to every simulation of a fit)."""
    k = int(math.floor(band_top_hz / first_axial_hz + 1e-9))
    for n in range(SEGMENTS, MAX_SEGMENTS):
        x = math.pi / (2.0 * n)
        if k <= 1 or math.sin(k * x) / (k * math.sin(x)) >= 1.0 - SEGMENT_ERROR:
            return n
    return MAX_SEGMENTS


def _finer_rods(d, context):
    """The fitted rod floors with the segments the recording's band asks (``segments_for``, at the lowest
    first axial frequency of any floor of the row), or None when the segments they have suffice.  EA, the
    centre of mass and the damping stay as fitted (the first axial frequency then moves by the
    discretisation's share, 2 % from 4 segments to 8; the polish that follows refits it)."""
    from ..quantities import _first_axial

    if context is None or not context.band_top_hz:
        return None
    rods = [(b, b["floor_model"]) for b in d["building"]
            if (b.get("floor_model") or {}).get("kind") == "rod" and "attachment" not in b["floor_model"]]
    if not rods:
        return None
    f1 = min(_first_axial(max(b["floor_masses"] if isinstance(b["floor_masses"], list) else [b["floor_masses"]]), rod)
             for b, rod in rods)
    n = segments_for(context.band_top_hz, f1)
    if all(n <= rod["segments"] for _, rod in rods):
        return None
    for _, rod in rods:
        rod["segments"] = n
    return d


def _attached(d):
    # a pounding element on a compliant joint (a body bolted or cast on at the contact face): every floor a stiff
    # two-node rod (EA 1e13 N over an assumed 20 m) carrying on each face toward a neighbour a body on a joint;
    # the joint's stiffness fitted per building, the body's mass and the joint's damping one value for the row
    # (null: a body of 0.01 % of the lightest floor on a joint as stiff as the rod).  The body stands for whatever
    # of the floor moves against the rest at the contact face, up to half the lightest floor's mass: the
    # effective mass at a face of a uniform free-free rod in its first axial mode (mode shape cos(pi x / L),
    # modal mass m / 2 at unit end amplitude; derived here), and a floor whose mass gathers toward its contact
    # face holds more there than a uniform rod's half segment
    floors = [m for b in d["building"] for m in (b["floor_masses"] if isinstance(b["floor_masses"], list)
                                                 else [b["floor_masses"]])]
    m_lo, m_hi = 1e-4 * min(floors), 0.5 * min(floors)
    # the bounds in full precision: the null point sits on the lower one, and "%g" rounded it above the value
    specs = [f"building.*.floor_model.attachment.mass={float(m_lo)!r}:{float(m_hi)!r}",
             "building.*.floor_model.attachment.joint_damping=10:1e8"]
    null = {"building.*.floor_model.attachment.mass": m_lo, "building.*.floor_model.attachment.joint_damping": 10.0}
    for b in d["building"]:
        b["floor_model"] = {"kind": "rod", "segments": 1, "length": 20.0, "axial_stiffness": 1e13,
                            "axial_damping": 0.02,
                            "attachment": {"mass": m_lo, "joint_stiffness": 1e12, "joint_damping": 10.0}}
        specs.append(f"building.{b['name']}.floor_model.attachment.joint_stiffness=1e6:1e12")
        null[f"building.{b['name']}.floor_model.attachment.joint_stiffness"] = 1e12
    return specs, null


HYPOTHESIS = Hypothesis(
    "distributed-mass", "the floors' distributed mass: axial waves and internal vibration of the floors at impacts",
    "high-frequency residual on floor channels that starts at each impact",
    forms=(_distributed_mass, _attached), why_not=needs_gaps("to set the floors' axial waves ringing"),
    refine=(_finer_rods, None))
