"""Every form of every hypothesis starts inside its own bounds (a conformance check over the registry).

A form's null point is the model as given with the form's physics switched off; its fits start
there. A null value outside the bounds its specs state makes ``parse_fit`` refuse the start, and
the form is then never fitted from its null point. Floor masses and storey heights with many
digits are the case that caught it: the body on a joint's mass bounds were printed with "%g",
which rounded the null mass's lower bound above the null mass.
"""

import copy
import tomllib

import pytest

from seispound.calibrate.fit import parse_fit
from seispound.diagnose.hypotheses import REGISTRY, Context
from seispound.model.paths import set_value
from tests._models import REPO

HYPOTHESES = {h.name: h for h in REGISTRY}
FORMS = [(h.name, k) for h in REGISTRY for k in range(h.variants)]
# a recording with building B's base acceleration (the file is not read: a form only writes the model table)
CONTEXT = Context(base_records={"B": {"file": "/data/recording.mseed", "trace": "XX.B.00.HNX", "scale": 1.0}})


def _tables():
    base = tomllib.loads((REPO / "models" / "two_buildings.toml").read_text())
    awkward = copy.deepcopy(base)
    for b, m in zip(awkward["building"], (71451.59138044329, 123456.789)):
        b["floor_masses"] = m
    return {"as bundled": base, "floor masses with many digits": awkward}


@pytest.mark.parametrize("name,k", FORMS, ids=[f"{n}-{k + 1}" for n, k in FORMS])
@pytest.mark.parametrize("which", list(_tables()))
def test_a_forms_null_point_lies_inside_its_bounds(name, k, which):
    aug, specs, null = HYPOTHESES[name].augment(_tables()[which], k, CONTEXT)
    table = copy.deepcopy(aug)
    for path, value in null.items():
        set_value(table, path, value)
    params = parse_fit(specs, table)  # raises InputError for a start outside its bounds
    assert {p.path for p in params} == {s.partition("=")[0] for s in specs}
    for p in params:
        assert p.lo <= p.start <= p.hi, p.path


def test_the_registry_names_every_hypothesis_once_and_diagnose_refuses_others():
    from seispound.diagnose import diagnose
    from seispound.diagnose.hypotheses import ALTERNATIVES
    from seispound.errors import InputError

    names = [h.name for h in REGISTRY]
    assert len(names) == len(set(names))
    assert set(names) == set(HYPOTHESES) and all(h.alternative == (h.name in ALTERNATIVES) for h in REGISTRY)
    assert all(h.variants >= 1 and h.what and h.signature for h in REGISTRY)
    with pytest.raises(InputError, match="hypotheses: unknown hypothesis 'rocking-walls'; one of: distributed-mass"):
        diagnose("no-model.toml", channels="no-channels.toml", hypotheses=["rocking-walls"])


def test_the_recorded_base_form_drives_each_building_with_a_base_channel_by_a_share_of_its_record():
    from seispound.diagnose.hypotheses import HYPOTHESES as PHYSICS

    hyp = PHYSICS["spatially-varying-input"]
    k = next(k for k, f in enumerate(hyp.forms) if getattr(f, "reads_recording", False))
    aug, specs, null = hyp.augment(_tables()["as bundled"], k, CONTEXT)
    assert specs == ["building.B.ground_motion.weight=0:1.5"] and null == {"building.B.ground_motion.weight": 0.0}
    gm = aug["building"][1]["ground_motion"]
    assert (gm["file"], gm["trace"], gm["units"]) == ("/data/recording.mseed", "XX.B.00.HNX", "m/s2")
    assert "ground_motion" not in aug["building"][0]  # A has no base channel: it stands on the row's record
    # only A's base recorded: A driven by its share, B (no base channel) delayed and low-passed
    only_a = Context(base_records={"A": CONTEXT.base_records["B"]})
    aug, specs, null = hyp.augment(_tables()["as bundled"], k, only_a)
    assert [s.partition("=")[0] for s in specs] == ["building.A.ground_motion.weight", "building.B.ground_motion.delay",
                                                    "building.B.ground_motion.lowpass"]
    assert null["building.B.ground_motion.delay"] == 0.0 and "file" not in aug["building"][1]["ground_motion"]
    with pytest.raises(ValueError, match="no building has its base acceleration recorded apart from the model's"):
        hyp.augment(_tables()["as bundled"], k)  # a recording without base channels: the form cannot run
