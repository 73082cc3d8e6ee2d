"""Least-squares calibration of a model against recordings, with uncertainties.

The residual is, channel by channel, (simulated - recorded) / ||recorded||_2 at the
recording's samples, so that its squared norm is the sum of the channels' squared
normalised errors (seed Eq. 10: NE = ||sim - rec||_2 / ||rec||_2).  It is minimised by
:func:`scipy.optimize.least_squares` (trust-region reflective, bounds) over parameters
named by the study's dotted paths (``model.paths``); a path to a list of numbers fits one
factor on the whole list.  Stiffness-, mass- and yield-like parameters are fitted in log
space.

Uncertainties: a sandwich (heteroscedasticity- and autocorrelation-consistent) covariance,
cov = (J^T J)^-1 J^T S J (J^T J)^-1 n / (n - p), where S is the covariance of the residual.
An accelerogram's residual is coloured (a model error rings at the structure's modes), so an
AR(1) effective sample size, which suits a sample mean, misstates it by factors of 2-5 either
way.  J^T S J is formed in the frequency domain, where a stationary S is diagonal: per trial,
Z(f) = sum over channels of conj(J_c(f)) R_c(f) and J^T S J = sum_f w_f Z(f) Z(f)^H / (N N_fft)
(the quadratic form of the sample autocovariance over every lag: Parseval, with the series
zero-padded to N_fft = 2 N so that no lag wraps round; the frequency-domain form of the
sandwich, Brillinger 1981, Time Series, Sect. 8.2; Hannan 1963).  The residual at the optimum
is orthogonal to J, which depletes it exactly where J lives (a narrowband error at a mode is
partly absorbed by the fitted stiffness); each channel's R_c(f) is therefore divided by
1 - h_c(f), h_c(f) = w_f J_c(f)^H (J^T J)^-1 J_c(f) / N the leverage of that frequency bin:
the HC3 correction of MacKinnon & White (1985, J. Econometrics 29:305), carried over to
frequency bins here (derived, not read).  Trials are independent: their J^T S J add.
Verified by Monte Carlo with narrowband model error on white noise
(``tests/calibrate/test_uncertainty_coverage.py``, docs/verification.md).
n_eff, the sample count the information criterion uses, is n divided by the mean ratio of the
sandwich variances to the white-noise ones s^2 (J^T J)^-1, s^2 = ||r||^2 / (n - p), held to
[p + 1, n].  Standard errors of log-space parameters by the delta method (sigma_x = x sigma_log x).

The 68 % interval is value +- t_nu(0.8413) sigma, Student's t with the variance's effective degrees
of freedom nu, not the normal +- sigma.  A sandwich variance is a weighted sum of periodogram bins,
and a Jacobian that lives at a structure's few modes weights only a few of them (nu of 3-6 on a
three-storey building's 10 s record): an unbiased variance with so few degrees of freedom gives
+- sigma a coverage of 58-64 %, not 68 %.  nu for a direction c of the parameters is Satterthwaite's
(1946, Biometrics Bull. 2:110), nu = 2 (sum_f E a_f)^2 / sum_f (E a_f)^2 over the unpadded bins f,
whose contributions a_f = w_f |c^T H J(f)^H R(f)|^2 are independent and exponentially distributed
(two degrees of freedom each) for a stationary residual; E a_f = w_f c^T H J(f)^H S(f) J(f) H c takes the
residual's cross-spectral matrix S(f) smoothed over five bins (a Daniell window) as its working
model.  This is Bell & McCaffrey's (2002, Survey Methodology 28:169) small-sample correction of a
robust variance, carried to frequency bins here (derived, not read); Imbens & Kolesar (2016, Rev.
Econ. Stat. 98:701) recommend it over the normal interval.  ``CalibrationResult.dof`` gives nu for
any direction (a quantity's delta-method gradient).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from .._blas import single_threaded
from ..errors import InputError

__all__ = ["FitParameter", "CalibrationResult", "parse_fit", "default_bounds"]

_LOG_WORDS = ("stiffness", "mass", "yield", "inertia", "damping_constant", "modulus", "area")


@dataclass
class FitParameter:
    """One fitted quantity: a dotted path, bounds, and whether it is a factor on a list."""

    path: str
    lo: float
    hi: float
    log: bool
    factor: bool  # the path holds a list: one factor on every entry
    start: float  # the value (or factor 1) in the model as given

    def value_at(self, base, x: float):
        """What the model file gets at ``path`` for the parameter value x."""
        return [v * x for v in base] if self.factor else x


_RESTITUTION_KEYS = ("restitution", "e0", "e_inf", "e_ref", "min", "max")
_LINEAR_KEYS = _RESTITUTION_KEYS + ("ratio", "size", "centre_of_mass")  # fitted on a linear scale


def default_bounds(path: str, value) -> tuple[float, float, bool]:
    """(lo, hi, log) for a path when --fit gives none (documented in the README)."""
    last = path.split(".")[-1]
    if isinstance(value, list):
        return 0.2, 5.0, True  # a factor on a list: masses, stiffnesses per storey
    v = float(value)
    if last in _RESTITUTION_KEYS:
        return 0.05, 0.99, False
    if last == "ratio":
        return 0.001, 0.3, False
    if last == "size":
        return 0.0, max(4.0 * v, 0.05), False
    if last == "centre_of_mass":  # a rod floor's: its linear mass density stays positive inside (1/3, 2/3)
        return 0.34, 0.66, False
    if any(w in path for w in _LOG_WORDS) and v > 0:
        return v / 10.0, v * 10.0, True
    if v > 0:
        return v / 5.0, v * 5.0, True
    raise InputError(f"no default bounds for a value of {v:g}: give them as PATH=lo:hi", key=path)


def parse_fit(specs, model_data) -> list[FitParameter]:
    """``PATH[=lo:hi]`` strings -> FitParameters, checked against the model file's table."""
    from ..model.paths import get_value

    out = []
    for spec in specs:
        path, _, bounds = spec.partition("=")
        path = path.strip()
        try:
            value = get_value(model_data, path)
        except (KeyError, IndexError, InputError, TypeError):
            raise InputError("no such key in the model (dotted path as in a study axis)", key=path) from None
        is_list = isinstance(value, list)
        if is_list and not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
            raise InputError("a list path must hold numbers (one factor is fitted on it)", key=path)
        if not is_list and (isinstance(value, bool) or not isinstance(value, (int, float))):
            raise InputError(f"must be a number or a list of numbers to fit, the model has {value!r}", key=path)
        if bounds:
            try:
                lo, hi = (float(x) for x in bounds.split(":"))
            except ValueError:
                raise InputError(f"bounds must read lo:hi, got {bounds!r}", key=path) from None
            log = lo > 0 and (is_list or path.split(".")[-1] not in _LINEAR_KEYS)
        else:
            lo, hi, log = default_bounds(path, value)
        start = 1.0 if is_list else float(value)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise InputError(f"bounds must be finite with lo < hi, got {lo:g}:{hi:g}", key=path)
        if not lo <= start <= hi:
            raise InputError(f"the model's value {start:g} lies outside the bounds {lo:g}:{hi:g}", key=path)
        if any(p.path == path for p in out):
            raise InputError("fitted twice", key=path)
        out.append(FitParameter(path, lo, hi, log, is_list, start))
    if not out:
        raise InputError("give at least one --fit PATH", key="fit")
    return out


@dataclass
class CalibrationResult:
    """What a calibration found.

    Attributes: parameters (path -> dict of value, start, stderr, lo, hi, at_bound, identified,
    reason), correlation (p, p), ne_before / ne_after (trial -> {trace id: NE}), ne_mean_before /
    ne_mean_after (mean over every mapped channel of every trial), evaluations, seconds, model_text
    (the calibrated model file), n_eff / n (the residual's effective and actual sample counts),
    message, converged (False when the fit stopped at its cap on simulations), noise_ne (the NE
    the recordings' sensor noise alone leaves, mean over channels), starts (fits started).
    A parameter the data cannot constrain (its Jacobian column zero, or a flat direction of
    J^T J) has ``identified`` False, ``stderr`` inf and the reason in words.
    """

    parameters: dict
    correlation: np.ndarray
    ne_before: dict
    ne_after: dict
    ne_mean_before: float
    ne_mean_after: float
    evaluations: int
    seconds: float
    model_text: str
    n: int
    n_eff: float
    success: bool
    message: str
    history: list = field(default_factory=list)
    converged: bool = True
    noise_ne: float = float("nan")
    starts: int = 1
    dof_terms: tuple | None = field(default=None, repr=False)  # (log flags (p,), bins (K, p, p)): ``dof``

    def dof(self, grad) -> float:
        """Effective degrees of freedom of the variance of sum_k grad[k] x_k (grad (p,) in the parameters'
        order, per unit of each fitted value): Satterthwaite's nu (module docstring); inf where unknown."""
        if self.dof_terms is None:
            return math.inf
        logs, bins = self.dof_terms
        xs = np.array([p["value"] for p in self.parameters.values()], float)
        c = np.asarray(grad, float) * np.where(logs, xs, 1.0)  # per unit of the fitted (log-)value
        a = np.einsum("p,kpq,q->k", c, bins.astype(float), c)
        den = float(a @ a)
        return float(2.0 * a.sum() ** 2 / den) if den > 0.0 else math.inf

    def summary(self) -> str:
        lines = [f"calibration: {self.evaluations} simulations, {self.seconds:.1f} s; NE (mean over channels) "
                 f"{self.ne_mean_before:.4f} -> {self.ne_mean_after:.4f}"
                 + (f" (fits from {self.starts} starts)" if self.starts > 1 else "")]
        if not self.converged:
            lines.append("  NOT CONVERGED: the fit stopped at its cap on simulations (--max-evaluations)")
        noise = max(self.noise_ne, 1e-3)  # noise-free synthetic recordings: a misfit of 0.1 % is a fit
        if math.isfinite(self.noise_ne) and self.ne_mean_after > FAR * noise:
            lines.append(f"  the fit ends {self.ne_mean_after / noise:.1f} times above what the sensor noise "
                         f"leaves (NE {self.noise_ne:.4f}): the model cannot reproduce the recordings with these "
                         "parameters (seispound diagnose says where and why); the values below are the closest "
                         "this model comes, and their intervals hold for a model of the right form only")
        lines.append(f"  {'parameter':40s} {'start':>12s} {'fitted':>12s} {'std. error':>11s} {'68 % +-':>11s} "
                     f"{'dof':>5s}")
        for path, p in self.parameters.items():
            flag = "  (at a bound)" if p["at_bound"] else ""
            err = (f"{p['stderr']:11.3g} {p.get('half68', p['stderr']):11.3g} {p.get('dof', math.inf):5.1f}"
                   if p.get("identified", True) else f"{'-':>11s}  not identified: {p['reason']}")
            lines.append(f"  {path:40s} {p['start']:12.5g} {p['value']:12.5g} {err}{flag}")
        names = list(self.parameters)
        for i in range(len(names)):
            for j in range(i):
                if abs(self.correlation[i, j]) >= 0.8:
                    lines.append(f"  strongly correlated: {names[i]} and {names[j]} ({self.correlation[i, j]:+.2f})")
        for trial, nes in self.ne_after.items():
            for cid, ne in nes.items():
                lines.append(f"  NE {trial} {cid}: {self.ne_before[trial][cid]:.4f} -> {ne:.4f}")
        return "\n".join(lines)


def normalised_errors(sim, rec) -> dict:
    """{trace id: ||sim - rec|| / ||rec||} (seed Eq. 10)."""
    return {cid: float(np.linalg.norm(sim[cid] - x) / max(np.linalg.norm(x), 1e-300)) for cid, x in rec.items()}


@single_threaded  # a fit's matrices are tall and thin: one BLAS thread is faster (_blas.py)
def calibrate_observer(observer, params, progress=True, max_evaluations=None, write_base=None,
                       tolerance=1e-8, step_fraction=None) -> CalibrationResult:
    """Fit ``params`` (FitParameters) through ``observer`` (observe.Observer); see the module docstring.

    ``tolerance``: least_squares' ftol and gtol (its default 1e-8; a model comparison that needs
    the misfit to a few parts in 10^4 uses a looser one and fewer simulations).
    ``step_fraction``: the finite-difference step of the Jacobian as a fraction of each
    parameter's (log-)range, instead of 1e-4 of its (log-)value: a pounding response is rough
    on the scale of tiny steps (an impact a substep earlier or later), so a step too small
    gives a gradient of the wrong sign.
    """
    from scipy.optimize import least_squares

    from ..model.paths import get_value

    base_values = {p.path: get_value(observer.model_data, p.path) for p in params}
    lo = np.array([math.log(p.lo) if p.log else p.lo for p in params])
    hi = np.array([math.log(p.hi) if p.log else p.hi for p in params])
    y0 = np.array([math.log(p.start) if p.log else p.start for p in params])
    y0 = np.clip(y0, lo, hi)
    # least_squares works on w, y = a + b w: y itself, or (with step_fraction) w in [1, 2] across the bounds, so
    # that its relative finite-difference step is the same fraction of every parameter's range
    a, b = (np.zeros_like(lo), np.ones_like(lo)) if step_fraction is None else (2.0 * lo - hi, hi - lo)
    recs = [{c.id: t.recording.data[c.id] for c in observer.channels} for t in observer.trials]
    norms = [{cid: max(np.linalg.norm(x), 1e-300) for cid, x in r.items()} for r in recs]
    t0 = time.perf_counter()
    history = []

    def values(w):
        return [math.exp(v) if p.log else float(v) for p, v in zip(params, a + b * np.asarray(w))]

    def overrides(y):
        return [(p.path, p.value_at(base_values[p.path], x)) for p, x in zip(params, values(y))]

    first = []  # the simulation at the start: least_squares evaluates there first
    kept = {}  # the KEPT lowest-misfit evaluations' simulations, by their point: the fit ends at one of them

    def residual(y):
        sims = observer.simulate(overrides(y))
        if not first:
            first.append(sims)
        r = np.concatenate([(s[cid] - rec[cid]) / nrm[cid] for s, rec, nrm in zip(sims, recs, norms) for cid in rec])
        history.append((values(y), float(r @ r)))
        kept[np.asarray(y, float).tobytes()] = (float(r @ r), sims)
        if len(kept) > KEPT:
            kept.pop(max(kept, key=lambda k: kept[k][0]))
        if progress:
            print(f"\r  simulation {observer.evaluations}: sum of NE^2 {r @ r:.6g}   ", end="", file=sys.stderr,
                  flush=True)
        return r

    # max_evaluations caps simulations: least_squares' max_nfev leaves out the p more of each finite-difference Jacobian
    nfev = None if max_evaluations is None else max(1, int(max_evaluations) // (len(params) + 1))
    fit = least_squares(residual, (y0 - a) / b, bounds=((lo - a) / b, (hi - a) / b), x_scale="jac", method="trf",
                        max_nfev=nfev, diff_step=step_fraction or 1e-4, ftol=tolerance,
                        xtol=min(tolerance, 1e-8), gtol=tolerance)
    sims0 = first[0]
    ne_before = {t.name: normalised_errors(s, r) for t, s, r in zip(observer.trials, sims0, recs)}
    if progress:
        print(file=sys.stderr)
    # least_squares returns a point it evaluated (its last accepted step), almost always among the best kept
    sims = kept[fit.x.tobytes()][1] if fit.x.tobytes() in kept else observer.simulate(overrides(fit.x))
    ne_after = {t.name: normalised_errors(s, r) for t, s, r in zip(observer.trials, sims, recs)}
    cov_w, n, n_eff, bins = _covariance(fit, recs)
    cov_y = cov_w * np.outer(b, b)
    xs = values(fit.x)
    sd_y = np.sqrt(np.clip(np.diag(cov_y), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov_y / np.outer(sd_y, sd_y)
    out = {}
    blind = _not_identified(fit.jac, [p.path for p in params], observer)
    blind.update(force_scale(observer, params, base_values, first[0]))
    for k, p in enumerate(params):
        sd = xs[k] * sd_y[k] if p.log else sd_y[k]
        at_bound = ended_at_bound(a[k] + b[k] * fit.x[k], lo[k], hi[k], fit.active_mask[k])
        out[p.path] = dict(value=xs[k], start=p.start, stderr=float(sd) if p.path not in blind else math.inf,
                           lo=p.lo, hi=p.hi, at_bound=at_bound, factor=p.factor, identified=p.path not in blind,
                           reason=blind.get(p.path, ""), log=p.log)
    text = _calibrated_text(observer, params, base_values, xs, write_base)
    mean = lambda d: float(np.mean([v for nes in d.values() for v in nes.values()]))  # noqa: E731
    res = CalibrationResult(parameters=out, correlation=corr, ne_before=ne_before, ne_after=ne_after,
                            ne_mean_before=mean(ne_before), ne_mean_after=mean(ne_after),
                            evaluations=observer.evaluations, seconds=time.perf_counter() - t0, model_text=text,
                            n=n, n_eff=n_eff, success=bool(fit.success), message=str(fit.message), history=history,
                            converged=bool(fit.status > 0), noise_ne=noise_ne(observer),
                            dof_terms=None if bins is None else (np.array([p.log for p in params]),
                                                                 bins * np.outer(b, b)[None]))
    for k, p in enumerate(out.values()):
        grad = np.zeros(len(params))
        grad[k] = 1.0
        p["dof"] = res.dof(grad)
        p["half68"] = interval68(p["stderr"], p["dof"])
    return res


KEPT = 4  # simulations a fit keeps (its lowest misfits), so that its result needs no simulation of its own

Z68 = 0.8413447460685429  # the normal distribution's value at one standard deviation: a 68.27 % interval


def interval68(stderr: float, dof: float) -> float:
    """Half-width of the 68.27 % interval of an estimate with standard error ``stderr`` whose variance has
    ``dof`` effective degrees of freedom: t_dof(0.8413) stderr (at least one degree of freedom; inf: +- stderr)."""
    from scipy.stats import t

    if not math.isfinite(stderr) or not math.isfinite(dof):
        return stderr
    return float(t.ppf(Z68, max(dof, 1.0)) * stderr)


AT_BOUND = 1e-4  # a value within this fraction of its (log-)range of a bound ended at that bound


def ended_at_bound(y: float, lo: float, hi: float, active: int = 0) -> bool:
    """Whether a fitted (log-)value ``y`` in [lo, hi] ended at a bound: least squares' active set says so, or it
    lies within AT_BOUND of the range from one.  The trust-region method keeps its iterates strictly inside
    the bounds, so a parameter the data push onto a bound (a yield drift at "never yields") ends a hair inside
    it with the active set empty, and its standard error would read as if the data placed it there."""
    return bool(active != 0) or min(y - lo, hi - y) <= AT_BOUND * (hi - lo)


FAR = 3.0  # a fit ending above this many times the noise's NE is said to be far above the noise
FLAT = 1e-6  # a singular value of J below this fraction of the largest: a direction the data cannot see


def noise_ne(observer) -> float:
    """The NE that the recordings' sensor noise alone leaves, mean over the mapped channels of every trial: the
    noise's standard deviation from the second differences (robust scale; ``diagnose.locate.noise_sigma``)
    times sqrt(n), over the channel's norm."""
    from ..diagnose.locate import noise_ne as channel_noise_ne

    vals = [channel_noise_ne(t.recording.data[c.id]) for t in observer.trials for c in observer.channels]
    return float(np.mean(vals)) if vals else float("nan")


# the last key of a path that holds a mass, an inertia, a stiffness or a dashpot's constant: what carries a
# model's force scale (the contact's stiffness too); a candidate only, the simulation decides (force_scale)
_FORCE_KEYS = ("floor_masses", "storey_stiffness", "mass", "rotary_inertia", "floor_rotary_inertia",
               "sway_stiffness", "sway_damping", "rocking_stiffness", "rocking_damping", "axial_stiffness")
SCALE_TRIAL = 1.25  # the factor the force-scale check multiplies its candidates by
SCALE_SAME = 1e-9  # no channel moving by more than this fraction of its peak: the same recording


def force_scale(observer, params, base_values, sims0) -> dict:
    """{path: why} for the fitted paths that together hold the model's force scale, or {} if they do not.

    Recordings of motion carry no force scale.  Multiply every mass, inertia, stiffness and dashpot
    constant of a model by one factor c, and its equations of motion become c (M a + C v + K u + f(u, v))
    = -c M iota a_g: the same equations, since M, C, K and every contact law are homogeneous of degree one
    in them (a Rayleigh ratio, e, a gap and a yield drift are not scaled; Hertz's and the Hertzdamp's
    k delta^(3/2) (1 + ...) scale with k).  Derived here from the equations of motion, not read.  So when
    the fitted parameters include every quantity that carries the model's force scale, scaling them all
    together changes no recorded channel: only their ratios are seen, and least squares wanders along
    that line.  Whether they do is decided by a simulation, not a list: every fitted path whose last key
    names a mass, an inertia, a stiffness or a dashpot's constant (``_FORCE_KEYS``, and contact.stiffness)
    multiplied by SCALE_TRIAL at its start, the direction reported if no channel of any trial moves by
    more than SCALE_SAME of its peak from ``sims0`` (the simulation at the start).  Checked only when the
    masses of every building are among them (else a building's masses hold the scale).
    """
    model = observer.model_data
    paths = [p.path for p in params]
    buildings = [b.get("name") for b in model.get("building", [])]
    if not buildings or any(f"building.{b}.floor_masses" not in paths for b in buildings):
        return {}
    scaled = [p for p in params if p.path == "contact.stiffness" or p.path.rsplit(".", 1)[-1] in _FORCE_KEYS]
    start = {p.path: p.value_at(base_values[p.path], p.start) for p in params}
    over = [(p.path, p.value_at(base_values[p.path], p.start * SCALE_TRIAL) if p in scaled else start[p.path])
            for p in params]
    for s1, s0 in zip(observer.simulate(over), sims0):
        for cid, x in s0.items():
            if not np.max(np.abs(s1[cid] - x)) <= SCALE_SAME * max(np.max(np.abs(x)), 1e-300):
                return {}
    names = [p.path for p in scaled]
    return {q: ("sets the force scale with " + ", ".join(n for n in names if n != q) + ": scaling them all by one "
                "factor changes no recorded channel (recordings of motion carry no force scale), so only their "
                "ratios are fitted; hold one of them as given") for q in names}


def _not_identified(J, paths, observer) -> dict:
    """{path: why the data cannot constrain it} from the Jacobian ``J`` (n, p) at the fit.

    A zero column: the simulated channels do not change with the parameter (a gap or contact
    constant with no impact in any trial's fitted simulation says so).  A singular value of J
    below FLAT times the largest: a flat direction, and the parameters that make up most of it
    trade off against each other (each named with its partner).
    """
    J = np.asarray(J, float)
    if J.size == 0:
        return {}
    if not np.all(np.isfinite(J)):
        return {path: "the model blows up next to the fitted point, so its sensitivity is unknown" for path in paths}
    cols = np.linalg.norm(J, axis=0)
    out = {}
    no_impact = not any(len(t) for t in getattr(observer, "impact_times", []) or [])
    for k, path in enumerate(paths):
        if cols[k] <= 1e-12 * max(cols.max(), 1e-300):
            contact = path.startswith(("gap.", "contact."))
            out[path] = ("no impact in the recording: the fitted model's gaps never close" if contact and no_impact
                         else "the recorded channels do not change with it")
    _, s, vt = np.linalg.svd(J / np.where(cols > 0, cols, 1.0), full_matrices=False)
    for row in vt[s < FLAT * s.max()]:
        big = [k for k in np.argsort(-np.abs(row)) if abs(row[k]) >= 0.3 and paths[k] not in out]
        for k in big:
            partners = [paths[j] for j in big if j != k]
            out[paths[k]] = ("trades off with " + ", ".join(partners) if partners else "a flat direction of the fit")
    return out


def _covariance(fit, recs):
    """The sandwich covariance of the (log-)parameters, the sample counts and the variance's bins: (cov, n,
    n_eff, bins).

    ``fit``: scipy's OptimizeResult (``fun`` (n,), ``jac`` (n, p)); ``recs``: per trial {trace id: samples},
    in the residual's order (module docstring).  bins (K, p, p) float32: the largest K <= DOF_BINS expected
    contributions of single frequency bins to cov, for the degrees of freedom (``_dof_bins``).
    """
    r, J = fit.fun, fit.jac
    n, p = J.shape
    unknown = np.full((p, p), np.inf), n, float(n), None
    if not (np.all(np.isfinite(J)) and np.all(np.isfinite(r))):
        return unknown  # a finite difference reached a point where the model blows up
    # (J^T J)^-1 with J's columns scaled to unit norm first: J^T J squares J's condition number, and a pseudo-inverse
    # of it would drop a parameter whose column is 1e-8 of the others' as if the data fixed it exactly (a yield
    # drift of metres, where the storey never yields, came out at +- 1e-9 m); scaled, it gets the large variance
    # it has
    scale = np.linalg.norm(J, axis=0)
    scale = np.where(scale > 0.0, scale, 1.0)
    try:
        H = np.linalg.pinv((J / scale).T @ (J / scale)) / np.outer(scale, scale)
    except np.linalg.LinAlgError:
        return unknown
    meat, start, bins = np.zeros((p, p)), 0, []
    for rec in recs:
        size = sum(x.size for x in rec.values())
        # zero-padded to twice the length: its even bins are the unpadded spectrum's (the same sums), which the
        # degrees of freedom take
        spectra = _hc3_spectra(J[start:start + size], r[start:start + size], len(rec), H, 2 * (size // len(rec)))
        meat += _trial_meat(*spectra, size // len(rec))
        bins.append(_dof_bins(*(x[::2] if x.ndim == 1 else x[:, ::2] for x in spectra), H))
        start += size
    bins = np.concatenate(bins)
    share = np.max(np.abs(np.diagonal(bins, axis1=1, axis2=2)), axis=1)
    bins = bins[np.argsort(-share)[:DOF_BINS]].astype(np.float32)
    cov = H @ meat @ H * (n / max(n - p, 1))
    white = H * float(r @ r) / max(n - p, 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.diag(cov) / np.diag(white)
    ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
    n_eff = float(np.clip(n / float(np.mean(ratio)), p + 1.0, n)) if ratio.size else float(n)
    return cov, n, n_eff, bins


DOF_BINS = 256  # bins kept per fit for the degrees of freedom: a Jacobian lives at a few modes' bins
DANIELL = 5  # the working model's cross-spectral matrix is smoothed over this many bins


def _dof_bins(JF, RF, w, H):
    """One trial's expected contributions of single (unpadded, independent) frequency bins to the
    (log-)parameters' covariance, (bins, p, p), up to a common factor: w_f H Re(J(f)^H S(f) J(f)) H with S(f)
    the HC3-corrected residual's cross-spectral matrix over the channels, smoothed over DANIELL bins (the
    working model of Satterthwaite's degrees of freedom, module docstring).  JF (channels, bins, p), RF
    (channels, bins), w (bins,): ``_hc3_spectra`` over the unpadded length; H = (J^T J)^-1 (p, p)."""
    from scipy.ndimage import uniform_filter1d

    S = np.einsum("cf,df->fcd", RF, RF.conj())
    S = uniform_filter1d(S.real, DANIELL, axis=0) + 1j * uniform_filter1d(S.imag, DANIELL, axis=0)
    B = (JF @ H).transpose(1, 0, 2)  # J(f) H per channel: (bins, channels, p)
    return w[:, None, None] * np.real(np.conj(B).transpose(0, 2, 1) @ (S @ B))


def _trial_meat(JF, RF, w, n):
    """J^T S J of one trial (its channels share the time grid), HC3-corrected per frequency bin: sum_f w_f Z(f)
    Z(f)^H / (nfft n), Z(f) = sum over channels of conj(J_c(f)) R_c(f), from its spectra (``_hc3_spectra``)
    zero-padded to nfft = 2 n, n the samples per channel."""
    nfft = 2 * n  # zero-padded: the sample autocovariance at every lag, none wrapped round
    Z = np.sum(JF.conj() * RF[..., None], axis=0)  # (bins, p)
    return np.real((Z.T * w) @ Z.conj()) / (nfft * n)


def _hc3_spectra(J, r, channels, H, nfft):
    """One trial's one-sided spectra over nfft points: (J(f) (channels, bins, p), the residual's R(f) divided by
    one minus its bin's leverage (HC3; module docstring) (channels, bins), the bins' weights w (bins,): 2, but 1
    at 0 and Nyquist)."""
    n = r.size // channels
    p = J.shape[1]
    JF = np.fft.rfft(J.reshape(channels, n, p), nfft, axis=1)
    RF = np.fft.rfft(r.reshape(channels, n), nfft, axis=1)
    w = np.full(RF.shape[1], 2.0)  # the one-sided spectrum counts every bin but 0 and Nyquist twice
    w[0] = 1.0
    if nfft % 2 == 0:
        w[-1] = 1.0
    h = np.real(np.sum((JF @ H) * JF.conj(), axis=-1)) * w / n  # leverage of each bin of width 1/T
    return JF, RF / (1.0 - np.clip(h, 0.0, 0.9)), w


def _calibrated_text(observer, params, base_values, xs, write_base) -> str:
    """The model file with the fitted values, its relative record paths rebased onto ``write_base``."""
    import copy
    import os

    import tomli_w

    from ..model.paths import set_value

    data = copy.deepcopy(observer.model_data)
    for p, x in zip(params, xs):
        set_value(data, p.path, p.value_at(base_values[p.path], x))
    if write_base is not None:
        tables = [data.get("ground_motion", {})] + [b.get("ground_motion", {}) for b in data.get("building", [])
                                                    if isinstance(b.get("ground_motion"), dict)]
        for t in tables:
            if isinstance(t, dict) and isinstance(t.get("file"), str) and not os.path.isabs(t["file"]):
                t["file"] = os.path.relpath(os.path.abspath(os.path.join(observer.base, t["file"])), write_base)
    return tomli_w.dumps(data)
