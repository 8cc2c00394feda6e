"""Column indices of the compiled plan's tables (compile-time constants in numba).

The float tables (nodes, spans, drives, web) hold parameters and are passed to the kernel at
run time. The line's structure (which node is what, which drive sits where, where each state
block starts, which features exist) is also held in small integer tables that the kernel is
compiled against as constants (``webline.sim.kernel.compiled_loop``): its loops then have
known lengths and its branches known outcomes (the right-hand side runs 2.6 times faster
than one that reads the structure at run time). A new parameter value reuses the compiled
kernel; a new structure compiles (and caches) another.
"""

# node table columns
(N_KIND, N_RADIUS, N_CORE, N_JCONST, N_VISCOUS, N_COULOMB, N_RATIO, N_DRIVE, N_ECC,
 N_ECCSTATE, N_INVJ,
 # web-roller traction (Ch. 5): 1 if the web may slip, wrap [rad], μ0, μ', viscous [N·s/m]
 N_TRACTION, N_WRAP, N_MU, N_MUK, N_SLIPB,
 # profile of a torque opposing the rotation (drive brake or roller drag), -1: none
 N_DRAG) = range(17)
N_COLS = 17

# node structure (integer) columns, and the float columns they copy
NS_KIND, NS_DRIVE, NS_ECCSTATE, NS_TRACTION, NS_DRAG = range(5)
NS_COLS = 5
NODE_STRUCTURE = (N_KIND, N_DRIVE, N_ECCSTATE, N_TRACTION, N_DRAG)

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
 D_FEEDBACK,
 # ... and the MRAC of (6.66-6.68, E-6.8): P·b on (T, V) deviations [1/N, s/m], adaptation
 # rates of k̂_T, k̂_V [N·m/N², N·m·s²/m²] and of the bias [N·m], projection half-widths
 # of k̂_T, k̂_V [N·m/N, N·m·s/m] and of the bias [N·m]
 D_PBT, D_PBV, D_GKT, D_GKV, D_GBIAS, D_KBT, D_KBV, D_CBOUND,
 # ... and the tension observer (sim/observer.py): 1 if used, its gains on the speed residual
 # [N·s/rad, 1/s], the node on the other side of the observed span, its length [m] and the
 # EA the observer assumes [N]
 D_OBS, D_OBS_LT, D_OBS_LW, D_OBS_OTHER, D_OBS_LENGTH, D_OBS_EA) = range(48)
D_COLS = 48
ROLE_MASTER, ROLE_TENSION = 0, 1

# drive structure (integer) columns, and the float columns they copy
(DS_NODE, DS_ROLE, DS_LOADCELL, DS_REF, DS_UPREF, DS_TSTATE, DS_FAMILY, DS_FEEDBACK,
 DS_ADAPTIVE, DS_ZFIRST, DS_ZLAST) = range(11)
DS_COLS = 11
DRIVE_STRUCTURE = (D_NODE, D_ROLE, D_LOADCELL, D_REF, D_UPREF, D_TSTATE, D_FAMILY, D_FEEDBACK,
                   D_ADAPTIVE, D_ZFIRST, D_ZLAST)
FAMILY_PI, FAMILY_STATE_FEEDBACK, FAMILY_ADAPTIVE, FAMILY_MRAC = 0, 1, 2, 3

# controller memory per drive: PI integrators, adaptive friction estimate [N·m·s], the MRAC's
# adapted gains k̂_T [N·m/N], k̂_V [N·m·s/m] and bias [N·m]
I_SPEED, I_TENSION, I_FRICTION, I_KT, I_KV, I_BIAS, I_THAT, I_WHAT = range(8)
I_COLS = 8

# line-wide scalars
(W_EA, W_THICK, W_WIDTH, W_DENSITY, W_T0, W_NOISE_T, W_NOISE_V, W_SEED,
 W_RHOA,
 # the physical envelope checked every tick: web strength [N] (inf: none given), largest
 # |stretch| [N] and surface speed [m/s] a state may reach before the run is a runaway
 W_STRENGTH, W_STRETCH_MAX, W_SPEED_MAX) = range(12)
W_COLS = 12

# the integer ``offsets`` array: where state blocks start (spans at 0, node speeds, the two roll
# radii, motor torques, eccentric angles, web-length integrals), the master's upstream
# reference profile, the master node, where transmission states start, then two flags
(O_OMEGA, O_RADIUS, O_TORQUE, O_ANGLE, O_WEB, O_MASTER_UP, O_MASTER, O_TRANSMISSION) = range(1, 9)
O_NOISE = 9  # 1 if measurements carry noise
O_NEED_EQ = 10  # 1 if a controller needs the reference state every tick

# kernel status codes; with each failure the kernel returns where it happened: the span
# (strength, runaway stretch), node (runaway speed) or drive (runaway motor speed), else -1
STATUS_OK, STATUS_NONFINITE, STATUS_UNWIND_EMPTY = 0, 1, 2
STATUS_STRENGTH, STATUS_RUNAWAY_STRETCH, STATUS_RUNAWAY_SPEED, STATUS_RUNAWAY_MOTOR = 3, 4, 5, 6
