"""Restitution forms e(v0): the kernel's evaluation equals the Python one, and bad forms are refused."""

import numpy as np
import pytest

from seispound.contact import _scalar, make_law, restitution_from
from seispound.contact.restitution import FORMS
from seispound.errors import InputError

V = np.array([0.0, 0.005, 0.05, 0.2, 0.5, 1.0, 3.0, 10.0])
EXAMPLES = {
    "linear": dict(form="linear", e0=0.9, slope=0.3, min=0.4, max=0.85),
    "exponential": dict(form="exponential", e0=0.95, e_inf=0.45, v_c=0.4),
    "power": dict(form="power", e_ref=0.6, v_ref=0.5, exponent=0.125, max=0.95),
    "table": dict(form="table", velocity=[0.01, 0.1, 1.0, 2.0], e=[0.95, 0.8, 0.6, 0.55]),
}
CLOSED = {
    "linear": lambda v: np.clip(0.9 - 0.3 * v, 0.4, 0.85),
    "exponential": lambda v: 0.45 + 0.5 * np.exp(-v / 0.4),
    "power": lambda v: np.minimum(0.95, np.where(v > 0, 0.6 * (np.maximum(v, 1e-300) / 0.5) ** -0.125, np.inf)),
    "table": lambda v: np.interp(v, [0.01, 0.1, 1.0, 2.0], [0.95, 0.8, 0.6, 0.55]),
}


@pytest.mark.parametrize("form", list(EXAMPLES))
def test_kernel_and_python_evaluate_the_stated_formula(form):
    law = make_law("Hd", stiffness=1e9, restitution=dict(EXAMPLES[form]))
    par = law.kernel_params(100.0, 100.0)
    python = law.restitution_at(V)
    kernel = np.array([_scalar.restitution_at(par, v) for v in V])
    np.testing.assert_allclose(python, CLOSED[form](V), rtol=1e-14)
    np.testing.assert_allclose(kernel, python, rtol=1e-14)
    zeta, e = _scalar.onset_state(law.code, par, 0.7)
    assert e == pytest.approx(float(CLOSED[form](np.array(0.7))), rel=1e-14)
    assert zeta == pytest.approx(1e9 * _scalar.hunt_crossley_s(e) / 0.7, rel=1e-14)


def test_constant_restitution_keeps_the_precomputed_damping_bit_for_bit():
    for name in ("LVe", "MLVe", "NIVe", "Hd", "LHC", "Hertzdamp"):
        law = make_law(name, stiffness=1e9, restitution=0.65)
        par = law.kernel_params(100.0, 120.0)
        zeta, e = _scalar.onset_state(law.code, par, 0.3)
        assert zeta == _scalar.onset_damping(law.code, par, 0.3) and e == 0.65


def test_velocity_dependent_lve_damping_is_seed_eq_3_at_e_of_v0():
    law = make_law("LVe", stiffness=1e8, restitution=dict(EXAMPLES["exponential"]))
    par = law.kernel_params(110.0, 109.0)
    e = float(CLOSED["exponential"](np.array(0.3)))
    xi = -np.log(e) / np.sqrt(np.pi**2 + np.log(e) ** 2)
    zeta, _ = _scalar.onset_state(law.code, par, 0.3)
    assert zeta == pytest.approx(2 * xi * np.sqrt(1e8 * 110 * 109 / 219), rel=1e-13)


@pytest.mark.parametrize("value, key", [
    (dict(form="cubic"), "contact.restitution.form"),
    (dict(form="linear", e0=0.9, slope=0.1, min=0.5), "contact.restitution.max"),
    (dict(form="linear", e0=0.9, slope=-0.1, min=0.5, max=0.9), "contact.restitution.slope"),
    (dict(form="linear", e0=0.9, slope=0.1, min=0.8, max=0.5), "contact.restitution.min"),
    (dict(form="exponential", e0=1.2, e_inf=0.5, v_c=1.0), "contact.restitution.e0"),
    (dict(form="exponential", e0=0.9, e_inf=0.5, v_c=0.0), "contact.restitution.v_c"),
    (dict(form="power", e_ref=0.6, v_ref=0.5, exponent=0.1, max=0.9, extra=1), "contact.restitution.extra"),
    (dict(form="table", velocity=[0.1, 0.05], e=[0.9, 0.8]), "contact.restitution.velocity"),
    (dict(form="table", velocity=[0.1, 0.5], e=[0.9]), "contact.restitution.e"),
    (dict(form="table", velocity=list(range(20)), e=[0.5] * 20), "contact.restitution.velocity"),
])
def test_bad_forms_name_their_key(value, key):
    with pytest.raises(InputError) as info:
        restitution_from(value, "contact.restitution")
    assert info.value.key == key


def test_every_form_is_listed():
    assert set(FORMS) == set(EXAMPLES)


def test_hertz_refuses_a_form():
    with pytest.raises(InputError) as info:
        make_law("Hertz", stiffness=1e9, restitution=restitution_from(dict(EXAMPLES["linear"]), "contact.restitution"))
    assert info.value.key == "contact.restitution"
