"""Integer codes and parameter columns of the storey laws with history, shared by the model and the kernel.

Plain constants (no numba), so that reading a model does not compile anything.
Codes start at 20, above every contact-law code (``contact.codes``): both
families go through one material protocol in the kernel (``integrate._material``).
"""

LINEAR = 0  # an elastic storey (a linear spring of the linear part)
BILINEAR = 20  # kinematic hardening
BOUC_WEN = 21  # smooth hysteresis (Bouc 1967, Wen 1976)
PEAK_ORIENTED = 22  # stiffness-degrading, peak-oriented (Clough & Johnston 1966; Takeda, Sozen & Nielsen 1970)
IWAN = 23  # distributed-element (Iwan 1966): Masing's rules, optionally partly self-centring
FLAG = 24  # flag-shaped, self-centring (Christopoulos, Filiatrault & Folz 2002)

# parameter columns of BILINEAR: initial stiffness k [N/m], yield force fy [N], post-yield ratio alpha [-]
B_K, B_FY, B_ALPHA = 0, 1, 2
# parameter columns of BOUC_WEN: k [N/m], yield deformation dy [m], alpha [-], exponent n, beta, gamma [-],
# the degradation rates of strength (delta_nu) and stiffness (delta_eta) with the hysteretic energy [-],
# and the pinching's severity zeta_s [-], its growth rate p with the hysteretic energy [-] and its width over dy
# psi [-] (Baber & Noori 1985; Foliente 1995)
BW_K, BW_DY, BW_ALPHA, BW_N, BW_BETA, BW_GAMMA, BW_DNU, BW_DETA = 0, 1, 2, 3, 4, 5, 6, 7
BW_PINCH, BW_PINCH_RATE, BW_PINCH_WIDTH = 8, 9, 10
# parameter columns of PEAK_ORIENTED: k [N/m], yield force fy [N], post-yield ratio alpha [-], the unloading
# stiffness's exponent beta_u [-] (Otani 1974: k_u = k (dy / d_m)^beta_u) and the pinching severity [-]
# (reloading first aims at (1 - pinching) times its target force)
PO_K, PO_FY, PO_ALPHA, PO_UNLOAD, PO_PINCH = 0, 1, 2, 3, 4
# parameter columns of IWAN: k [N/m], the sliders' geometric-mean yield drift dy [m], alpha [-], the spread s of
# the sliders' yield drifts [decades] and the self-centring share c of the hysteretic stiffness [-] (``_iwan``)
IW_K, IW_DY, IW_ALPHA, IW_SPREAD, IW_CENTRING = 0, 1, 2, 3, 4
# and, derived from dy and s by ``laws.StoreyLaw.kernel_rows`` (so that the kernel raises nothing to a power): the
# first slider's yield drift d_0 [m] and the ratio d_(i+1) / d_i [-]
IW_D0, IW_RATIO = 5, 6
IWAN_SLIDERS = 8  # elastic-perfectly-plastic sliders of an Iwan storey (a state column each)
# parameter columns of FLAG: k [N/m], yield drift dy [m], alpha [-] and beta, the force drop on unloading over the
# yield force k dy [-] (``_flag``)
FL_K, FL_DY, FL_ALPHA, FL_BETA = 0, 1, 2, 3
N_STOREY_PAR = 11

NAMES = {"elastic": LINEAR, "bilinear": BILINEAR, "bouc-wen": BOUC_WEN, "peak-oriented": PEAK_ORIENTED, "iwan": IWAN,
         "flag": FLAG}
