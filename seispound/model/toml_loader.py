"""Read a model from a TOML file, with one-line errors naming the file and the key."""

from __future__ import annotations

import math
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from ..contact import get_law, restitution_from
from ..errors import InputError, number_array
from ..floor import Attachment, RodFloor
from ..foundation import Footing, Foundation, Soil
from ..storey import StoreyLaw
from ..structure import Building, Gap, NoDamping, RayleighDamping
from .analysis import DEFAULT_TOLERANCE, Analysis, Newmark
from .parts import frozen
from .spec import BuildingMotion, GroundMotionSpec, Model

__all__ = ["load_model", "parse_model", "read_toml"]

_TOP = {"title", "description", "analysis", "ground_motion", "contact", "building", "gap"}
_ANALYSIS = {"dt", "duration", "newmark", "contact_substeps", "rtol", "max_iter", "scheme", "tolerance"}
_NEWMARK = {"beta", "gamma"}
_GROUND = {"file", "format", "dt", "trace", "units", "scale", "calibration", "baseline"}
_BUILDING = {"name", "floors", "floor_masses", "storey_stiffness", "storey_heights", "damping",
             "initial_velocity", "position", "ground_motion", "storey_law", "foundation", "floor_model",
             "storey_stiffness_taper"}
_FLOOR_MODEL = {"kind", "segments", "length", "axial_stiffness", "youngs_modulus", "area", "axial_damping", "sensor",
                "attachment", "centre_of_mass"}
_ATTACHMENT = {"mass", "joint_stiffness", "joint_damping"}
_FOUNDATION = {"mass", "rotary_inertia", "floor_rotary_inertia", "sway_stiffness", "sway_damping",
               "rocking_stiffness", "rocking_damping", "soil", "footing"}
_SOIL = {"shear_wave_velocity", "density", "poisson", "radiation"}
_SOIL_REQUIRED = {"shear_wave_velocity", "density", "poisson"}
_FOOTING = {"width", "length", "radius"}
_STOREY_LAW = {"kind", "yield_drift", "yield_force", "post_yield_ratio", "n", "beta", "gamma", "strength_degradation",
               "stiffness_degradation", "pinching", "pinching_rate", "pinching_width", "unloading_exponent", "yield_spread", "self_centring",
               "energy_dissipation"}
_VARIANT = {"delay", "lowpass", "lowpass_order", "weight"}
_DAMPING = {"kind", "ratio", "modes"}
_LAW_KEYS = {"law", "stiffness", "restitution", "tension", "damping_constant", "exponent"}
_GAP = {"between", "size", "levels"} | _LAW_KEYS


def load_model(path) -> Model:
    """Read and validate a model file.

    Parameters
    ----------
    path : str or Path
        TOML model file; ``ground_motion.file`` is relative to it.

    Returns
    -------
    Model

    Raises
    ------
    InputError
        ``FILE: KEY: what is wrong`` for every problem (missing file, TOML
        syntax, unknown key, wrong type or value, inconsistent lengths ...).
    """
    path = Path(path)
    text, data = read_toml(path, "model")
    try:
        return parse_model(data, base=path.parent, source=str(path), text=text)
    except InputError as err:
        raise err.located(file=path) from None


def read_toml(path: Path, what: str) -> tuple[str, dict]:
    """The text and parsed table of a TOML file; InputError naming the file for a missing or bad one."""
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{what} file not found", file=path) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read {what} file ({exc.__class__.__name__}: {exc})", file=path) from None
    try:
        return text, tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"malformed TOML: {exc}", file=path, key="(syntax)") from None


def parse_model(data: dict, base=Path("."), source=None, text=None, parts=None) -> Model:
    """Build a :class:`Model` from the parsed TOML table ``data``.

    ``parts`` (:class:`~seispound.model.parts.Parts`): read a variant of a model, reusing the buildings
    whose tables an earlier variant read with the same ``parts`` had unchanged; the model is the caller's
    own and must not be changed (see ``model/parts.py``).
    """
    if "model" in data and ("axis" in data or "records" in data):
        raise InputError("is a study file (it names a model and its axes), not a model: run it with "
                         "`seispound study FILE -o STUDY.h5`", key="model")
    _check_keys(data, _TOP, "")
    title = data.get("title", "untitled")
    if not isinstance(title, str):
        raise InputError("must be a string", key="title")

    # -- analysis ----------------------------------------------------------------
    an = _table(data, "analysis", required=True)
    _check_keys(an, _ANALYSIS, "analysis")
    nmk = an.get("newmark", {})
    if not isinstance(nmk, dict):
        raise InputError("must be a table {beta, gamma}", key="analysis.newmark")
    _check_keys(nmk, _NEWMARK, "analysis.newmark")
    newmark = Newmark(beta=nmk.get("beta", 0.25), gamma=nmk.get("gamma", 0.5),
                      contact_substeps=an.get("contact_substeps"), rtol=an.get("rtol", 1e-10),
                      max_iter=an.get("max_iter", 30))
    for req in ("dt", "duration"):
        if req not in an:
            raise InputError("is required", key=f"analysis.{req}")
    analysis = Analysis(dt=an["dt"], duration=an["duration"], newmark=newmark, scheme=an.get("scheme", "exact"),
                        tolerance=an.get("tolerance", DEFAULT_TOLERANCE))
    analysis.validate()

    # -- ground motion (optional: free vibration / impact test) ----------------
    gm = None
    if "ground_motion" in data:
        g = _table(data, "ground_motion")
        _check_keys(g, _GROUND | {"apparent_velocity"}, "ground_motion")
        gm = _record_spec(g, "ground_motion", base)
        if "apparent_velocity" in g:
            gm.apparent_velocity = g["apparent_velocity"]

    # -- contact law ---------------------------------------------------------------
    law = None
    if "contact" in data:
        c = _table(data, "contact")
        law = _make_law(c, "contact")

    # -- buildings -------------------------------------------------------------------
    blist = data.get("building")
    if not isinstance(blist, list) or not blist:
        raise InputError("at least one [[building]] table is required", key="building")
    buildings = []
    for idx, b in enumerate(blist):
        if parts is None:
            buildings.append(_building(b, idx, base))
        else:  # a variant: a building whose table is unchanged is the one read before
            key = (idx, frozen(b), str(base))
            buildings.append(parts.building(key, lambda: _building(b, idx, base)))  # noqa: B023 (called at once)
    # Building validates itself in __post_init__ with keys building.<name>.<field>

    # -- gaps ----------------------------------------------------------------------------
    gaps = []
    for idx, gp in enumerate(data.get("gap", []) or []):
        key = f"gap.{idx + 1}"
        if not isinstance(gp, dict):
            raise InputError("must be a table", key=key)
        _check_keys(gp, _GAP, key)
        for req in ("between", "size"):
            if req not in gp:
                raise InputError("is required", key=f"{key}.{req}")
        own = {k: gp[k] for k in _LAW_KEYS if k in gp}
        glaw = None
        if own:
            other = law is not None and "law" in own and str(own["law"]).lower() != law.name.lower()
            merged = {} if law is None or other else {"law": law.name, **law.get_params()}
            merged = {k: v for k, v in merged.items() if v is not None}
            merged.update(own)
            glaw = _make_law(merged, key)
        gaps.append(Gap(between=tuple(gp["between"]) if isinstance(gp["between"], list) else gp["between"],
                        size=gp["size"], law=glaw, levels=gp.get("levels", "lower")))
    if gaps and law is None and any(g.law is None for g in gaps):
        raise InputError("a [contact] table (law, stiffness, restitution) is required when there are gaps",
                         key="contact")
    model = Model(title=title, buildings=buildings, gaps=gaps, contact=law, analysis=analysis,
                  ground_motion=gm, source=source, text=text)
    if parts is not None:
        model.__dict__["_parts"] = parts  # its kept buildings are validated and laid out once (Model.kept)
    model.validate()  # buildings, gaps (neighbours, common levels, sizes), laws, Newmark stability
    return model


def _building(b, idx: int, base) -> Building:
    """The :class:`Building` of the ``idx``-th (0-based) ``[[building]]`` table ``b``, validated."""
    if not isinstance(b, dict):
        raise InputError("must be a table", key=f"building.{idx + 1}")
    name = b.get("name")
    key = f"building.{name}" if isinstance(name, str) and name else f"building.{idx + 1}"
    _check_keys(b, _BUILDING, key)
    if not isinstance(name, str) or not name.strip():
        raise InputError("is required (a non-empty string)", key=f"{key}.name")
    for req in ("floor_masses", "storey_stiffness", "storey_heights"):
        if req not in b:
            raise InputError("is required", key=f"{key}.{req}")
    floors = b.get("floors")
    fields = {}
    for fld in ("floor_masses", "storey_stiffness", "storey_heights"):
        val = b[fld]
        number_array(val, f"{key}.{fld}")  # a quoted number is reported here, at its own key
        if _number(val) and floors is not None:
            if not isinstance(floors, int) or isinstance(floors, bool) or floors < 1:
                raise InputError(f"must be an integer >= 1, got {floors!r}", key=f"{key}.floors")
            val = [val] * floors
        elif isinstance(val, list) and floors is not None and len(val) != floors:
            raise InputError(f"has {len(val)} entries but floors = {floors}", key=f"{key}.{fld}")
        fields[fld] = val
    if "storey_stiffness_taper" in b:
        fields["storey_stiffness"] = _tapered(fields["storey_stiffness"], b["storey_stiffness_taper"],
                                              f"{key}.storey_stiffness_taper")
    damping = _damping(b.get("damping", {"kind": "rayleigh"}), f"{key}.damping")
    motion = _building_motion(b["ground_motion"], f"{key}.ground_motion", base) if "ground_motion" in b else None
    storey_law = _storey_law(b["storey_law"], f"{key}.storey_law") if "storey_law" in b else None
    foundation = _foundation(b["foundation"], f"{key}.foundation") if "foundation" in b else None
    floor_model = _floor_model(b["floor_model"], f"{key}.floor_model") if "floor_model" in b else None
    return Building(name=name, damping=damping, initial_velocity=b.get("initial_velocity", 0.0),
                    position=b.get("position"), ground_motion=motion, storey_law=storey_law,
                    foundation=foundation, floor_model=floor_model, **fields)


# -- helpers ---------------------------------------------------------------------------
def _tapered(stiffness, taper, key: str) -> list:
    """The storey stiffnesses [N/m] times a smooth factor over the height, 1 at the first storey.

    ``taper`` is the top storey's factor r (a number: storey i of N times r^x, x = (i - 1) / (N - 1), a
    geometric taper), or a table ``{ top = r, middle = m }`` whose log-factor is the quadratic through 1 at
    the first storey, m at mid-height (x = 1/2) and r at the top: ln f(x) = (4 ln m - ln r) x +
    (2 ln r - 4 ln m) x^2 (derived here; m = sqrt(r) is the geometric taper).  One or two numbers that a
    study or a fit can vary (``building.A.storey_stiffness_taper.top``); log-smooth so that every positive
    value keeps every storey's stiffness positive.
    """
    if isinstance(taper, dict):
        _check_keys(taper, {"top", "middle"}, key)
        if "top" not in taper:
            raise InputError("is required (the top storey's factor)", key=f"{key}.top")
        top, mid = taper["top"], taper.get("middle")
        for name, v in (("top", top), ("middle", mid)):
            if v is not None and (not _number(v) or not math.isfinite(v) or not v > 0):
                raise InputError(f"must be a number > 0 (1: no taper), got {v!r}", key=f"{key}.{name}")
    elif not _number(taper) or not math.isfinite(taper) or not taper > 0:
        raise InputError(f"must be a number > 0 (the top storey's factor; 1: no taper) or a table "
                         f"{{ top, middle }}, got {taper!r}", key=key)
    else:
        top, mid = taper, None
    if not isinstance(stiffness, list):
        raise InputError("needs the storey stiffnesses as a list, or floors = N with one value", key=key)
    n = len(stiffness)
    if n < 2:
        raise InputError("needs a building of two or more storeys", key=key)
    lt = math.log(float(top))
    lm = 0.5 * lt if mid is None else math.log(float(mid))
    a, b = 4.0 * lm - lt, 2.0 * lt - 4.0 * lm
    out = []
    for i, k in enumerate(stiffness):
        x = i / (n - 1)
        out.append(float(k) if i == 0 else float(k) * math.exp(a * x + b * x * x))
    return out


def _record_spec(g: dict, key: str, base) -> GroundMotionSpec:
    """A record's settings (``[ground_motion]`` or a building's own ``ground_motion``) as a GroundMotionSpec."""
    if "file" not in g or not isinstance(g["file"], str) or not g["file"]:
        raise InputError("is required (a record file relative to the model file)", key=f"{key}.file")
    fpath = (Path(base) / g["file"]).resolve()
    if not fpath.is_file():
        raise InputError(f"record file not found: {fpath}", key=f"{key}.file")
    trace = g.get("trace", 0)
    if not isinstance(trace, (int, str)) or isinstance(trace, bool):
        raise InputError(f"must be an index or a channel/id string, got {trace!r}", key=f"{key}.trace")
    units = g.get("units", "auto")
    if not isinstance(units, str):
        raise InputError(f"must be a string, got {units!r}", key=f"{key}.units")
    from ..motion.units import _canonical_units

    try:
        _canonical_units(units, None)  # fail at load time, before any work
    except InputError as err:
        raise InputError(err.message, key=f"{key}.units") from None
    scale = g.get("scale", 1.0)
    if not _number(scale) or not scale > 0:
        raise InputError(f"must be a number > 0, got {scale!r}", key=f"{key}.scale")
    cal = g.get("calibration")
    if cal is not None and (not _number(cal) or not cal > 0):
        raise InputError(f"must be a number > 0 (m/s^2 per count), got {cal!r}", key=f"{key}.calibration")
    baseline = g.get("baseline", None)
    if baseline is not None and (not isinstance(baseline, int) or isinstance(baseline, bool)
                                 or not 0 <= baseline <= 3):
        raise InputError(f"must be a polynomial order 0..3, got {baseline!r}", key=f"{key}.baseline")
    fmt = _record_format(g.get("format"), f"{key}.format")
    rec_dt = g.get("dt")
    if rec_dt is not None and (not _number(rec_dt) or not rec_dt > 0):
        raise InputError(f"must be a time step > 0 in s, got {rec_dt!r}", key=f"{key}.dt")
    if rec_dt is not None and fmt != "text":
        raise InputError('is stated only for text records (format = "text"); other formats carry their own '
                         "time step", key=f"{key}.dt")
    return GroundMotionSpec(file=fpath, trace=trace, units=units, scale=float(scale), calibration=cal,
                            baseline=baseline, format=fmt, dt=rec_dt)



def _building_motion(g, key: str, base) -> BuildingMotion:
    """``[[building]] ground_motion = { delay, lowpass, lowpass_order }``, optionally with a record of its own
    (``file`` and the record keys, and ``weight``: its share of the building's motion)."""
    if not isinstance(g, dict):
        raise InputError("must be a table { delay, lowpass, lowpass_order } or a record { file, units, ... }",
                         key=key)
    _check_keys(g, _GROUND | _VARIANT, key)
    record = _record_spec(g, key, base) if "file" in g else None
    own = set(g) & ((_GROUND - {"file"}) | {"weight"})
    if record is None and own:
        raise InputError(f"{', '.join(sorted(own))} describe a record of the building's own, which "
                         "needs a file", key=f"{key}.file")
    motion = BuildingMotion(delay=g.get("delay", 0.0), lowpass=g.get("lowpass"),
                            lowpass_order=g.get("lowpass_order", 2), record=record, weight=g.get("weight", 1.0))
    motion.validate(key)
    return motion

def record_formats() -> list[str]:
    """Names ``[ground_motion] format`` accepts: obspy's waveform formats (with PEER_AT2) and "text"."""
    from obspy.core.util.base import ENTRY_POINTS

    return sorted(ENTRY_POINTS["waveform"]) + ["text"]


def _record_format(fmt, key="ground_motion.format"):
    if fmt is None:
        return None
    names = record_formats()
    hits = [n for n in names if isinstance(fmt, str) and n.lower() == fmt.strip().lower()]
    if not hits:
        raise InputError(f"unknown record format {fmt!r}; one of: {', '.join(names)}", key=key)
    return hits[0]


def _number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _table(data, key, required=False) -> dict:
    val = data.get(key)
    if val is None:
        if required:
            raise InputError(f"a [{key}] table is required", key=key)
        return {}
    if not isinstance(val, dict):
        raise InputError("must be a table", key=key)
    return val


def _check_keys(table: dict, allowed: set, where: str) -> None:
    for k in table:
        if k not in allowed:
            full = f"{where}.{k}" if where else k
            raise InputError(f"unknown key; allowed here: {', '.join(sorted(allowed))}", key=full)


def _make_law(c: dict, key: str):
    if "law" not in c:
        _check_keys(c, _LAW_KEYS | ({"between", "size"} if key.startswith("gap") else set()), key)
        raise InputError("is required (one of the names listed by `seispound laws`)", key=f"{key}.law")
    try:
        cls = get_law(c["law"])
    except InputError as err:
        raise InputError(err.message, key=f"{key}.law") from None
    names = cls.param_names()
    _check_keys(c, {"law", *names} | ({"between", "size"} if key.startswith("gap") else set()), key)
    if "stiffness" not in c:
        raise InputError("is required", key=f"{key}.stiffness")
    params = {k: c[k] for k in names if k in c}
    if "restitution" in names and "restitution" not in params and cls.name != "Hertz":
        raise InputError("is required", key=f"{key}.restitution")
    if "restitution" in params:  # a number, or e(v0) as {form = ...} (contact/restitution.py)
        params["restitution"] = restitution_from(params["restitution"], f"{key}.restitution")
    law = cls(**params)
    law.validate(key=key)
    return law


def _storey_law(d, key):
    """``[[building]] storey_law = { kind, yield_drift or yield_force, post_yield_ratio, n, beta, gamma }``."""
    if not isinstance(d, dict):
        raise InputError('must be a table {kind = "bilinear" | "bouc-wen" | "peak-oriented" | "iwan" | "flag", yield_drift or '
                         'yield_force, post_yield_ratio, ...}', key=key)
    _check_keys(d, _STOREY_LAW, key)
    if "kind" not in d:
        raise InputError('is required ("elastic", "bilinear", "bouc-wen", "peak-oriented", "iwan" or "flag")', key=f"{key}.kind")
    if not isinstance(d["kind"], str):
        raise InputError(f"must be a string, got {d['kind']!r}", key=f"{key}.kind")
    return StoreyLaw(**d)


def _foundation(d, key):
    """``[[building]] foundation = { mass, rotary_inertia, ..., springs and dashpots or soil and footing }``."""
    if not isinstance(d, dict):
        raise InputError("must be a table { mass, rotary_inertia, sway_stiffness, ... } or "
                         "{ mass, rotary_inertia, soil = {...}, footing = {...} }", key=key)
    _check_keys(d, _FOUNDATION, key)
    if "mass" not in d:
        raise InputError("is required (the foundation's mass, kg)", key=f"{key}.mass")
    parts = {}
    for name, allowed, cls in (("soil", _SOIL, Soil), ("footing", _FOOTING, Footing)):
        if name in d:
            t = d[name]
            if not isinstance(t, dict):
                raise InputError("must be a table", key=f"{key}.{name}")
            _check_keys(t, allowed, f"{key}.{name}")
            if name == "soil":
                for k in sorted(_SOIL_REQUIRED - set(t)):
                    raise InputError("is required", key=f"{key}.soil.{k}")
            parts[name] = cls(**t)
    return Foundation(**{k: v for k, v in d.items() if k not in parts}, **parts)


def _floor_model(d, key):
    """``[[building]] floor_model = { kind = "rod", segments, length, axial_stiffness, ..., attachment = {...} }``."""
    if not isinstance(d, dict):
        raise InputError('must be a table { kind = "rod", segments, length, axial_stiffness, ... }', key=key)
    _check_keys(d, _FLOOR_MODEL, key)
    kind = d.get("kind", "rod")
    if kind == "lumped":
        return None
    if kind != "rod":
        raise InputError(f'must be "rod" or "lumped", got {kind!r}', key=f"{key}.kind")
    for req in ("segments", "length"):
        if req not in d:
            raise InputError("is required", key=f"{key}.{req}")
    att = None
    if "attachment" in d:
        a = d["attachment"]
        if not isinstance(a, dict):
            raise InputError("must be a table { mass, joint_stiffness, joint_damping }", key=f"{key}.attachment")
        _check_keys(a, _ATTACHMENT, f"{key}.attachment")
        for req in ("mass", "joint_stiffness"):
            if req not in a:
                raise InputError("is required", key=f"{key}.attachment.{req}")
        att = Attachment(**a)
    return RodFloor(**{k: v for k, v in d.items() if k not in ("kind", "attachment")}, attachment=att)


def _damping(d, key):
    if not isinstance(d, dict):
        raise InputError('must be a table {kind = "rayleigh", ratio, modes}', key=key)
    _check_keys(d, _DAMPING, key)
    kind = d.get("kind", "rayleigh")
    if kind == "none":
        return NoDamping()
    if kind != "rayleigh":
        raise InputError(f'kind must be "rayleigh" or "none", got {kind!r}', key=f"{key}.kind")
    ratio = d.get("ratio", 0.05)
    if not _number(ratio):
        raise InputError(f"must be a number, got {ratio!r}", key=f"{key}.ratio")
    modes = d.get("modes")
    if modes is not None and not isinstance(modes, list):
        raise InputError(f"must be a list of two mode numbers, got {modes!r}", key=f"{key}.modes")
    return RayleighDamping(ratio=float(ratio), modes=None if modes is None else tuple(modes))
