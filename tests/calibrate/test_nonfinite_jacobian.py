"""A fit whose finite differences reached a point where the model blows up: the errors are reported as
unknown instead of raising (``calibrate.fit._covariance`` and ``_not_identified``).  Regression guard."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from seispound.calibrate import fit as F


def test_a_nonfinite_jacobian_gives_unknown_errors_not_an_exception():
    rng = np.random.default_rng(1)
    J = rng.standard_normal((50, 3))
    J[7, 1] = np.nan
    res = SimpleNamespace(fun=rng.standard_normal(50), jac=J)
    cov, n, n_eff, bins = F._covariance(res, [{"a": np.zeros(50)}])
    assert n == 50 and n_eff == 50.0 and np.all(np.isinf(cov)) and bins is None
    why = F._not_identified(J, ["x", "y", "z"], SimpleNamespace(impact_times=[]))
    assert set(why) == {"x", "y", "z"} and all("blows up" in w for w in why.values())


def test_a_finite_jacobian_keeps_its_sandwich():
    rng = np.random.default_rng(2)
    J = rng.standard_normal((200, 2))
    res = SimpleNamespace(fun=rng.standard_normal(200), jac=J)
    cov, n, n_eff, bins = F._covariance(res, [{"a": np.zeros(200)}])
    assert np.all(np.isfinite(cov)) and 3.0 <= n_eff <= 200.0 and bins.shape == (101, 2, 2)


def test_a_polish_that_cannot_run_is_reported_not_raised(monkeypatch):
    """``diagnose``'s polish of a form: a stage that raises leaves an error string (the form's short fit
    stands in ``_fit_all``), so that one form cannot end a diagnosis with a traceback."""
    from seispound.diagnose import api

    def broken(*a, **k):
        raise np.linalg.LinAlgError("SVD did not converge")

    monkeypatch.setattr(F, "calibrate_observer", broken)
    spec = ["contact.stiffness=1e8:1e10"]
    out = api._polish(["[contact]\nstiffness = 1e9\n"], spec, spec, ".", [], [], 10)
    assert isinstance(out, str) and "SVD did not converge" in out
