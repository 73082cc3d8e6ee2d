"""The physics a model may have left out: each with the augmentation that adds it and the parameters it fits.

An augmentation edits the model file's table (never the base model's own values) and
names the dotted paths to fit with their bounds, in the calibration's ``PATH=lo:hi`` form
(``building.*.KEY`` ties one value across the row), and its *null point*: the values at which
the augmented model reduces to the base model (rigid floors, constant e, rigid soil, storeys
that never yield, no delay).  Every hypothesis nests the base model, so a fit started at its
null point can only improve on it.  Where a physics needs a quantity the base model does not
state (a floor's length along the line of impact, a footing's size), the augmentation assumes
a stated default and fits the parameter that the data can see instead.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

__all__ = ["ALTERNATIVES", "HYPOTHESES", "Hypothesis"]


@dataclass(frozen=True)
class Hypothesis:
    name: str
    what: str  # what was left out, in words
    signature: str  # what the residual should show

    def applies(self, data: dict) -> str | None:
        """Why this physics cannot apply to the model file's table ``data``, or None when it can."""
        check = _APPLIES.get(self.name)
        return check(data) if check else None

    @property
    def variants(self) -> int:
        """How many forms the augmentation takes (each fitted; the best is kept)."""
        return len(_AUGMENT[self.name])

    def augment(self, data: dict, variant: int = 0) -> tuple[dict, list, dict]:
        """(the augmented model table, the fit specs PATH=lo:hi, the null point {PATH: value})."""
        out = copy.deepcopy(data)
        specs, null = _AUGMENT[self.name][variant](out)
        return out, specs, null


def _names(data):
    return [b["name"] for b in data.get("building", [])]


def _distributed_mass(d):
    # every floor an axial rod, 20 m long in the line of impact (assumed), 4 segments; EA fitted per building
    # (the first axial frequency sees EA / L, so the assumed length costs nothing), the damping ratio of the
    # first axial mode one value for the row
    specs, null = ["building.*.floor_model.axial_damping=0.002:0.3"], {"building.*.floor_model.axial_damping": 0.02}
    for b in d["building"]:
        b["floor_model"] = {"kind": "rod", "segments": 4, "length": 20.0, "axial_stiffness": 1e10,
                            "axial_damping": 0.02}
        specs.append(f"building.{b['name']}.floor_model.axial_stiffness=1e8:1e13")
        null[f"building.{b['name']}.floor_model.axial_stiffness"] = 1e13
    return specs, null


def _attached(d):
    # a pounding element on a compliant joint (a body bolted or cast on at the contact face): every floor a stiff
    # two-node rod (EA 1e13 N over an assumed 20 m) carrying on each face toward a neighbour a body on a joint;
    # the joint's stiffness fitted per building, the body's mass and the joint's damping one value for the row
    # (null: a body of 0.01 % of the lightest floor on a joint as stiff as the rod)
    floors = [m for b in d["building"] for m in (b["floor_masses"] if isinstance(b["floor_masses"], list)
                                                 else [b["floor_masses"]])]
    m_lo, m_hi = 1e-4 * min(floors), 0.1 * min(floors)
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


def _velocity_restitution(d):
    e = d["contact"].get("restitution", 0.65)
    e = float(e) if isinstance(e, (int, float)) else 0.65
    d["contact"]["restitution"] = {"form": "linear", "e0": e, "slope": 0.0, "min": 0.05, "max": 0.99}
    # impacts between storeys close at 0.05-1 m/s: a slope above 5 s/m would span e's whole range within 0.2 m/s;
    # e levels off at a floor (min) for the fastest impacts
    return (["contact.restitution.e0=0.1:0.99", "contact.restitution.slope=0:5", "contact.restitution.min=0.05:0.9"],
            {"contact.restitution.e0": e, "contact.restitution.slope": 0.0, "contact.restitution.min": 0.05})


def _soil(d):
    # a rigid footing (plan 15 m x 15 m, assumed) on soil of fitted shear-wave velocity, density 1900 kg/m^3,
    # Poisson 0.3; foundation mass and rotary inertia from the building's floor masses; the share of the
    # half-space's radiation damping one value for the row (a stratum on rock radiates little: Soil.radiation)
    specs = ["building.*.foundation.soil.radiation=0.01:1"]
    null = {"building.*.foundation.soil.radiation": 1.0}
    for b in d["building"]:
        _footing(b, 0.2, 200.0)
        specs.append(f"building.{b['name']}.foundation.soil.shear_wave_velocity=30:3000")
        null[f"building.{b['name']}.foundation.soil.shear_wave_velocity"] = 3000.0
    return specs, null


def _footing(b, share, vs):
    """A rigid 15 m x 15 m footing (assumed) under building table ``b``: its mass and rotary inertia ``share`` of
    the building's, soil of shear-wave velocity ``vs`` [m/s], density 1900 kg/m^3, Poisson 0.3."""
    m = b["floor_masses"]
    total = float(sum(m)) if isinstance(m, list) else float(m) * int(b.get("floors", 1))
    b["foundation"] = {"mass": share * total, "rotary_inertia": share * total * 15.0 ** 2 / 12.0,
                       "soil": {"shear_wave_velocity": vs, "density": 1900.0, "poisson": 0.3, "radiation": 1.0},
                       "footing": {"width": 15.0, "length": 15.0}}


def _bilinear(d):
    # sharp yielding (bilinear, kinematic hardening): a yield drift per building, the post-yield ratio for the row
    specs = ["building.*.storey_law.post_yield_ratio=0.005:0.5"]
    null = {"building.*.storey_law.post_yield_ratio": 0.05}
    for b in d["building"]:
        b["storey_law"] = {"kind": "bilinear", "yield_drift": 0.02, "post_yield_ratio": 0.05}
        specs.append(f"building.{b['name']}.storey_law.yield_drift=0.0005:5")
        null[f"building.{b['name']}.storey_law.yield_drift"] = 5.0
    return specs, null


def _bouc_wen(d):
    # smooth hysteresis (Bouc-Wen; large exponents approach the bilinear law): a yield drift per building,
    # the post-yield ratio and the exponent one value for the row
    specs = ["building.*.storey_law.post_yield_ratio=0.005:0.5", "building.*.storey_law.n=1:20"]
    null = {"building.*.storey_law.post_yield_ratio": 0.05, "building.*.storey_law.n": 2.0}
    for b in d["building"]:
        b["storey_law"] = {"kind": "bouc-wen", "yield_drift": 0.02, "post_yield_ratio": 0.05, "n": 2.0,
                           "beta": 0.5, "gamma": 0.5}
        specs.append(f"building.{b['name']}.storey_law.yield_drift=0.0005:5")
        null[f"building.{b['name']}.storey_law.yield_drift"] = 5.0
    return specs, null


def _spatial(d):
    # the free field is recorded at the first building: the others' motion delayed (wave passage)
    specs, null = [], {}
    for b in d["building"][1:]:
        b["ground_motion"] = {"delay": 0.0}
        specs.append(f"building.{b['name']}.ground_motion.delay=0:0.3")
        null[f"building.{b['name']}.ground_motion.delay"] = 0.0
    return specs, null


def _exponential_restitution(d):
    # e falls from e0 at slow impacts to e_inf at fast ones over a velocity scale v_c (null: e0 = e_inf = e)
    e = _constant_e(d)
    d["contact"]["restitution"] = {"form": "exponential", "e0": e, "e_inf": e, "v_c": 0.3}
    return (["contact.restitution.e0=0.1:0.99", "contact.restitution.e_inf=0.05:0.99",
             "contact.restitution.v_c=0.02:2"],
            {"contact.restitution.e0": e, "contact.restitution.e_inf": e, "contact.restitution.v_c": 0.3})


def _power_restitution(d):
    # e = e_ref (v / 0.3 m/s)^-exponent, capped at 0.99 (null: exponent 0); Johnson's plastic impact gives 1/4
    e = _constant_e(d)
    d["contact"]["restitution"] = {"form": "power", "e_ref": e, "v_ref": 0.3, "exponent": 0.0, "max": 0.99}
    return (["contact.restitution.e_ref=0.05:0.99", "contact.restitution.exponent=0:1.5"],
            {"contact.restitution.e_ref": e, "contact.restitution.exponent": 0.0})


def _constant_e(d):
    e = d["contact"].get("restitution", 0.65)
    return float(e) if isinstance(e, (int, float)) else 0.65


def _soil_sized(d):
    # each building's own soil and footing: Vs and the footing's width fitted per building, so that sway and
    # rocking (rocking ~ width^3, sway ~ width) are two quantities the data set, not a ratio assumed; a light
    # foundation (1 % of the building's mass); the radiation share one value for the row
    specs = ["building.*.foundation.soil.radiation=0.01:1"]
    null = {"building.*.foundation.soil.radiation": 1.0}
    for b in d["building"]:
        _footing(b, 0.01, 3000.0)
        specs += [f"building.{b['name']}.foundation.soil.shear_wave_velocity=30:3000",
                  f"building.{b['name']}.foundation.footing.width=3:60"]
        null[f"building.{b['name']}.foundation.soil.shear_wave_velocity"] = 3000.0
        null[f"building.{b['name']}.foundation.footing.width"] = 15.0
    return specs, null


def _degrading(d):
    # smooth hysteresis whose strength and stiffness degrade with the energy it dissipates (Baber & Wen 1981):
    # a yield drift per building; post-yield ratio, exponent and the two degradation rates one value for the row
    specs = ["building.*.storey_law.post_yield_ratio=0.005:0.5", "building.*.storey_law.n=1:20",
             "building.*.storey_law.strength_degradation=0:0.2", "building.*.storey_law.stiffness_degradation=0:0.2"]
    null = {"building.*.storey_law.post_yield_ratio": 0.05, "building.*.storey_law.n": 2.0,
            "building.*.storey_law.strength_degradation": 0.0, "building.*.storey_law.stiffness_degradation": 0.0}
    for b in d["building"]:
        b["storey_law"] = {"kind": "bouc-wen", "yield_drift": 0.02, "post_yield_ratio": 0.05, "n": 2.0,
                           "beta": 0.5, "gamma": 0.5, "strength_degradation": 0.0, "stiffness_degradation": 0.0}
        specs.append(f"building.{b['name']}.storey_law.yield_drift=0.0005:5")
        null[f"building.{b['name']}.storey_law.yield_drift"] = 5.0
    return specs, null


def _spatial_filtered(d):
    # the others' motion delayed and low-passed (a wave that loses its high frequencies on the way; the
    # incoherence of a wide foundation); null: no delay, a cut-off far above the structure's band
    nyquist = 0.5 / float(d.get("analysis", {}).get("dt", 0.005))
    specs, null = [], {}
    for b in d["building"][1:]:
        b["ground_motion"] = {"delay": 0.0, "lowpass": 0.8 * nyquist, "lowpass_order": 2}
        specs += [f"building.{b['name']}.ground_motion.delay=0:0.3",
                  f"building.{b['name']}.ground_motion.lowpass=0.5:{float(0.8 * nyquist)!r}"]
        null[f"building.{b['name']}.ground_motion.delay"] = 0.0
        null[f"building.{b['name']}.ground_motion.lowpass"] = 0.8 * nyquist
    return specs, null


def _stiffness_profile(d):
    # the storeys' stiffness distributed otherwise over the height than modelled (a soft first storey, a taper):
    # the first and the top storey's stiffness of every building of two or more storeys fitted on their own,
    # over a factor of 4 either way, while the building's stiffness factor scales the rest
    specs, null = [], {}
    for b in d["building"]:
        if not isinstance(b["storey_stiffness"], list) and int(b.get("floors", 1)) >= 2:
            b["storey_stiffness"] = [b["storey_stiffness"]] * int(b["floors"])  # one value for every storey
        k = b["storey_stiffness"]
        if not isinstance(k, list) or len(k) < 2:
            continue
        for j in (1, len(k)):
            path = f"building.{b['name']}.storey_stiffness.{j}"
            specs.append(f"{path}={0.25 * k[j - 1]!r}:{4.0 * k[j - 1]!r}")
            null[path] = k[j - 1]
    return specs, null


def _needs_gaps(what):
    return lambda d: None if d.get("gap") else f"the model has no gap element, so no impact {what}"


def _needs_two(d):
    return None if len(d.get("building", [])) >= 2 else ("a single building: the ground motion is the record itself, "
                                                          "there is no second base for it to differ at")


def _needs_storeys(d):
    return None if d.get("building") else "the model has no building"


def _needs_profile(d):
    multi = [b for b in d.get("building", []) if int(b.get("floors", 1)) >= 2 or
             (isinstance(b.get("storey_stiffness"), list) and len(b["storey_stiffness"]) >= 2)]
    return None if multi else "no building has two or more storeys whose stiffness could be distributed otherwise"


_APPLIES = {"stiffness-distribution": _needs_profile,
            "velocity-dependent-restitution": _needs_gaps("whose restitution could vary"),
            "spatially-varying-input": _needs_two,
            "distributed-mass": _needs_gaps("to set the floors' axial waves ringing"), "inelastic-storey": _needs_storeys,
            "soil-structure-interaction": _needs_storeys}

_AUGMENT = {"distributed-mass": [_distributed_mass, _attached],
            "velocity-dependent-restitution": [_velocity_restitution, _exponential_restitution, _power_restitution],
            "soil-structure-interaction": [_soil, _soil_sized], "inelastic-storey": [_bouc_wen, _bilinear, _degrading],
            "spatially-varying-input": [_spatial, _spatial_filtered],
            "stiffness-distribution": [_stiffness_profile]}

HYPOTHESES = {
    "distributed-mass": Hypothesis(
        "distributed-mass", "the floors' distributed mass: axial waves and internal vibration of the floors at impacts",
        "high-frequency residual on floor channels that starts at each impact"),
    "velocity-dependent-restitution": Hypothesis(
        "velocity-dependent-restitution", "a coefficient of restitution that changes with the impact velocity",
        "residual concentrated in the impacts, their rebound velocities wrong in opposite directions for strong "
        "and weak impacts"),
    "soil-structure-interaction": Hypothesis(
        "soil-structure-interaction", "a flexible foundation: sway and rocking on the soil",
        "the first mode's period and damping off on every floor channel of a building, all record long"),
    "inelastic-storey": Hypothesis(
        "inelastic-storey", "storeys that yield",
        "residual that grows after the strongest shaking, with a permanent drift in the roof displacement"),
    "spatially-varying-input": Hypothesis(
        "spatially-varying-input", "a different ground motion under a building (wave passage)",
        "a building's floor channels out of phase with the model from the start, the free-field building right"),
}

# wrong parameters beyond what recalibration spans: fitted beside the physics so that a model whose parameters
# are wrong in a way a factor cannot fix is not mistaken for missing physics (a soft first storey is a sway
# spring under the base to within its radiation damping)
ALTERNATIVES = {
    "stiffness-distribution": Hypothesis(
        "stiffness-distribution", "the storeys' stiffness distributed otherwise over the height than modelled",
        "a building's modes off in ratio to one another, which one stiffness factor cannot set right"),
}
