"""Soil-structure interaction: each building's foundation sways and rocks on the soil (Wolf's cones)."""

from __future__ import annotations

from ._hypothesis import Hypothesis, needs_buildings


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


def _footing(b, share, vs):
    """A rigid 15 m x 15 m footing (assumed) under building table ``b``: its mass and rotary inertia ``share`` of
    the building's, soil of shear-wave velocity ``vs`` [m/s], density 1900 kg/m^3, Poisson 0.3."""
    m = b["floor_masses"]
    total = float(sum(m)) if isinstance(m, list) else float(m) * int(b.get("floors", 1))
    b["foundation"] = {"mass": share * total, "rotary_inertia": share * total * 15.0 ** 2 / 12.0,
                       "soil": {"shear_wave_velocity": vs, "density": 1900.0, "poisson": 0.3, "radiation": 1.0},
                       "footing": {"width": 15.0, "length": 15.0}}


HYPOTHESIS = Hypothesis(
    "soil-structure-interaction", "a flexible foundation: sway and rocking on the soil",
    "the first mode's period and damping off on every floor channel of a building, all record long",
    forms=(_soil, _soil_sized), why_not=needs_buildings)
