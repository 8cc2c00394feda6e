"""Column indices of the compiled plan's parameter tables (compile-time constants in numba)."""

# node table columns
(N_KIND, N_RADIUS, N_CORE, N_JCONST, N_VISCOUS, N_COULOMB, N_RATIO, N_DRIVE, N_ECC,
 N_ECCSTATE, N_INVJ) = range(11)
N_COLS = 11

# span table columns
S_LENGTH, S_INVLENGTH = range(2)
S_COLS = 2
KIND_UNWIND, KIND_DRIVEN, KIND_IDLE, KIND_REWIND = 0, 1, 2, 3

# drive table columns
(D_NODE, D_ROLE, D_LOADCELL, D_REF, D_SIGMA, D_KPS, D_KIS, D_KPT, D_KIT, D_LIMIT, D_LAG,
 D_ADAPTIVE, D_GAINNORM, D_UPREF, D_INVLAG) = range(15)
D_COLS = 15
ROLE_MASTER, ROLE_TENSION = 0, 1

# web scalars
W_EA, W_THICK, W_WIDTH, W_DENSITY, W_T0 = range(5)
W_COLS = 5

# kernel status codes
STATUS_OK, STATUS_NONFINITE, STATUS_UNWIND_EMPTY = 0, 1, 2
