"""Impacts: their onset and end (the law's onset hook, the catalogue row), their substeps, the contact groups.

A contact law (``seispound.contact._scalar``, through the material protocol ``_material``)
knows only the penetration, its rate and the per-impact state set at onset; the gap element
knows its two DOFs (``_elements._gap_kinematics``); the Newton iteration on the closed gaps'
forces is ``_newton``.
"""

from __future__ import annotations

import math

import numpy as np
from seispound._jit import njit

from ..contact._scalar import NIVE, contact_duration, contact_force
from ._material import ST_E, ST_ZETA, material_onset

# NIVe's damping c-bar ~ delta^(1/4) makes the force rise like t^(1/4) at first
# contact; its first substeps are graded (1/2^ONSET_GRADING of the regular
# substep, doubling each substep) so that the impact converges with the substep.
ONSET_GRADING = 6
# the row's fastest mode (``simulation.contact_step``) may shorten an impact's substeps up to this factor
MAX_SUBSTEP_FACTOR = 4


@njit(cache=True, inline="always")
def _contact_step(t, t_end, dt, m_act, act_list, code, hsub, age, h_lev, n_lev, lev_min):
    """(h, lev): the next step inside the analysis step ending at t_end while gaps are closed.

    No step is longer than h_lev[lev_min] (dt / 2^lev_min: the general driver's step for rows whose
    Newmark steps need substeps to be accurate; 0 for none).

    Each closed gap asks for substeps of at most hsub (its impact's duration / n_sub), on
    the grid dt / 2^lev (h_lev[:n_lev]) so that each size is factored once; NIVe's first substeps are
    graded (ONSET_GRADING).  An element whose hsub is inf (a storey) asks for none.  The
    step runs to the next grid point, absorbing a sliver before t_end.  Shared by both
    drivers; inlined (the fast driver's loop is sensitive to calls).
    """
    remaining = t_end - t
    h = remaining
    lev = lev_min
    for q in range(m_act):
        g = act_list[q]
        lg = 0
        while lg < n_lev - 1 and h_lev[lg] > hsub[g]:
            lg += 1
        if code[g] == NIVE and age[g] < ONSET_GRADING:
            lg = min(lg + ONSET_GRADING - age[g], n_lev - 1)
        lev = max(lev, lg)
    if lev > 0:
        # next point of the dt/2^lev grid inside this analysis step
        hl = h_lev[lev]
        t_start = t_end - dt
        # (tolerant rounding: t carries round-off, never take a sliver step)
        nxt = t_start + (math.floor((t - t_start) / hl + 1e-6) + 1.0) * hl
        if nxt - t < 1e-3 * hl:
            nxt += hl
        h = min(nxt - t, remaining)
        if remaining - h < 1e-3 * hl:
            h = remaining  # absorb a sliver rather than step over it alone
    return h, lev


@njit(cache=True, inline="always")
def _grid_level(h, lev, h_lev, dt):
    """(lv, h): the level of the dt/2^k grid a step of h [s] lies on (lev, the level its step was cut
    to, or 0 for a whole analysis step) and h snapped to it; (-1, h) for a step off the grid (a
    located step), which takes a scratch factor.  Both drivers cache A(h) per level."""
    if abs(h - h_lev[lev]) <= 1e-9 * h:
        return lev, h_lev[lev]
    if abs(h - dt) <= 1e-9 * dt:
        return 0, h_lev[0]
    return -1, h


@njit(cache=True, inline="always")
def _peak_through(fa, fb, fc, ha, hc):
    """The peak of a contact force between its samples: the vertex of the parabola through
    (-ha, fa), (0, fb), (hc, fc) when fb is a local maximum, else fb.

    The force of a substepped impact is known at the substeps' ends only, and its
    maximum falls between two of them: taking the largest sample misses it by up to
    (omega h)^2 / 8 of the peak for a force ~ sin(omega t) (0.5 % at 16 substeps per
    impact).  The vertex of the interpolating parabola (Lagrange, unequal spacing) is
    within O((omega h)^3) of it.  Forces [N], step lengths [s].
    """
    if fb < fa or fb < fc or ha <= 0.0 or hc <= 0.0:
        return fb
    sa = (fa - fb) / ha
    sc = (fc - fb) / hc
    c = (sa + sc) / (ha + hc)  # curvature / 2 (<= 0 here)
    if c >= 0.0:
        return fb  # flat: the three samples are equal
    b = sc - c * hc  # slope at the middle sample
    x = -b / (2.0 * c)
    if x < -ha or x > hc:
        return fb
    return fb - b * b / (4.0 * c)


@njit(cache=True)
def _end_impact(g, t, rg, m_act, act_list, cs, cat):
    """Close gap g's impact at time t with separation rate rg: its catalogue row (duration, exit
    velocity -rg) and the list of closed gaps; returns the new number of closed gaps.

    cs = (active, st_c, hsub, age, cur_imp): each gap's contact state; cat = (gap, t0, v0, vout, fmax,
    dur, zeta, e): the impact catalogue (``_begin_impact``)."""
    active, cur_imp = cs[0], cs[4]
    imp_t0, imp_vout, imp_dur = cat[1], cat[3], cat[5]
    active[g] = False
    for q in range(m_act):
        if act_list[q] == g:
            act_list[q] = act_list[m_act - 1]
            m_act -= 1
            break
    q = cur_imp[g]
    imp_dur[q] = t - imp_t0[q]
    imp_vout[q] = -rg
    cur_imp[g] = -1
    return m_act


@njit(cache=True)
def _group_contacts(m, act_list, gap_lo, gap_hi, comp_off):
    """Order the m closed gaps into groups that share no building; return the number of groups.

    Gaps whose blocks (DOF ranges gap_lo..gap_hi-1: the buildings a gap links
    and any between them) do not overlap are uncoupled: G = B^T K_hat^-1 B is
    block diagonal over such groups, because K_hat is block diagonal over the
    buildings.  act_list[:m] is sorted by gap_lo (insertion sort: it is
    nearly sorted from the previous event) and group c is
    act_list[comp_off[c]:comp_off[c + 1]].
    """
    comp_off[0] = 0
    if m <= 1:
        comp_off[1] = m
        return m
    for s in range(1, m):
        g = act_list[s]
        t = s - 1
        while t >= 0 and (gap_lo[act_list[t]] > gap_lo[g]
                          or (gap_lo[act_list[t]] == gap_lo[g] and act_list[t] > g)):
            act_list[t + 1] = act_list[t]
            t -= 1
        act_list[t + 1] = g
    n_comp = 0
    reach = gap_hi[act_list[0]]
    for q in range(1, m):
        g = act_list[q]
        if gap_lo[g] >= reach:
            n_comp += 1
            comp_off[n_comp] = q
        reach = max(reach, gap_hi[g])
    n_comp += 1
    comp_off[n_comp] = m
    return n_comp


@njit(cache=True)
def _begin_impact(g, t, dg, rg, code, par, n_sub, cs, cat, n_imp):
    """Open impact number ``n_imp`` at gap g: the law's onset hook (``_material.material_onset``)
    commits its damping and the e it comes from, set by the approach velocity rg, to row g of the
    state table st_c; size its substeps, start its catalogue row; return its onset
    force.

    cs = (active (ng,) bool, st_c (ng, N_STATE), hsub (ng,) [s], age (ng,) int, cur_imp (ng,) int): each
    gap's contact state (closed?, committed law state, substep, accepted substeps, catalogue row);
    cat = (gap, t0 [s], v0 [m/s], vout [m/s], fmax [N], dur [s], zeta, e), each (capacity,): the impact
    catalogue."""
    active, st_c, hsub, age, cur_imp = cs
    imp_gap, imp_t0, imp_v0, imp_vout, imp_fmax, imp_dur, imp_zeta, imp_e = cat
    active[g] = True
    material_onset(code, par, rg, st_c[g])
    imp_e[n_imp] = st_c[g, ST_E]
    # n_sub = (substeps per impact duration, longest substep [s]: the row's fastest mode's limit), the
    # limit never asking more than MAX_SUBSTEP_FACTOR times the substeps (it costs that much per impact)
    dur = contact_duration(code, par, rg)
    hsub[g] = max(min(dur / n_sub[0], n_sub[1]), dur / (MAX_SUBSTEP_FACTOR * n_sub[0]))
    age[g] = 0
    cur_imp[g] = n_imp
    imp_gap[n_imp] = g
    imp_t0[n_imp] = t
    imp_v0[n_imp] = rg
    imp_zeta[n_imp] = st_c[g, ST_ZETA]
    imp_dur[n_imp] = np.nan
    imp_vout[n_imp] = np.nan
    f0 = contact_force(code, par, dg, rg, st_c[g, ST_ZETA])[0]
    imp_fmax[n_imp] = max(f0, 0.0)
    return f0
