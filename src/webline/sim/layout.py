"""Column indices of the compiled plan's parameter tables (compile-time constants in numba)."""

# node table columns
(N_KIND, N_RADIUS, N_CORE, N_JCONST, N_VISCOUS, N_COULOMB, N_RATIO, N_DRIVE, N_ECC,
 N_ECCSTATE, N_INVJ,
 # web-roller traction (Ch. 5): 1 if the web may slip, wrap [rad], μ0, μ', viscous [N·s/m]
 N_TRACTION, N_WRAP, N_MU, N_MUK, N_SLIPB,
 # profile of a torque opposing the rotation (drive brake or roller drag), -1: none
 N_DRAG) = range(17)
N_COLS = 17

# span table columns
S_LENGTH, S_INVLENGTH = range(2)
S_COLS = 2
KIND_UNWIND, KIND_DRIVEN, KIND_IDLE, KIND_REWIND = 0, 1, 2, 3

# drive table columns: topology and cascaded PI ...
(D_NODE, D_ROLE, D_LOADCELL, D_REF, D_SIGMA, D_KPS, D_KIS, D_KPT, D_KIT, D_LIMIT, D_LAG,
 D_ADAPTIVE, D_GAINNORM, D_UPREF, D_INVLAG, D_ZFIRST, D_ZLAST,
 # ... and the decentralized controllers of Ch. 6: family, state-feedback gains, adaptive
 # law (rate, leakage, upper bound of the estimate) and the controller's friction model
 D_FAMILY, D_KT, D_KV, D_GAMMA, D_LEAK, D_BMAX, D_BMODEL,
 # ... and the transmission: compliant or rigid, its state offset, load-side stiffness
 # [N·m/rad], damping [N·m·s/rad] and free travel [rad], motor inertia and friction, ratio,
 # speed feedback side (0 load, 1 motor)
 D_COMPLIANT, D_TSTATE, D_KTRANS, D_CTRANS, D_GAPNEG, D_GAPPOS, D_JMOTOR, D_BMOTOR, D_RATIO,
 D_FEEDBACK) = range(34)
D_COLS = 34
ROLE_MASTER, ROLE_TENSION = 0, 1
FAMILY_PI, FAMILY_STATE_FEEDBACK, FAMILY_ADAPTIVE = 0, 1, 2

# controller memory per drive: PI integrators, adaptive friction estimate [N·m·s]
I_SPEED, I_TENSION, I_FRICTION = range(3)
I_COLS = 3

# line-wide scalars
(W_EA, W_THICK, W_WIDTH, W_DENSITY, W_T0, W_NOISE_T, W_NOISE_V, W_SEED,
 W_NEED_EQ, W_RHOA) = range(10)
W_COLS = 10

# kernel status codes
STATUS_OK, STATUS_NONFINITE, STATUS_UNWIND_EMPTY = 0, 1, 2
