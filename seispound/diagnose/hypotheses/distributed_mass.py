"""Distributed mass: the floors' axial waves and internal vibration at impacts (rod floors, or a body on a joint)."""

from __future__ import annotations

from ._hypothesis import Hypothesis, needs_gaps


def _distributed_mass(d):
    # every floor an axial rod, 20 m long in the line of impact (assumed), 4 segments; EA fitted per building
    # (the first axial frequency sees EA / L, so the assumed length costs nothing), and the floors' centre of
    # mass per building (a floor heavier toward one face strikes with more or less of its mass); the damping
    # ratio of the first axial mode one value for the row
    specs, null = ["building.*.floor_model.axial_damping=0.002:0.3"], {"building.*.floor_model.axial_damping": 0.02}
    for b in d["building"]:
        b["floor_model"] = {"kind": "rod", "segments": 4, "length": 20.0, "axial_stiffness": 1e10,
                            "axial_damping": 0.02, "centre_of_mass": 0.5}
        rod = f"building.{b['name']}.floor_model"
        specs += [f"{rod}.axial_stiffness=1e8:1e13", f"{rod}.centre_of_mass=0.34:0.66"]
        null.update({f"{rod}.axial_stiffness": 1e13, f"{rod}.centre_of_mass": 0.5})
    return specs, null


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
    forms=(_distributed_mass, _attached), why_not=needs_gaps("to set the floors' axial waves ringing"))
