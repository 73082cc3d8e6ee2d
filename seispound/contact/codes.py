"""Integer law codes and parameter-table columns shared by the laws, the assembly and the kernel.

Plain constants (no numba), so that reading a model does not compile anything.
"""

# Integer law codes: the kernel dispatches on these so that numba's on-disk
# cache is shared across processes (no first-class functions in the loop).
NONE = 0
LVE = 1
MLVE = 2
NIVE = 3
HD = 4
LHC = 5
HERTZ = 6
HERTZDAMP = 7
HC = 8  # Hunt-Crossley with a fixed material damping constant

# Columns of the per-gap parameter table ``gap_par``.
P_K = 0  # contact stiffness k [N/m] (linear laws) or [N/m^1.5] (Hertz laws)
P_E = 1  # target coefficient of restitution e [-]
P_XI = 2  # damping ratio from e (LVe Eq. 3, MLVe Eq. 5, NIVe xi-bar) [-]
P_MEFF = 3  # m1*m2/(m1+m2) of the two colliding floors [kg]
P_TENSION = 4  # 1.0 if the force may become tensile, else clamp F >= 0
P_EXPONENT = 5  # exponent n of delta in the elastic term [-]
# restitution as a function of the approach velocity v0 (``contact.restitution``)
P_EFORM = 6  # E_CONSTANT (P_E), E_LINEAR, E_EXPONENTIAL, E_POWER or E_TABLE
P_EA, P_EB, P_EC, P_ED = 7, 8, 9, 10  # the form's parameters, in the order its docstring lists them
P_NTAB = 11  # points of a table
MAX_TABLE = 16  # points a table may have
P_TAB = 12  # velocities [m/s] in P_TAB..P_TAB+MAX_TABLE-1, e in the next MAX_TABLE columns
N_PAR = P_TAB + 2 * MAX_TABLE

E_CONSTANT, E_LINEAR, E_EXPONENTIAL, E_POWER, E_TABLE = 0, 1, 2, 3, 4
