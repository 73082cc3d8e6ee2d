"""A parameter the data hardly see gets the large variance it has (``calibrate.fit._covariance``).

A yielding storey whose yield drift is metres never yields: the recorded channels move with it by a
hundred-millionth of what they move with the other parameters.  Inverting J^T J, which squares J's
condition number, a pseudo-inverse dropped that direction as if the data fixed it exactly (a held-out
diagnosis reported such a yield drift at +- 1e-9 m).  Closed form, white residual of standard deviation
sigma on orthogonal columns: each parameter's variance is sigma^2 / |column|^2 (ordinary least squares;
the sandwich equals it for white, homoscedastic residuals up to the n / (n - p) factor and sampling).
"""

from types import SimpleNamespace

import numpy as np

from seispound.calibrate import fit as F


def test_a_column_1e8_times_smaller_gets_a_standard_error_1e8_times_larger():
    rng = np.random.default_rng(3)
    n, sigma = 4000, 0.01
    J, _ = np.linalg.qr(rng.standard_normal((n, 3)))  # orthonormal columns
    J[:, 2] *= 1e-8
    r = sigma * rng.standard_normal(n)
    cov, *_ = F._covariance(SimpleNamespace(fun=r, jac=J), [{"A": r}])
    se = np.sqrt(np.diag(cov))
    want = sigma / np.linalg.norm(J, axis=0)
    print(f"MEASURED standard errors / closed form: {se / want}")
    assert np.allclose(se / want, 1.0, atol=0.1)  # measured within 0.03 (the residual's sampling)
