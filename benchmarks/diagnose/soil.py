"""Foundation impedances for the held-out generator (``outside.py``), in forms the hypothesis library does not hold.

Independent of the package (NumPy only).  Each function returns a lumped-parameter model of the
soil under one rigid footing, referred to the foundation's two DOFs (sway ``u0`` [m] and rocking
``theta`` [rad], the reference point at the base of the first storey):

    {"K": 2x2 static stiffness, "C": 2x2 dashpots straight to ground,
     "cells": [((g_u, g_theta), dashpot, mass), ...],  # a dashpot from g . (u0, theta) to an internal DOF of that mass
     "trapped_inertia": rotational inertia added to the foundation,  ...quantities for the key}

An internal "cell" (a dashpot ``c`` from the foundation DOF to an internal DOF of mass ``m``, the
internal DOF otherwise free) has the dynamic stiffness, derived for this generator,

    S_cell(w) = i w c * (-w^2 m) / (i w c - w^2 m) = (-w^2 m + i w c (w tau)^2) / (1 + (w tau)^2),  tau = m / c,

an added mass at low frequency whose damping grows as w^3, and a dashpot c above w = 1 / tau.

1. ``rocking_cone``: Wolf's cones (J. P. Wolf, *Foundation Vibration Analysis Using Simple
   Physical Models*, Prentice Hall 1994, ch. 2-3; the spring-dashpot-mass form also in Wolf,
   *Earthquake Engng Struct. Dyn.* 26:931-949, 1997).  Sway: the translational cone, exact as a
   spring ``K_x = rho cs^2 A / z0`` and a dashpot ``C_x = rho cs A`` to ground, ``z0/r0 = pi/8 (2 - nu)``.
   Rocking: the ROTATIONAL cone WITH its internal DOF: spring ``K_t = 3 rho c^2 I / z0`` to ground,
   and the dashpot ``C_t = rho c I`` not to ground but to an internal rotational DOF of inertia
   ``M_t = rho I z0``; ``z0/r0 = 9 pi/32 (1 - nu) (c/cs)^2``, c = cp (nu <= 1/3) or 2 cs (1/3 < nu <
   1/2, with the trapped inertia ``0.3 pi (nu - 1/3) rho r0^5`` added to the foundation).  What was
   derived here (the arrangement as recalled from Wolf 1994; the book's text could not be
   retrieved with the search tool, only the 1997 paper's abstract): with tau = M_t / C_t = z0 / c
   and b0 = w z0 / c the cell above gives

       S_t(w) = K_t [1 - (b0^2 / 3) / (1 + b0^2) + i b0 (b0^2 / 3) / (1 + b0^2)],

   Wolf's closed form of the rotational cone, k(b0) = 1 - b0^2 / (3 (1 + b0^2)), c(b0) = b0^2 /
   (3 (1 + b0^2)): the radiation damping vanishes as w^3 at low frequency and tends to C_t at high
   frequency.  The library now uses the same rotational cone on soil (``seispound.foundation.rocking_cone``,
   issue 30 item 4); this generator keeps its own copy, written apart from the package.
   Footing: a rectangle (L along the row, B across), equivalent discs r_x = sqrt(L B / pi),
   r_t = (4 I / pi)^(1/4) with I = B L^3 / 12.

2. ``stratum``: a circular footing of radius r, embedded a depth D, in a layer of depth H over
   rigid rock, a model of my own choice:
   * static stiffness of the embedded footing at its base (the approximations of Kausel 1974 /
     Elsabee & Morray 1977 as quoted by Gazetas 1983 and Pais & Kausel 1988):
     K_x = 8 G r / (2 - nu) (1 + r / 2H) (1 + 2D / 3r) (1 + 5D / 4H),
     K_t = 8 G r^3 / (3 (1 - nu)) (1 + r / 6H) (1 + 2D / r) (1 + 0.7 D / H);
   * referred to the reference point D above the base (a rigid offset, u_base = u0 - D theta): the
     sway-rocking coupling K_xt = -D K_x, K_tt = K_t + D^2 K_x (the library's springs are uncoupled);
   * radiation only above the layer's cutoffs, w_s = pi cs / 2H (sway) and w_p = pi V_La / 2H
     (rocking, V_La = 3.4 cs / (pi (1 - nu)), Lysmer's analogue): one cell per DOF with the
     half-space dashpot c_inf (rho cs A; rho V_La I) and tau = 1 / w_cut, so that the damping is
     (w/w_cut)^2 / (1 + (w/w_cut)^2) of c_inf; c_inf is capped so that the cell's high-frequency
     softening c_inf w_cut stays below half the static stiffness;
   * the soil's material damping: a dashpot 2 xi K / w_cut straight to ground, xi = 3 %.
"""

from __future__ import annotations

import math

import numpy as np


def rocking_cone(L, B, nu, vs, rho):
    """Wolf's translational cone (sway) and rotational cone with its internal DOF (rocking), module docstring 1."""
    G = rho * vs ** 2
    A, I = L * B, B * L ** 3 / 12.0
    r_x, r_t = math.sqrt(A / math.pi), (4.0 * I / math.pi) ** 0.25
    z0_x = math.pi / 8.0 * (2.0 - nu) * r_x
    kx, cx = G * A / z0_x, rho * vs * A
    cp = vs * math.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu))
    c = cp if nu <= 1.0 / 3.0 else 2.0 * vs
    z0_t = 9.0 * math.pi / 32.0 * (1.0 - nu) * (c / vs) ** 2 * r_t
    kt = 3.0 * rho * c ** 2 * I / z0_t
    ct = rho * c * I
    mt = rho * I * z0_t
    trapped = 0.3 * math.pi * (nu - 1.0 / 3.0) * rho * r_t ** 5 if nu > 1.0 / 3.0 else 0.0
    return {"K": np.diag([kx, kt]), "C": np.diag([cx, 0.0]), "cells": [((0.0, 1.0), ct, mt)], "trapped_inertia": trapped,
            "z0_rocking": z0_t, "c_rocking": c, "K_t": kt, "C_t": ct, "M_t": mt, "kx": kx, "cx": cx}


def cone_closed_form(w, K_t, z0, c):
    """Wolf's rotational cone, S(w) = K_t [k(b0) + i b0 c(b0)], b0 = w z0 / c (module docstring 1)."""
    b0 = np.asarray(w, float) * z0 / c
    g = b0 ** 2 / (3.0 * (1.0 + b0 ** 2))
    return K_t * (1.0 - g + 1j * b0 * g)


def stratum(r, D, H, nu, vs, rho, xi=0.03):
    """Embedded footing on a layer over rock, module docstring 2."""
    G = rho * vs ** 2
    A, I = math.pi * r ** 2, math.pi * r ** 4 / 4.0
    kx = 8 * G * r / (2 - nu) * (1 + r / (2 * H)) * (1 + 2 * D / (3 * r)) * (1 + 5 * D / (4 * H))
    kt = 8 * G * r ** 3 / (3 * (1 - nu)) * (1 + r / (6 * H)) * (1 + 2 * D / r) * (1 + 0.7 * D / H)
    w_s = math.pi * vs / (2 * H)
    v_la = 3.4 * vs / (math.pi * (1 - nu))
    w_p = math.pi * v_la / (2 * H)
    cx_inf = min(rho * vs * A * (1 + 2 * D / r), 0.5 * kx / w_s)  # the side walls radiate too
    ct_inf = min(rho * v_la * I * (1 + 2 * D / r), 0.5 * kt / w_p)
    K = np.array([[kx, -D * kx], [-D * kx, kt + D * D * kx]])
    cmx, cmt = 2 * xi * kx / w_s, 2 * xi * kt / w_p
    C = np.array([[cmx, -D * cmx], [-D * cmx, cmt + D * D * cmx]])
    # the sway cell acts on the base's sway u0 - D theta: written as a cell on u0 when D = 0; with D > 0 the
    # cell's dashpot connects the internal DOF to the combination (1, -D) of the foundation DOFs
    return {"K": K, "C": C, "cells": [((1.0, -D), cx_inf, cx_inf / w_s), ((0.0, 1.0), ct_inf, ct_inf / w_p)],
            "trapped_inertia": 0.0, "kx": kx, "kt": kt, "w_cut_sway": w_s, "w_cut_rocking": w_p,
            "cx_inf": cx_inf, "ct_inf": ct_inf}


def cell_closed_form(w, c, m):
    """The derived dynamic stiffness of a dashpot-to-internal-mass cell (module docstring)."""
    w = np.asarray(w, float)
    tau = m / c
    return (-(w ** 2) * m + 1j * w * c * (w * tau) ** 2) / (1.0 + (w * tau) ** 2)


def dynamic_stiffness_by_time_integration(model, dof, w, cycles=40):
    """The foundation's dynamic stiffness in ``dof`` (0 sway, 1 rocking) at frequency ``w``, from a time integration.

    The foundation DOF is driven as sin(w t) (the other held at zero); the internal DOFs are
    integrated with ``solve_ivp``; the reaction is fitted by least squares to a cos + b sin over
    the last ten cycles: S = b + i a.  An independent check of the lumped model's matrices against
    the closed forms (``tests/diagnose/test_generator_outside.py``)."""
    from scipy.integrate import solve_ivp

    cells = model["cells"]
    gen = [np.asarray(g, float) for g, _c, _m in cells]

    def drive(t):
        u = np.zeros(2)
        v = np.zeros(2)
        u[dof], v[dof] = math.sin(w * t), w * math.cos(w * t)
        return u, v

    def rhs(t, y):
        _u, v = drive(t)
        out = []
        for k, (g, (_, c, m)) in enumerate(zip(gen, cells)):
            out += [y[2 * k + 1], c * (g @ v - y[2 * k + 1]) / m]
        return out

    T = 2 * math.pi / w
    t = np.linspace(0, cycles * T, cycles * 200 + 1)
    sol = solve_ivp(rhs, (0, t[-1]), np.zeros(2 * len(cells)), t_eval=t, rtol=1e-10, atol=1e-14, method="DOP853")
    reac = []
    for i, tt in enumerate(t):
        u, v = drive(tt)
        r = model["K"] @ u + model["C"] @ v
        for k, (g, (_, c, _m)) in enumerate(zip(gen, cells)):
            r = r + g * c * (g @ v - sol.y[2 * k + 1, i])
        reac.append(r[dof])
    reac = np.array(reac)
    sel = t >= (cycles - 10) * T
    X = np.column_stack([np.cos(w * t[sel]), np.sin(w * t[sel])])
    a, b = np.linalg.lstsq(X, reac[sel], rcond=None)[0]
    return b + 1j * a
