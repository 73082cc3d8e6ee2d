"""Study files: a base model, the records, and the axes of parameters to vary.

A study file (TOML)::

    title = "Gap study"
    model = "row_of_three.toml"          # relative to the study file

    [records]                            # one or more of:
    bundled = ["elcentro_180"]           #   names in ground_motions/catalogue.toml
    files = ["../records/x.AT2"]         #   files, relative to the study file
    glob = "../records/*.AT2"            #   a folder pattern

    [[axis]]
    name = "law"                         # dimension name in the store (default: the path)
    path = "contact.law"                 # dotted path into the model file
    values = ["Hd", "LVe"]

    [[axis]]
    name = "gap_size"
    path = "gap.*.size"                  # every gap at once
    range = {start = 0.005, stop = 0.04, num = 8, spacing = "linear"}   # or "log"

    [[axis]]
    name = "stiffer"
    zip = [{path = "building.A.storey_stiffness", factors = [1.0, 1.5]},
           {path = "building.B.storey_stiffness", factors = [1.5, 1.0]}]

    [output]
    histories = ["pounding_force"]       # optional time histories to keep
    decimate = 2                         # keep every 2nd analysis instant

Each axis gives its values by ``values`` (a list), ``range`` (``start``,
``stop``, ``num``, ``spacing``) or ``factors`` (multiplying the base model's
value, a number or a list such as storey stiffnesses); ``zip`` varies several
paths together, entry by entry.  The records vary the model's
``ground_motion.file``; the rest of its ``[ground_motion]`` table (units, trace,
scale) applies to every record.

Every path and every value is checked against the model before any run starts;
a problem raises InputError naming the study file and the axis key.
"""

from __future__ import annotations

import copy
import glob as _glob
import hashlib
import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import numpy as np

from ..errors import InputError
from ..model.paths import get_value, resolve, scaled, set_value
from .schema import HISTORY_VARIABLES, RESERVED_DIMS

__all__ = ["Axis", "Member", "Record", "Study", "load_study"]

_TOP = {"title", "description", "model", "records", "axis", "output"}
_RECORDS = {"bundled", "files", "glob"}
_AXIS = {"name", "path", "values", "range", "factors", "zip"}
_MEMBER = {"path", "values", "range", "factors"}
_RANGE = {"start", "stop", "num", "spacing"}
_OUTPUT = {"histories", "decimate"}

# paths that leave the no-pounding twin unchanged (it has no gaps and no contact)
_TWIN_FREE_PREFIXES = ("gap.", "contact.")


@dataclass(frozen=True)
class Member:
    """One varied path of an axis: ``values`` replace the model value, or multiply it (``factor``)."""

    path: str
    values: tuple
    factor: bool = False


@dataclass(frozen=True)
class Axis:
    """A study dimension: one path (or several zipped) and its n values."""

    name: str
    members: tuple

    @property
    def size(self) -> int:
        return len(self.members[0].values)

    @property
    def zipped(self) -> bool:
        return len(self.members) > 1

    def coordinate(self) -> np.ndarray:
        """The coordinate along this dimension: the values of its (first) path, or 0..n-1 for a
        zipped axis whose first path repeats a value or is a factor."""
        first = self.members[0]
        if self.zipped and (first.factor or len({_hashable(v) for v in first.values}) < self.size):
            return np.arange(self.size)
        return _coord_array(first.values)

    def describe(self) -> dict:
        return {"name": self.name, "members": [{"path": m.path, "factor": m.factor, "values": list(m.values)}
                                               for m in self.members]}


@dataclass(frozen=True)
class Record:
    """A ground-motion record of the study: coordinate name, file, sha256 of its bytes."""

    name: str
    file: Path
    sha256: str


@dataclass
class Study:
    """A parsed, validated study.  Runs are numbered in C order over ``shape``."""

    path: Path
    text: str
    title: str
    model_path: Path
    model_text: str
    model_data: dict
    records: list
    axes: list
    histories: tuple = ()
    decimate: int = 1
    meta: dict = field(default_factory=dict)  # structure of the base model (buildings, floors, gaps)

    @property
    def run_dims(self) -> tuple:
        return ("record", *(a.name for a in self.axes))

    @property
    def shape(self) -> tuple:
        return (len(self.records), *(a.size for a in self.axes))

    @property
    def n_runs(self) -> int:
        return int(np.prod(self.shape))

    def run_position(self, index: int) -> tuple:
        """The position (record, axis values ...) of run ``index``."""
        return tuple(int(i) for i in np.unravel_index(index, self.shape))

    def overrides(self, index: int) -> list:
        """(path, value, is_factor) applied to the base model for run ``index`` (record excluded)."""
        pos = self.run_position(index)
        out = []
        for ax, k in zip(self.axes, pos[1:]):
            for m in ax.members:
                out.append((m.path, m.values[k], m.factor))
        return out

    def model_data_for(self, index: int) -> dict:
        """The model file's table for run ``index``: record and axis values applied."""
        pos = self.run_position(index)
        return _apply(self.model_data, self.records[pos[0]].file, self.overrides(index), self.model_path)

    def model_for(self, index: int, parts=None):
        """The :class:`~seispound.model.Model` of run ``index``.

        ``parts`` (:class:`~seispound.model.parts.Parts`): read it as a variant of the study's model, reusing
        the buildings the axes left unchanged; the model must then not be changed (the workers' runs).
        """
        from ..model.toml_loader import parse_model

        data = self.model_data_for(index)
        return parse_model(data, base=self.model_path.parent, source=str(self.model_path), text=self.model_text,
                           parts=parts)

    def twin_key(self, index: int) -> tuple:
        """Runs with equal keys share their no-pounding twin (gaps and contact law do not change it)."""
        pos = self.run_position(index)
        rest = tuple((p, _hashable(v), f) for p, v, f in self.overrides(index)
                     if not p.startswith(_TWIN_FREE_PREFIXES))
        return (pos[0], rest)

    def definition(self) -> dict:
        """Everything the results depend on (what a resumed study must match)."""
        from .. import __version__

        return {"model_text": self.model_text, "records": [(r.name, r.sha256) for r in self.records],
                "axes": [a.describe() for a in self.axes], "histories": list(self.histories),
                "decimate": self.decimate, "seispound_version": __version__}

    def hash(self) -> str:
        blob = json.dumps(self.definition(), sort_keys=True, default=str).encode()
        return hashlib.sha256(blob).hexdigest()


def load_study(path) -> Study:
    """Read a study file, resolve its records and axes, and check every value against the model.

    Raises InputError ``STUDY: KEY: message`` for any problem, before any run.
    """
    from ..model.toml_loader import read_toml

    path = Path(path)
    text, data = read_toml(path, "study")
    try:
        return _parse(data, path, text)
    except InputError as err:
        raise err.located(file=path) from None


def _parse(data: dict, path: Path, text: str) -> Study:
    from ..model.toml_loader import load_model

    _check_keys(data, _TOP, "")
    title = data.get("title", path.stem)
    if not isinstance(title, str):
        raise InputError("must be a string", key="title")
    mfile = data.get("model")
    if not isinstance(mfile, str) or not mfile:
        raise InputError("is required: the base model file, relative to the study file", key="model")
    model_path = (path.parent / mfile).resolve()
    try:
        base = load_model(model_path)  # the base model must be valid on its own
    except InputError as err:
        raise InputError(f"the base model is invalid: {err}", key="model") from None
    model_text = base.text
    model_data = tomllib.loads(model_text)
    records = _records(data.get("records"), path.parent)
    axes = _axes(data.get("axis"), model_data)
    histories, decimate = _output(data.get("output"))
    if histories:
        timed = [m.path for a in axes for m in a.members if m.path.startswith("analysis.")]
        if timed:
            raise InputError(f"histories need one time axis for every run, but {timed[0]} varies it; "
                             "keep histories or that axis", key="output.histories")
    study = Study(path=path, text=text, title=title, model_path=model_path, model_text=model_text,
                  model_data=model_data, records=records, axes=axes, histories=histories, decimate=decimate)
    _validate_values(study, base)
    return study


# -- records ---------------------------------------------------------------------------
def _records(tab, folder: Path) -> list:
    if not isinstance(tab, dict) or not tab:
        raise InputError("a [records] table is required (bundled, files or glob)", key="records")
    _check_keys(tab, _RECORDS, "records")
    found: list[tuple[str, Path, str]] = []
    if "bundled" in tab:
        from ..motion.catalogue import bundled_path

        names = tab["bundled"]
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            raise InputError("must be a list of record names from ground_motions/catalogue.toml", key="records.bundled")
        for n in names:
            try:
                found.append((n, Path(bundled_path(n)), "records.bundled"))
            except (InputError, KeyError, FileNotFoundError) as err:
                raise InputError(f"unknown bundled record {n!r} ({err})", key="records.bundled") from None
    if "files" in tab:
        files = tab["files"]
        if not isinstance(files, list) or not all(isinstance(f, str) and f for f in files):
            raise InputError("must be a list of record files relative to the study file", key="records.files")
        for f in files:
            p = (folder / f).resolve()
            if not p.is_file():
                raise InputError(f"record file not found: {p}", key="records.files")
            found.append((p.stem, p, "records.files"))
    if "glob" in tab:
        pat = tab["glob"]
        if not isinstance(pat, str) or not pat:
            raise InputError("must be a file pattern relative to the study file", key="records.glob")
        hits = sorted(Path(p).resolve() for p in _glob.glob(str(folder / pat)) if Path(p).is_file())
        if not hits:
            raise InputError(f"matches no file: {folder / pat}", key="records.glob")
        found.extend((p.stem, p, "records.glob") for p in hits)
    if not found:
        raise InputError("lists no record", key="records")
    names = [n for n, _, _ in found]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise InputError(f"record names must be unique; repeated: {', '.join(dup)}", key="records")
    out = []
    for n, p, key in found:
        try:
            digest = hashlib.sha256(p.read_bytes()).hexdigest()
        except OSError as exc:
            raise InputError(f"cannot read record {p} ({exc.__class__.__name__})", key=key) from None
        out.append(Record(name=n, file=p, sha256=digest))
    return out


# -- axes ------------------------------------------------------------------------------
def _axes(items, model_data) -> list:
    if items is None:
        return []
    if not isinstance(items, list):
        raise InputError("must be an array of tables [[axis]]", key="axis")
    axes = []
    for k, a in enumerate(items):
        key = f"axis.{k + 1}"
        if not isinstance(a, dict):
            raise InputError("must be a table", key=key)
        _check_keys(a, _AXIS, key)
        if "zip" in a:
            extra = sorted(set(a) - {"zip", "name"})
            if extra:
                raise InputError(f"a zipped axis takes only name and zip, not {', '.join(extra)}", key=key)
            zs = a["zip"]
            if not isinstance(zs, list) or len(zs) < 1 or not all(isinstance(z, dict) for z in zs):
                raise InputError("must be a list of tables {path, values | range | factors}", key=f"{key}.zip")
            members = tuple(_member(z, model_data, f"{key}.zip.{j + 1}") for j, z in enumerate(zs))
            sizes = {len(m.values) for m in members}
            if len(sizes) != 1:
                raise InputError(f"zipped paths must have as many values each; got {sorted(sizes)}", key=f"{key}.zip")
            name = a.get("name")
            if name is None:
                raise InputError("a zipped axis needs a name", key=f"{key}.name")
        else:
            members = (_member(a, model_data, key, allowed=_AXIS - {"zip"}),)
            name = a.get("name", members[0].path)
        if not isinstance(name, str) or not name or "/" in name:
            raise InputError(f"must be a non-empty string without '/', got {name!r}", key=f"{key}.name")
        if name in RESERVED_DIMS:
            raise InputError(f"{name!r} is a dimension of the store already; choose another axis name",
                             key=f"{key}.name")
        if any(name == ax.name for ax in axes):
            raise InputError(f"axis name {name!r} is used twice", key=f"{key}.name")
        axes.append(Axis(name=name, members=members))
    paths = [m.path for ax in axes for m in ax.members]
    dup = sorted({p for p in paths if paths.count(p) > 1})
    if dup:
        raise InputError(f"a path may be varied by one axis only; repeated: {', '.join(dup)}", key="axis")
    return axes


def _member(tab: dict, model_data: dict, key: str, allowed=_MEMBER) -> Member:
    _check_keys(tab, allowed, key)
    mpath = tab.get("path")
    if not isinstance(mpath, str) or not mpath:
        raise InputError("is required: a dotted path into the model file, like gap.1.size", key=f"{key}.path")
    if mpath == "ground_motion.file":
        raise InputError("records are varied by [records], not by an axis", key=f"{key}.path")
    try:
        resolve(model_data, mpath)
    except InputError as err:
        raise InputError(f"{mpath}: {err.message}", key=f"{key}.path") from None
    given = [k for k in ("values", "range", "factors") if k in tab]
    if len(given) != 1:
        raise InputError("give exactly one of values, range or factors", key=key)
    kind = given[0]
    if kind == "range":
        vals = _range(tab["range"], f"{key}.range")
    else:
        vals = tab[kind]
        if not isinstance(vals, list) or not vals:
            raise InputError("must be a non-empty list", key=f"{key}.{kind}")
    if kind == "factors":
        try:
            base = get_value(model_data, mpath)
        except KeyError:
            raise InputError(f"{mpath} is not set in the model, so it has nothing to multiply",
                             key=f"{key}.factors") from None
        for f in vals:
            scaled(base, f, f"{key}.factors")
    types = {type(v) for v in vals}
    if len({t for t in types if t not in (int, float)} | ({float} if types & {int, float} else set())) > 1:
        raise InputError("values must be all numbers or all of one type", key=f"{key}.{kind}")
    return Member(path=mpath, values=tuple(vals), factor=kind == "factors")


def _range(r, key: str) -> list:
    if not isinstance(r, dict):
        raise InputError("must be a table {start, stop, num, spacing}", key=key)
    _check_keys(r, _RANGE, key)
    for k in ("start", "stop", "num"):
        if k not in r:
            raise InputError("is required", key=f"{key}.{k}")
    start, stop, num = r["start"], r["stop"], r["num"]
    spacing = r.get("spacing", "linear")
    for k, v in (("start", start), ("stop", stop)):
        if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
            raise InputError(f"must be a finite number, got {v!r}", key=f"{key}.{k}")
    if not isinstance(num, int) or isinstance(num, bool) or num < 1:
        raise InputError(f"must be an integer >= 1, got {num!r}", key=f"{key}.num")
    if spacing == "linear":
        vals = np.linspace(start, stop, num)
    elif spacing == "log":
        if not (start > 0 and stop > 0):
            raise InputError("log spacing needs start > 0 and stop > 0", key=f"{key}.spacing")
        vals = np.geomspace(start, stop, num)
    else:
        raise InputError(f'must be "linear" or "log", got {spacing!r}', key=f"{key}.spacing")
    return [float(v) for v in vals]


# -- output ----------------------------------------------------------------------------
def _output(tab):
    if tab is None:
        return (), 1
    if not isinstance(tab, dict):
        raise InputError("must be a table", key="output")
    _check_keys(tab, _OUTPUT, "output")
    hist = tab.get("histories", [])
    if not isinstance(hist, list) or not all(isinstance(h, str) for h in hist):
        raise InputError(f"must be a list of names from {', '.join(HISTORY_VARIABLES)}", key="output.histories")
    bad = [h for h in hist if h not in HISTORY_VARIABLES]
    if bad:
        raise InputError(f"unknown history {bad[0]!r}; known: {', '.join(HISTORY_VARIABLES)}",
                         key="output.histories")
    dec = tab.get("decimate", 1)
    if not isinstance(dec, int) or isinstance(dec, bool) or dec < 1:
        raise InputError(f"must be an integer >= 1, got {dec!r}", key="output.decimate")
    return tuple(dict.fromkeys(hist)), dec


# -- validation against the model ------------------------------------------------------
def _structure(model) -> dict:
    from ..structure import assemble

    system = assemble(model.buildings, model.gaps, model.contact)
    return {"buildings": [b.name for b in model.buildings], "floors": [b.n_floors for b in model.buildings],
            "links": [(l.left, l.right, l.left_floor, l.right_floor) for l in system.links],
            "gap_height": [float(l.height) for l in system.links]}


def _validate_values(study: Study, base) -> None:
    """Every value of every axis, one axis at a time (the others at the base), must give a valid model
    with the structure of the base model (same buildings, floors and gap elements)."""
    from ..model.toml_loader import parse_model

    ref = _structure(base)
    study.meta = ref
    first_record = study.records[0].file
    for k, ax in enumerate(study.axes):
        for j in range(ax.size):
            over = [(m.path, m.values[j], m.factor) for m in ax.members]
            where = f"axis.{k + 1}" + (f" ({ax.name})" if ax.name != ax.members[0].path else "")
            shown = ", ".join(f"{m.path} {'x ' if m.factor else '= '}{m.values[j]!r}" for m in ax.members)
            try:
                data = _apply(study.model_data, first_record, over, study.model_path)
                model = parse_model(data, base=study.model_path.parent, source=str(study.model_path),
                                    text=study.model_text)
            except InputError as err:
                raise InputError(f"{shown}: {err}", key=where) from None
            if _structure(model) != ref:
                raise InputError(f"{shown} changes the buildings, floors or gap elements of the model; "
                                 "a study keeps them fixed", key=where)


def _apply(model_data: dict, record_file: Path, overrides, model_path: Path) -> dict:
    data = copy.deepcopy(model_data)
    gm = data.setdefault("ground_motion", {})
    if not isinstance(gm, dict):
        raise InputError("must be a table", key="ground_motion")
    gm["file"] = str(record_file)
    for p, v, is_factor in overrides:
        if is_factor:
            for table, key in resolve(data, p):
                table[key] = scaled(table[key], v, p)
        else:
            set_value(data, p, v)
    return data


def _coord_array(values) -> np.ndarray:
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return np.asarray(values, dtype=float)
    return np.asarray([str(v) if not isinstance(v, list) else json.dumps(v) for v in values], dtype=object)


def _hashable(v):
    return json.dumps(v, sort_keys=True) if isinstance(v, (list, dict)) else v


def _check_keys(table: dict, allowed: set, where: str) -> None:
    for k in table:
        if k not in allowed:
            full = f"{where}.{k}" if where else k
            raise InputError(f"unknown key; allowed here: {', '.join(sorted(allowed))}", key=full)

