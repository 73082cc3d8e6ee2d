"""Spatially varying input: a building's ground motion delayed, delayed and low-passed (wave passage), or the
motion recorded at its base (incoherence that no transformation of the free field describes)."""

from __future__ import annotations

from ._hypothesis import Hypothesis, reads_recording


def _spatial(d):
    # the free field is recorded at the first building: the others' motion delayed (wave passage)
    specs, null = [], {}
    for b in d["building"][1:]:
        b["ground_motion"] = {"delay": 0.0}
        specs.append(f"building.{b['name']}.ground_motion.delay=0:0.3")
        null[f"building.{b['name']}.ground_motion.delay"] = 0.0
    return specs, null


def _filtered(b, nyquist, specs, null):
    # a building's motion delayed and low-passed: null, no delay and a cut-off far above the structure's band
    key = f"building.{b['name']}.ground_motion"
    b["ground_motion"] = {"delay": 0.0, "lowpass": 0.8 * nyquist, "lowpass_order": 2}
    specs += [f"{key}.delay=0:0.3", f"{key}.lowpass=0.5:{float(0.8 * nyquist)!r}"]
    null.update({f"{key}.delay": 0.0, f"{key}.lowpass": 0.8 * nyquist})


def _spatial_filtered(d):
    # the others' motion delayed and low-passed (a wave that loses its high frequencies on the way; the
    # incoherence of a wide foundation)
    nyquist = 0.5 / float(d.get("analysis", {}).get("dt", 0.005))
    specs, null = [], {}
    for b in d["building"][1:]:
        _filtered(b, nyquist, specs, null)
    return specs, null


@reads_recording
def _spatial_recorded(d, ctx):
    # each building whose base acceleration was recorded driven by the free field plus a share w of the difference
    # its base sensor recorded, w a_base + (1 - w) a_free: a partly incoherent motion has a random part that no
    # delay or filter of the free field reproduces, but the sensor records it.  Null: w = 0, the row's record;
    # w = 1, the recorded base motion; up to 1.5 for a base sensor that reads low.  The buildings after the first
    # without a base channel as in ``_spatial_filtered``
    nyquist = 0.5 / float(d.get("analysis", {}).get("dt", 0.005))
    if not any(b["name"] in ctx.base_records for b in d["building"]):
        raise ValueError("no building has its base acceleration recorded apart from the model's input")
    specs, null = [], {}
    for k, b in enumerate(d["building"]):
        rec = ctx.base_records.get(b["name"])
        if rec is None:
            if k > 0:
                _filtered(b, nyquist, specs, null)
            continue
        key = f"building.{b['name']}.ground_motion"
        b["ground_motion"] = {"file": rec["file"], "trace": rec["trace"], "units": "m/s2", "scale": rec["scale"],
                              "weight": 0.0}
        specs.append(f"{key}.weight=0:1.5")
        null[f"{key}.weight"] = 0.0
    return specs, null


def _why_not(d):
    return None if len(d.get("building", [])) >= 2 else ("a single building: the ground motion is the record itself, "
                                                          "there is no second base for it to differ at")


HYPOTHESIS = Hypothesis(
    "spatially-varying-input", "a different ground motion under a building (wave passage)",
    "a building's floor channels out of phase with the model from the start, the free-field building right",
    forms=(_spatial, _spatial_filtered, _spatial_recorded), why_not=_why_not)
