"""Column indices of the compiled plan's tables (compile-time constants in numba).

The float tables (nodes, spans, drives, web) hold parameters and are passed to the kernel at
run time. The line's structure (which node is what, which drive sits where, where each state
block starts, which features exist) is also held in small integer tables that the kernel is
compiled against as constants (``webline.sim.core.kernel.compiled_loop``): its loops then have
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
 N_DRAG,
 # dancer (docs/winder.md): index of its position state (-1: none; velocity follows), 1/mass
 # [1/kg], spring [N/m], damper [N·s/m], set position, travel [m], end-stop spring [N/m] and
 # damper [N·s/m], load profile
 N_DANCER, N_DINVM, N_DK, N_DC, N_DSET, N_DTRAVEL, N_DSTOP, N_DSTOPC, N_DLOAD,
 # a traction nip's static and Coulomb friction on the web, 2 μ_n N and 2 μ_n' N [N] (its
 # inertia and bearing friction are in N_JCONST, N_VISCOUS, N_COULOMB; docs/winder.md, Nip)
 N_NIPS, N_NIPK,
 # the flying splices of a roll (docs/winder.md S1; ``sim.elements.splice``): index p of the profile
 # whose breakpoints are the splices' times [s] and new radii [m] (-1: none); profiles p + 1
 # and p + 2 hold, at the same times, the new roll's surface speed over the web's [-] and the
 # slack [m] each splice puts into the span next to the roll
 N_SPLICE,
 # a roll's wound density [kg/m³]: the web's, or derived from its totals (spec.roll_inertia)
 N_RHO) = range(30)
# friction as drives measure it (docs/winder.md F1-F2): points of the friction table (0:
# none), its speeds [rad/s] and torques [N·m] (5 slots each), the break-away torque [N·m]
# (0: none) and the time constant [s] that holds a stuck roller at rest
N_FRICN, N_FRICW, N_FRICT, N_BREAKAWAY, N_STICKTAU = 30, 31, 36, 41, 42
# a dancer's geometry (docs/winder.md D0): how much its upstream and downstream span lengthen
# per metre of carriage travel, g = (strands / 2) cos(angle) (1 for two parallel strands)
N_DGIN, N_DGOUT = 43, 44
# 1.0 for a dancer whose geometry is not g = 1 (N_DGIN, N_DGOUT), copied into the node
# structure so that a plain dancer's loop compiles as it did before D0 (numba's fastmath
# reassociates sums across the code it sees: a product by g = 1 changed the last bits)
N_DGEOM = 45
N_COLS = 46
FRICTION_POINTS = 5  # slots of a friction table (spec.friction.MAX_POINTS)

# node structure (integer) columns, and the float columns they copy
NS_KIND, NS_DRIVE, NS_ECCSTATE, NS_TRACTION, NS_DRAG, NS_DANCER = range(6)
NS_DGEOM = 6  # a dancer's geometry other than g = 1 (D0)
NS_COLS = 7
NODE_STRUCTURE = (N_KIND, N_DRIVE, N_ECCSTATE, N_TRACTION, N_DRAG, N_DANCER, N_DGEOM)

# span table columns
# length [m], 1/length, time it breaks [s] (inf), Kelvin-Voigt retardation τ [s] (0: elastic)
S_LENGTH, S_INVLENGTH, S_BREAK, S_TAU = range(4)
S_COLS = 4
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
 # ... and the tension observer (sim/drives/observer.py): 1 if used, its gains on the speed
 # residual
 # [N·s/rad, 1/s], the node on the other side of the observed span, its length [m] and the
 # EA the observer assumes [N]
 D_OBS, D_OBS_LT, D_OBS_LW, D_OBS_OTHER, D_OBS_LENGTH, D_OBS_EA,
 # ... and the dancer its zone's PI uses: node (-1 none) and use (DANCER_POSITION/_TENSION)
 D_DANCER, D_DUSE,
 # ... and the rewind's taper (docs/winder.md W1): kind (0 none, physics.taper), taper [-],
 # core and largest diameter [m], profile of its (diameter, factor) table
 D_TAPER, D_TAPERK, D_TAPERDC, D_TAPERDM, D_TAPERP,
 # ... and the diameter calculator (W2): method (0 none: the true radius), filter time
 # constant [s], rate limit [m/s of diameter], hold below [m/s], initial diameter [m] (0:
 # measured)
 D_DCALC, D_DFILTER, D_DRATE, D_DHOLD, D_DINIT,
 # ... and the centre winder's compensation (W3): inertia (1 on), static [N·m] and viscous
 # [N·m·s] friction at the roll shaft
 D_COMPJ, D_COMPCS, D_COMPB,
 # ... where the diameter calculator's line speed comes from (DSOURCE_* or the node of
 # a measuring roller)
 D_DSOURCE,
 # ... and an open-loop drive's speed limiter (W7): offset over the line reference [m/s]
 D_SPEEDLIM) = range(65)
# ... and its friction table (F1): points (0: none), speeds [rad/s], torques [N·m], 5 slots
D_COMPFN, D_COMPFW, D_COMPFT = 65, 66, 71
# ... and the diameter calculator's presets while running (W2a): how many, their times [s]
# and diameters [m] (0: the true one), 4 slots
D_PRESETN, D_PRESETT, D_PRESETD = 76, 77, 81
# ... and the sensors it reads (spec.sensors; read only where O_SENSORS is 1): its loadcell's
# gain [-] and offset [N] (the controller reads gain T + offset), its encoder's scale [-],
# and the delay of each signal in whole controller samples (at most MAX_DELAY)
D_TGAIN, D_TOFFSET, D_VSCALE, D_TDELAY, D_VDELAY = 85, 86, 87, 88, 89
D_COLS = 90
MAX_DELAY = 32  # the longest sensor delay [controller samples]: 32 ms at 1 kHz
DSOURCE_MASTER, DSOURCE_REFERENCE = -1, -2
DCALC_NONE, DCALC_SPEED_RATIO, DCALC_THICKNESS = 0, 1, 2
DANCER_NONE, DANCER_POSITION, DANCER_TENSION = 0, 1, 2
ROLE_MASTER, ROLE_TENSION = 0, 1

# drive structure (integer) columns, and the float columns they copy
(DS_NODE, DS_ROLE, DS_LOADCELL, DS_REF, DS_UPREF, DS_TSTATE, DS_FAMILY, DS_FEEDBACK,
 DS_ADAPTIVE, DS_ZFIRST, DS_ZLAST, DS_DANCER, DS_DUSE) = range(13)
DS_COLS = 13
DRIVE_STRUCTURE = (D_NODE, D_ROLE, D_LOADCELL, D_REF, D_UPREF, D_TSTATE, D_FAMILY, D_FEEDBACK,
                   D_ADAPTIVE, D_ZFIRST, D_ZLAST, D_DANCER, D_DUSE)
FAMILY_PI, FAMILY_STATE_FEEDBACK, FAMILY_ADAPTIVE, FAMILY_MRAC = 0, 1, 2, 3
FAMILY_OPEN_LOOP = 4  # indirect tension control of a centre winder (docs/winder.md W4)
# a user's controller: its held command is written between ticks (sim.drives.user_loop)
FAMILY_USER = 5

# controller memory per drive: PI integrators, adaptive friction estimate [N·m·s], the MRAC's
# adapted gains k̂_T [N·m/N], k̂_V [N·m·s/m] and bias [N·m] and its observer's estimates, the
# radius the controller uses [m] (calculated, or the true one) and the break monitor's
# detection time [s] (-1: none) and method (BREAK_*), in every row, and the smallest (unwind)
# or largest (rewind) calculated radius so far [m] (0: none yet), for BREAK_DIAMETER
(I_SPEED, I_TENSION, I_FRICTION, I_KT, I_KV, I_BIAS, I_THAT, I_WHAT, I_RADIUS, I_DETECT,
 I_METHOD, I_REXTREME) = range(12)
# ... and the last MAX_DELAY + 1 readings of its loadcell [N] and of its encoder [m/s], ring
# buffers indexed by tick (sim.elements.sensor_loop.delayed)
DELAY_SLOTS = MAX_DELAY + 1
I_TBUF = 12
I_VBUF = I_TBUF + DELAY_SLOTS
I_COLS = I_VBUF + DELAY_SLOTS

# line-wide scalars
(W_EA, W_THICK, W_WIDTH, W_DENSITY, W_T0, W_NOISE_T, W_NOISE_V, W_SEED,
 W_RHOA,
 # the physical envelope checked every tick: web strength [N] (inf: none given), largest
 # |stretch| [N] and surface speed [m/s] a state may reach before the run is a runaway
 W_STRENGTH, W_STRETCH_MAX, W_SPEED_MAX,
 # the break monitor: tension threshold [fraction of the reference], ramp-to-stop time [s],
 # diameter threshold [m] (0: off)
 W_BTHRESH, W_BSTOP, W_BDIAM,
 # ... its overspeed detection (1 on), the hold after the stop (HOLD_*), the standstill
 # tension [fraction of the set tension] and the brakes' torque [fraction of the limit] (W8)
 W_BOVER, W_BHOLD, W_BSTALL, W_BBRAKE,
 # the resolution of measured surface speeds [m/s] (0: exact)
 W_RES_V) = range(20)
W_TRAMP = 20  # the profile of the tension ramp's factor (docs/winder.md R1; 0: none)
W_COLS = 21
BREAK_TENSION, BREAK_DANCER, BREAK_DIAMETER = 1, 2, 3  # how the monitor detected a break
BREAK_OVERSPEED = 4  # an open-loop roll at its speed limit (W7)
HOLD_OFF, HOLD_ZERO_SPEED, HOLD_BRAKES = 0, 1, 2  # what the drives do after the stop (W8)
HOLD_STALL = 3  # the rolls' drives hold their stall tension as a torque, the others zero speed

# the integer ``offsets`` array: where state blocks start (spans at 0, node speeds, the two roll
# radii, motor torques, eccentric angles, web-length integrals), the master's upstream
# reference profile, the master node, where transmission states start, then flags
(O_OMEGA, O_RADIUS, O_TORQUE, O_ANGLE, O_WEB, O_MASTER_UP, O_MASTER, O_TRANSMISSION) = range(1, 9)
O_NOISE = 9  # 1 if measurements carry noise or a resolution
O_NEED_EQ = 10  # 1 if a controller needs the reference state every tick
O_BREAK = 11  # 1 if the web breaks in this run (docs/winder.md W5): the break monitor is on
O_KV = 12  # 1 if the rollers and loadcells feel other than the stretch: T = F(s) + τ ds/dt
O_SPLICE = 13  # 1 if a roll is spliced in this run (docs/winder.md S1, ``sim.elements.splice``)
O_FRICTION = 14  # 1 if a roller or a compensation has a friction table or a break-away (F1-F2)
O_OWNRHO = 15  # 1 if a roll has its own wound density, from its totals (J1)
O_LAW = 16  # 1 if the web's stress-strain law is nonlinear: T = F(s) (``physics.web_law``),
# the law's array after the W_COLS scalars of the web table
O_EXACT = 17  # 1 if spans conserve web mass exactly (``web.transport``), 0: thesis 6.8 (E-6.6)
O_SENSORS = 18  # 1 if a sensor is other than ideal (spec.sensors): D_TGAIN ... D_VDELAY

# kernel status codes; with each failure the kernel returns where it happened: the span
# (strength, runaway stretch), node (runaway speed) or drive (runaway motor speed), else -1
STATUS_OK, STATUS_NONFINITE, STATUS_UNWIND_EMPTY = 0, 1, 2
STATUS_STRENGTH, STATUS_RUNAWAY_STRETCH, STATUS_RUNAWAY_SPEED, STATUS_RUNAWAY_MOTOR = 3, 4, 5, 6
