"""Column numbers of the flat tables of a branched line's plan (``sim.branches.plan``).

State vector: span stretches EA·ε [N] | node speeds ω [rad/s] | roll radii [m] | motor
torques [N·m] | web length in and out [m] per web (unstrained web that entered the web's
first span and left its last one) | lane core speeds ω [rad/s] on differential shafts |
angles [rad] of eccentric rollers.
"""

from __future__ import annotations

from webline.sim.elements.layout import DELAY_SLOTS
from webline.spec.winder import MAX_PRESETS

# offsets row
O_OMEGA, O_RADIUS, O_TORQUE, O_WEB, O_CORE, O_ANGLE, O_N = range(7)
# (tension ramp, docs/winder.md R1: the profile of its factor on every zone's reference, -1
# without a ramp)
O_RAMP = 7
# web break (sim.branches.disturb): 1 where the line has a break in this run (a flag frozen
# into the compiled loop, so that a line without one folds the monitor and the cut away)
O_BREAK = 8
# traction rollers and measured friction (docs/branching.md, "Slip and measured friction"):
# 1 where any roller's web may slip over it | any roller has a friction table or a
# break-away torque; 0 folds their code away in the compiled loop
O_SLIP, O_FRICTION = 9, 10

# node table (float)
# (N_ECC: eccentricity [m]; N_ANGLE: its angle state's number, -1 where round)
(N_RADIUS, N_JCONST, N_VISCOUS, N_COULOMB, N_CORE, N_RATIO, N_DRIVE, N_INVJ, N_ROLLS, N_ECC,
 N_ANGLE, N_COLS) = range(12)

# traction rollers and measured friction (docs/branching.md, "Slip and measured friction"),
# node table columns at its end: 1 on a traction roller; wrap [rad], μ0, μ', viscous
# traction [N·s/m], a traction nip's static and Coulomb force [N], the web's mass per length
# [kg/m], the spans in and out; the stick/slip state held over a tick (0 stuck, 1
# slipping), the time slipped [s], the break-aways, the first one's time [s] (nan: none),
# the largest slip speed [m/s] at a tick; a friction table's points, speeds [rad/s] and
# torques [N·m]; the break-away torque [N·m]; the control period [s] (a held roller's ω
# decays in it)
(N_TRACTION, N_WRAP, N_MU, N_MUK, N_SLIPB, N_NIPS, N_NIPK, N_RHOA, N_SPIN, N_SPOUT,
 N_SLIPPING, N_SLIPTIME, N_SLIPCOUNT, N_SLIPFIRST, N_SLIPPEAK) = range(N_COLS, N_COLS + 15)
FRICTION_POINTS = 5  # (spec.friction.MAX_POINTS)
N_FRICN = N_SLIPPEAK + 1
N_FRICW = N_FRICN + 1
N_FRICT = N_FRICW + FRICTION_POINTS
N_BREAKAWAY = N_FRICT + FRICTION_POINTS
N_STICKTAU = N_BREAKAWAY + 1
N_COLS = N_STICKTAU + 1

# span table (int): nodes, web, where the carried-in stretch comes from, roll arms, layers,
# the clutch core its downstream end winds on (-1: the node itself), the angle states of its
# ends' nodes where they are eccentric (-1: round)
(S_A, S_B, S_WEB, S_SRC, S_FROM, S_ARMA, S_ARMB, S_COUNT, S_CORE, S_ECCA, S_ECCB,
 S_COLS) = range(12)
# span table (float)
SF_LENGTH, SF_EA, SF_SHARE, SF_INVEA = range(4)
# web break: the time [s] the span breaks (inf: never; every span of the broken segment)
SF_BREAK = 4
SF_COLS = 5
#: S_SRC: the previous span of the path | the unwind's wound-in tension | the sum of the
#: layers' last spans (a laminate's first span) | the base web's last span x share (a lane)
SRC_PREVIOUS, SRC_WOUND, SRC_LAYERS, SRC_SLIT = range(4)
# web laws (docs/branching.md, "Web laws"): span table (int) columns at its end, the first
# of the span's law terms and their number (0: the span's web is linear, T = max(s, 0));
# span table (float): Kelvin-Voigt retardation time [s] (0: elastic), the stretch [N] at
# which the span's weakest web breaks (inf: no strength)
S_LAW0, S_NLAW = S_COLS, S_COLS + 1
SF_TAU, SF_STRENGTH = SF_COLS, SF_COLS + 1
S_COLS, SF_COLS = S_COLS + 2, SF_COLS + 2
# law terms (int): the raw web whose law it is, its law's start in the flat law array;
# (float): the scale a on the span's stretch and the factor c on the law's tension,
# T = sum over the span's terms of c F_web(a s)
LI_WEB, LI_START, LI_COLS = range(3)
LF_SCALE, LF_FACTOR, LF_COLS = range(3)

# roll table (float): node, web, direction, thickness, width, density, core radius, 1 where
# the roll turns on its own clutch core (a differential shaft's lane), else 0
R_NODE, R_WEB, R_DIR, R_THICK, R_WIDTH, R_RHO, R_CORE, R_CLUTCH, R_COLS = range(9)

# clutch cores of differential shafts (int): the lane's roll, the shaft's node, the lane span
C_ROLL, C_NODE, C_SPAN, C_COLS = range(4)
# clutch cores (float): slip torque [N·m], core inertia [kg·m²], overspeed [-]
CF_SLIP, CF_INERTIA, CF_OVERSPEED, CF_COLS = range(4)

# web table (int): first span, last span
WB_FIRST, WB_LAST, WB_COLS = range(3)

# drive table (int)
# (DI_WINDER: centre-winder compensation, docs/winder.md W3-W4: WINDER_*; DI_FAMILY: the
# controller family, docs/branching.md "State feedback": FAMILY_*)
DI_NODE, DI_CELLS, DI_NCELLS, DI_ROLL, DI_WINDER, DI_FAMILY, DI_COLS = range(7)
WINDER_NONE, WINDER_COMP, WINDER_OPEN = range(3)
#: DI_FAMILY: the cascaded PI | decentralized state feedback | decentralized adaptive
#: (friction estimate) | MRAC
FAMILY_PI, FAMILY_STATE_FEEDBACK, FAMILY_ADAPTIVE, FAMILY_MRAC = range(4)
FAMILIES = {"cascaded_pi": FAMILY_PI, "state_feedback": FAMILY_STATE_FEEDBACK,
            "adaptive": FAMILY_ADAPTIVE, "mrac": FAMILY_MRAC}
# drive table (float)
# (taper: kind of physics.taper, 0 none; taper; largest diameter [m]; a table's profile.
# diameter calculator: DCALC_*; filter [s]; rate limit [m/s]; hold below [m/s]; line-speed
# source node, -1 the reference; thickness [m]; +1 winding, -1 unwinding; presets: their
# number, then MAX_PRESETS times and MAX_PRESETS diameters [m], 0: the true one)
(D_RATIO, D_KPS, D_KIS, D_KPT, D_KIT, D_LIMIT, D_INVLAG, D_SIGMA, D_GAINNORM, D_FF,
 D_ADAPTIVE, D_TAPER_KIND, D_TAPER, D_TAPER_DMAX, D_TAPER_PROF, D_DCALC, D_DFILTER, D_DRATE,
 D_DHOLD, D_DSOURCE, D_DTHICK, D_DDIR, D_PRESETN) = range(23)
D_PRESETT = D_PRESETN + 1
D_PRESETD = D_PRESETT + MAX_PRESETS
# centre-winder compensation and open-loop tension control (docs/winder.md W3-W4, W7): 1 with
# inertia compensation; static friction [N·m]; viscous friction [N·m·s]; the friction
# table's profile (over |ω| [rad/s]), -1 none; the open-loop speed limiter's offset [m/s];
# +1 a rewind (the web pulls it back), -1 an unwind
(D_COMPJ, D_COMPCS, D_COMPB, D_COMPFP, D_SPEEDLIM,
 D_DIR) = range(D_PRESETD + MAX_PRESETS, D_PRESETD + MAX_PRESETS + 6)
D_BREAK = D_DIR + 1
# web break (sim.branches.disturb), the same on every drive's row: the monitor's threshold
# (x each loadcell's reference), stop time [s], hold after the stop (HOLD_*), diameter
# threshold [m] (0: off), the holding brake as a fraction of the torque limit (hold
# "brakes": fraction x limit x ratio at the roller)
D_BTHRESH, D_BSTOP, D_BHOLD, D_BDIAM, D_BBRAKE = range(D_BREAK, D_BREAK + 5)
D_COLS = D_BREAK + 5
HOLD_ZERO_SPEED, HOLD_OFF, HOLD_BRAKES = range(3)
HOLD_STALL = 3  # the rolls' drives hold their stall tension as a torque, the others zero speed
DCALC_NONE, DCALC_SPEED_RATIO, DCALC_THICKNESS = range(3)

# controller memory per drive
# controller memory per drive (I_RADIUS: the diameter calculator's radius [m])
# (I_FRICTION: the adaptive family's friction estimate b̂ [N·m·s]; I_FACTOR: the drive's
# taper factor at its last tick, read by the decentralized families' references; the MRAC's
# adapted gains k̂_T [N·m/N], k̂_V [N·m·s/m] and bias ĉ [N·m])
I_SPEED, I_TENSION, I_RADIUS, I_FRICTION, I_FACTOR, I_KT, I_KV, I_BIAS = range(8)
# web break (sim.branches.disturb), on every drive's row: the time it was detected [s] (-1:
# not yet), the method (BREAK_*), where (the loadcell's span, or the drive), the extreme of
# the drive's calculated radius so far [m]
I_DETECT, I_METHOD, I_WHERE, I_REXTREME = range(8, 12)
I_COLS = 12
BREAK_TENSION, BREAK_DIAMETER = range(1, 3)

# event table (roll change): time, roll, new radius, new wound-in tension, web
# (flying splice, docs/winder.md S1: E_KIND an EVENT_*; the new roll's surface speed over the
# web's, 1 + mismatch; slack [m] put into the roll's span)
E_TIME, E_ROLL, E_RADIUS, E_WOUND, E_WEB, E_KIND, E_GAIN, E_SLACK, E_COLS = range(9)
EVENT_ROLL_CHANGE, EVENT_SPLICE = range(2)

STATUS_OK, STATUS_NONFINITE, STATUS_UNWIND_EMPTY, STATUS_RUNAWAY = range(4)
#: web laws: a span's stretch beyond its web's strength (``SF_STRENGTH``)
STATUS_STRENGTH = 4
#: a strain beyond this, or a speed beyond 3x the top reference + 1 m/s, is a runaway [-]
RUNAWAY_STRAIN = 0.05

# disturbance table (float): kind, index (web, drive, node; a noise's seed), then per kind
# ripple (amplitude, frequency [Hz], phase [rad]) | drag (profile number) | noise (tension
# sigma [N], speed sigma [m/s], speed resolution [m/s])
DS_KIND, DS_INDEX, DS_A, DS_B, DS_C, DS_COLS = range(6)
DIST_WOUND_RIPPLE, DIST_SPEED_RIPPLE, DIST_DRAG, DIST_NOISE = range(4)

# decentralized families (sim.branches.drives.decentral, loop.decentral): per drive (float) the
# gains K_T [N·m/N], K_V [N·m·s/m]; the friction model b [N·m·s] of the roller and the motor's
# reflected n² b_m; the adaptive law's (and the MRAC's) γ [rad/s], leakage, bound b_max
# [N·m·s]; the thickness [m] and direction (+1 winding, -1 unwinding, 0 a roller) of the roll
# it measures speed on; the MRAC's law (the chain's sim.core.drive_table._mrac_columns): P b
# per state, the rates of k̂_T, k̂_V and ĉ, the projection half-widths of k̂_T, k̂_V and ĉ
(FB_KT, FB_KV, FB_BMODEL, FB_BMOTOR, FB_GAMMA, FB_LEAK, FB_BMAX, FB_THICK, FB_DIR, FB_PBT,
 FB_PBV, FB_GKT, FB_GKV, FB_GBIAS, FB_KBT, FB_KBV, FB_CBOUND, FB_COLS) = range(18)
# references (float, rows x (1 + cells)): per span, its operating-point tension [N] then its
# change per newton of each loadcell's reference; per drive, its surface speed [m/s] and its
# change [m/s/N]; then the operating point's line speed [m/s] and each loadcell's reference
# [N] there (taper included); the last row: scratch, each loadcell's reference change [N]

# compliant transmissions and brakes (docs/branching.md, "Drive trains"): drive table (int)
# column at its end, the state number of the drive's motor speed ω_m [rad/s] (its twist
# [rad] at the load shaft follows it), -1 for a direct drive; drive table (float) columns at
# its end: stiffness [N·m/rad] and damping [N·m·s/rad] seen from the load shaft, the free
# travel backwards and forwards [rad], motor inertia [kg·m²] and friction [N·m·s] on the
# motor shaft, 1 where the speed loop measures the motor (feedback = "motor"). A compliant
# drive's node gets N_RATIO 0: its torque comes through ``loop.transmission``.
DI_TSTATE = DI_COLS
DI_COLS = DI_COLS + 1
(D_KTRANS, D_CTRANS, D_GAPNEG, D_GAPPOS, D_JMOTOR, D_BMOTOR,
 D_FEEDBACK) = range(D_COLS, D_COLS + 7)
D_COLS = D_COLS + 7

# dancers (docs/branching.md, "Dancers"): the offsets row's entries O_DANCER, the first
# dancer state (carriage position y [m] and speed [m/s] per dancer), and O_DANCER_END after
# the last; span table (int):
# the dancer state at the span's end a / end b (-1: a fixed roller), the other span of the
# dancer at end b (-1); span table (float): the span's strand gain g at end a / end b (it
# lengthens by g (y - y_set)); node table (float): the carriage's state (-1: no dancer) and
# parameters; held inputs: at their end, the load [N] per dancer (DIST_DANCER_LOAD rows);
# cells (int): a third column, the dancer node whose position the drive's loop reads (-1: a
# loadcell)
O_DANCER, O_DANCER_END = O_FRICTION + 1, O_FRICTION + 2
# 1 where the spans conserve web mass exactly (``web.transport``), 0: thesis 6.8 (E-6.6)
O_EXACT = O_DANCER_END + 3  # (after O_LAYER, O_LAYER_END below)
S_DANCEA, S_DANCEB, S_DOUT = S_COLS, S_COLS + 1, S_COLS + 2
S_COLS += 3
SF_GAINA, SF_GAINB = SF_COLS, SF_COLS + 1
SF_COLS += 2
(N_DSTATE, N_DINVM, N_DK, N_DC, N_DSET, N_DTRAVEL, N_DSTOP,
 N_DSTOPC) = range(N_COLS, N_COLS + 8)
N_COLS += 8
CELL_DANCER, CELL_COLS = 2, 3
DIST_DANCER_LOAD = DIST_NOISE + 1

# dancer as tension sensor or passive (docs/branching.md, "Dancers"): cells (int) a fourth
# column, 1 where the drive's loop reads its dancer as a tension sensor, T = (load - k (y -
# y_set)) / (g_in + g_out) (0: its position, or a loadcell); node table (float): the dancer's
# g_in + g_out [m/m]
CELL_SENSOR = CELL_COLS
CELL_COLS += 1
N_DGSUM = N_COLS
N_COLS += 1

# a stopped line's limits after a web break ([checks] and break limits, docs/branching.md
# "Web breaks", the chain's W7-W8): drive table (float) columns at its end, the same on every
# drive's row: 1 where the monitor watches the open-loop rolls for overspeed (a roll beyond
# its speed limiter's limit), the standstill fraction σ of the hold (an open-loop roll's
# torque on the tension side at most σ T_ref R / n); the monitor's method number of the
# chain (``sim.elements.layout.BREAK_OVERSPEED``)
D_BOVER, D_BSTALL = D_COLS, D_COLS + 1
D_COLS += 2
BREAK_OVERSPEED = 4

# section observer (docs/branching.md, "Section observer"; loop.observer): drive table (int)
# the observed span + 1 (0: none, the loadcell); drive table (float, fb): the gains l_T
# [N/rad], l_ω [1/s], the EA [N] and span length [m] it assumes, the wound-in tension [N] it
# assumes carried into an unwind's span; controller memory: its estimates T̂ [N], ω̂ [rad/s]
DI_OBS = DI_COLS
DI_COLS += 1
FB_OBS_LT, FB_OBS_LW, FB_OBS_EA, FB_OBS_LENGTH, FB_OBS_TIN = range(FB_COLS, FB_COLS + 5)
FB_COLS += 5
I_THAT, I_WHAT = I_COLS, I_COLS + 1
I_COLS += 2

# user controllers (docs/controllers.md, "On a branched line"; sim.branches.user): a drive of
# DI_FAMILY FAMILY_USER issues the command a Python controller wrote into its memory row
# (I_UCMD [N·m]) and stores what it measured there: surface speed [m/s], its zone's tension
# [N] (the sum of its loadcells; NaN without one), the radius it works with [m], the inertia
# at its roller [kg·m²], speed reference [m/s] and tension reference [N] (NaN without a zone);
# and the compensation its tick adds to the command [N·m] (NaN: the drive holds, W8), which
# a compiled law's command gets in the loop (loop.user.law_commands)
FAMILY_USER = FAMILY_MRAC + 1
(I_UCMD, I_USPEED, I_UTENSION, I_URADIUS, I_UINERTIA, I_UVREF,
 I_UTREF, I_UCOMP) = range(I_COLS, I_COLS + 8)
I_COLS += 8

# bonded laminates (docs/branching.md, (B2); sim.branches.laminates, loop.laminate):
# the offsets row's entries O_LAYER, the first layer state, and O_LAYER_END after the last.
# Every span of a web made of several raw webs (a laminate, its lanes) has law terms, one per
# raw web (layer), even where every layer is linear, and each term a state: the layer's
# stretch offset o [N] from the span's, its own stretch u = a s + o. Law terms (int) columns:
# the term's span; its offset state (absolute, -1: a span of one raw web, o = 0); the span
# upstream whose stretch it carries in; that span's term's offset state (-1: none); the
# layer's unstrained length in at its web's first span and out at its last (absolute states
# [m], -1: none). Law terms (float): the upstream term's scale a; the raw web's EA [N]; its
# stretch at its strength [N] (inf: none).
O_LAYER, O_LAYER_END = O_DANCER_END + 1, O_DANCER_END + 2
LI_SPAN, LI_STATE, LI_UP, LI_UPSTATE, LI_LIN, LI_LOUT = range(LI_COLS, LI_COLS + 6)
LI_COLS += 6
LF_UPSCALE, LF_EA, LF_STRENGTH = range(LF_COLS, LF_COLS + 3)
LF_COLS += 3

# sensors (spec.sensors; docs/branching.md, "Sensors"): the offsets row's entry O_SENSORS, 1
# where a sensor is other than ideal (the loop reads the columns only then, so a line without
# sensors compiles and runs as before); span table (float): the gain [-] and offset [N] of
# the loadcell on the span (1, 0: ideal or none), its reading gain T + offset; drive table
# (float): its encoder's scale [-] (1: ideal), the delay of its zone's loadcells' reading
# and of its encoder's, in whole controller samples (at most MAX_DELAY); controller memory:
# their ring buffers, the last DELAY_SLOTS readings of the zone's loadcells (their sum) [N]
# and of the encoder [m/s] (``sim.elements.sensor_loop.delayed``, as the chain's)
O_SENSORS = O_EXACT + 1
SF_TGAIN, SF_TOFFSET = SF_COLS, SF_COLS + 1
SF_COLS += 2
# span table (float): 1 / length [1/m], so that the plant multiplies where it would divide
# each RK4 stage (as the chain's S_INVLENGTH; issue 33, the general loop's cost per tick)
SF_INVLENGTH = SF_COLS
SF_COLS += 1
D_VSCALE, D_TDELAY, D_VDELAY = D_COLS, D_COLS + 1, D_COLS + 2
D_COLS += 3
I_TBUF = I_COLS
I_VBUF = I_TBUF + DELAY_SLOTS
I_COLS = I_VBUF + DELAY_SLOTS
