"""What the kernel returns besides its arrays: status codes, energy columns and counters."""

# status codes returned by the kernel
OK = 0
NEWTON_FAILED = 1
IMPACT_CAPACITY = 2

# columns of the energy output
E_INPUT, E_KINETIC, E_STRAIN, E_DAMPING, E_CONTACT = 0, 1, 2, 3, 4
# (the general driver adds the energy dissipated by hysteretic storeys)
E_HYSTERETIC = 5

# entries of the stats output
S_STEPS, S_ITERATIONS, S_REJECTED, S_FACTORIZATIONS, S_MAX_ITER, S_FREE_FLIGHT, S_BLOCKS = 0, 1, 2, 3, 4, 5, 6
# multi-rate stepping: analysis steps in which some buildings waited, buildings that
# joined the stepping ones inside a step, and DOF-steps (DOFs x steps, accepted or
# redone, free flight included: the work in units of one DOF's Newmark step)
S_WAITING, S_JOINS, S_DOF_STEPS = 7, 8, 9
N_STATS = 10
