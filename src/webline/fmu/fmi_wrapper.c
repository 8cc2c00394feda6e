/* webline FMU: an FMI 2.0 / 3.0 co-simulation wrapper around webline's general loop
 * (webline_loop, compiled from sim/branches/loop/kernel.py: see webline/fmu/loop_object.py).
 * "model.h" is generated per line by webline.fmu.c_model: the line's tables and start state,
 * the variables and the communication step. Build: cc -shared -fPIC -DFMI_VERSION=2|3. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

int32_t webline_loop(int64_t *status, void **excinfo, double **arrays, int64_t *prof_off,
                     int64_t tick0, int64_t n_ticks, int64_t record_every, int64_t include_end,
                     double *out);

enum { OP_COPY, OP_CLIP0, OP_MUL, OP_LE0, OP_SAT, OP_GE0, OP_STATUS, OP_PARAM, OP_INPUT, OP_TIME, OP_LIVE };
enum { T_REAL, T_BOOL, T_INT };
enum { MODE_INSTANTIATED, MODE_INIT, MODE_STEP, MODE_TERMINATED, MODE_ERROR };

typedef struct {
    double *store;               /* live tables (N_FLOATS), then the peek's copy (N_FLOATS) */
    double *live[N_ARRAYS], *peek[N_ARRAYS];
    int64_t prof_off[N_PROF_OFF];
    int64_t tick;
    int64_t status;              /* the loop's STATUS_* (0: running) */
    double inputs[N_VARS];
    int mode;
    char name[128];
    void *env;
    void *logger;
} Model;

static void say(Model *m, int status, const char *fmt, ...);
static int refresh(Model *m);

static void reset_model(Model *m) {
    memcpy(m->store, START, sizeof(double) * N_FLOATS);
    memcpy(m->prof_off, PROF_OFF, sizeof(PROF_OFF));
    for (int v = 0; v < N_VARS; v++) m->inputs[v] = VAR_START[v];
    m->tick = 0;
    m->status = 0;
    m->mode = MODE_INSTANTIATED;
    refresh(m);  /* the outputs at t = 0, readable before initialization ends */
}

static Model *new_model(const char *name, void *env, void *logger) {
    Model *m = calloc(1, sizeof(Model));
    if (!m) return NULL;
    m->store = malloc(sizeof(double) * 2 * (N_FLOATS > 0 ? N_FLOATS : 1));
    if (!m->store) { free(m); return NULL; }
    for (int a = 0; a < N_ARRAYS; a++) {
        m->live[a] = m->store + ARRAY_AT[a];
        m->peek[a] = m->store + N_FLOATS + ARRAY_AT[a];
    }
    snprintf(m->name, sizeof m->name, "%s", name ? name : MODEL_NAME);
    m->env = env;
    m->logger = logger;
    reset_model(m);
    return m;
}

/* The outputs at the current tick: the tick's events and controller step run on a copy of the
 * tables (the step that follows redoes them on the live ones, with the inputs set by then). */
static int refresh(Model *m) {
    int64_t status = 0;
    void *exc = NULL;
    double out[2];
    memcpy(m->store + N_FLOATS, m->store, sizeof(double) * N_FLOATS);
    if (webline_loop(&status, &exc, m->peek, m->prof_off, m->tick, 0, 1, 1, out) != 0) return -1;
    return 0;
}

static double value_of(Model *m, int v) {
    const double *s = m->store + N_FLOATS;
    int64_t a = VAR_A[v], b = VAR_B[v];
    switch (VAR_OP[v]) {
    case OP_COPY: return s[a];
    case OP_CLIP0: return s[a] > 0.0 ? s[a] : 0.0;
    case OP_MUL: return s[a] * s[b];
    case OP_LE0: return s[a] <= 0.0 ? 1.0 : 0.0;
    case OP_SAT: return fabs(s[a]) >= s[b] * (1.0 - 1e-12) ? 1.0 : 0.0;
    case OP_GE0: return s[a] >= 0.0 ? 1.0 : 0.0;
    case OP_STATUS: return (double)m->status;
    case OP_PARAM: case OP_LIVE: return m->store[a];
    case OP_INPUT: return m->inputs[v];
    case OP_TIME: return (double)m->tick * DT;
    }
    return NAN;
}

/* 0: set; 1: not settable now; 2: unknown reference; 3: out of range */
static int set_value(Model *m, int v, double value) {
    if (v < 0 || v >= N_VARS) return 2;
    if (VAR_OP[v] == OP_PARAM) {
        if (m->mode != MODE_INSTANTIATED && m->mode != MODE_INIT) return 1;
        if (!(value >= 0.0) || (VAR_B[v] >= 0 && value == 0.0)) return 3;  /* (min, 1/0) */
        m->store[VAR_A[v]] = value;
        if (VAR_B[v] >= 0) m->store[VAR_B[v]] = 1.0 / value;  /* its reciprocal (1/EA, 1/J) */
        return 0;
    }
    if (VAR_OP[v] == OP_LIVE) {  /* a torque command (plant only): held from now on */
        if (m->mode == MODE_TERMINATED || m->mode == MODE_ERROR) return 1;
        m->store[VAR_A[v]] = value;
        return 0;
    }
    if (VAR_OP[v] == OP_INPUT) {  /* hold the profile's value from now on */
        int64_t p = VAR_A[v];
        double *prof_v = m->live[PROF_V_ARRAY];
        for (int64_t k = m->prof_off[p]; k < m->prof_off[p + 1]; k++) prof_v[k] = value;
        m->inputs[v] = value;
        return 0;
    }
    return 1;
}

/* 0 when each of the n value references names a variable of `type`, else 3 (fmiXError) */
static int refs_of_type(const uint32_t vr[], size_t n, int type) {
    for (size_t k = 0; k < n; k++)
        if (vr[k] >= N_VARS || VAR_TYPE[vr[k]] != type) return 3;
    return 0;
}

/* Set n Real variables: 0, or 3 (fmiXError) with the first refusal said to the logger as
 * `fn` (fmi2SetReal, fmi3SetFloat64) names it */
static int set_reals(Model *m, const char *fn, const uint32_t vr[], size_t n,
                     const double value[]) {
    for (size_t k = 0; k < n; k++) {
        int why = vr[k] >= N_VARS || VAR_TYPE[vr[k]] != T_REAL ? 2 : set_value(m, vr[k], value[k]);
        if (why) {
            say(m, 3, "%s: value reference %u %s (%g)", fn, vr[k], why == 3 ? "out of its range"
                : why == 2 ? "is no Real variable" : "cannot be set now", value[k]);
            return 3;
        }
    }
    return 0;
}

static int do_step(Model *m, double t, double h) {
    int64_t n = llround(h / DT), status = 0;
    void *exc = NULL;
    double out[2];
    if (m->mode != MODE_STEP) { say(m, 3, "doStep: not in step mode"); return 3; }
    if (n < 1 || fabs((double)n * DT - h) > 1e-9 * DT) {
        say(m, 3, "doStep: the step %g s is not a whole number of controller periods (%g s)",
            h, DT);
        return 3;
    }
    if (fabs(t - (double)m->tick * DT) > 1e-6 * DT)
        say(m, 1, "doStep: t = %.17g s, the FMU is at %.17g s", t, (double)m->tick * DT);
    if (webline_loop(&status, &exc, m->live, m->prof_off, m->tick, n, INT64_MAX, 0, out) != 0)
        status = -1;
    m->tick += n;
    m->status = status;
    if (status != 0) {
        m->mode = MODE_ERROR;
        say(m, 3, "the run stopped at t = %.6g s (webline status %lld: %s)", out[1],
            (long long)status, status == 1 ? "the state stopped being finite" :
            status == 2 ? "an unwind roll ran out of web" :
            status == 3 ? "a runaway" : status == 4 ? "a web beyond its strength" : "error");
        return 3;
    }
    refresh(m);
    return 0;
}

static int start_step_mode(Model *m) {
    m->mode = MODE_STEP;
    return refresh(m) == 0 ? 0 : 3;
}

#if FMI_VERSION == 2
/* ------------------------------------------------------------------ FMI 2.0 co-simulation */
typedef void *fmi2Component;
typedef void *fmi2ComponentEnvironment;
typedef void *fmi2FMUstate;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Integer;
typedef int fmi2Boolean;
typedef char fmi2Char;
typedef const fmi2Char *fmi2String;
typedef int fmi2Status;
typedef void (*fmi2Logger)(fmi2ComponentEnvironment, fmi2String, fmi2Status, fmi2String,
                           fmi2String, ...);
typedef struct {
    fmi2Logger logger;
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(fmi2ComponentEnvironment, fmi2Status);
    fmi2ComponentEnvironment componentEnvironment;
} fmi2CallbackFunctions;
#define EXPORT __attribute__((visibility("default")))

static void say(Model *m, int status, const char *fmt, ...) {
    char text[512];
    va_list args;
    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    if (m->logger) ((fmi2Logger)m->logger)(m->env, m->name, status, "logStatusError", "%s", text);
}

EXPORT const char *fmi2GetTypesPlatform(void) { return "default"; }
EXPORT const char *fmi2GetVersion(void) { return "2.0"; }
EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                                      const fmi2String cats[]) { return 0; }

EXPORT fmi2Component fmi2Instantiate(fmi2String name, int type, fmi2String guid,
                                     fmi2String location, const fmi2CallbackFunctions *cb,
                                     fmi2Boolean visible, fmi2Boolean logging) {
    if (type != 1 || (guid && strcmp(guid, GUID) != 0)) {
        if (cb && cb->logger)
            cb->logger(cb->componentEnvironment, name, 3, "logStatusError",
                       "this FMU is co-simulation only, GUID %s", GUID);
        return NULL;
    }
    return new_model(name, cb ? cb->componentEnvironment : NULL, cb ? (void *)cb->logger : NULL);
}

EXPORT void fmi2FreeInstance(fmi2Component c) {
    Model *m = c;
    if (m) { free(m->store); free(m); }
}

EXPORT fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean tol_on, fmi2Real tol,
                                      fmi2Real start, fmi2Boolean stop_on, fmi2Real stop) {
    if (start != 0.0) { say(c, 3, "the FMU starts at t = 0 (its start state)"); return 3; }
    return 0;
}
EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    ((Model *)c)->mode = MODE_INIT;
    return 0;
}
EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component c) { return start_step_mode(c); }
EXPORT fmi2Status fmi2Terminate(fmi2Component c) {
    ((Model *)c)->mode = MODE_TERMINATED;
    return 0;
}
EXPORT fmi2Status fmi2Reset(fmi2Component c) {
    reset_model(c);
    return 0;
}

EXPORT fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              fmi2Real value[]) {
    if (refs_of_type(vr, n, T_REAL)) return 3;
    for (size_t k = 0; k < n; k++) value[k] = value_of(c, vr[k]);
    return 0;
}
EXPORT fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                 fmi2Integer value[]) {
    if (refs_of_type(vr, n, T_INT)) return 3;
    for (size_t k = 0; k < n; k++) value[k] = (fmi2Integer)value_of(c, vr[k]);
    return 0;
}
EXPORT fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                 fmi2Boolean value[]) {
    if (refs_of_type(vr, n, T_BOOL)) return 3;
    for (size_t k = 0; k < n; k++) value[k] = value_of(c, vr[k]) != 0.0;
    return 0;
}
EXPORT fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                fmi2String value[]) { return n ? 3 : 0; }
EXPORT fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                              const fmi2Real value[]) {
    return set_reals(c, "fmi2SetReal", vr, n, value);
}
EXPORT fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                 const fmi2Integer value[]) { return n ? 3 : 0; }
EXPORT fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                 const fmi2Boolean value[]) { return n ? 3 : 0; }
EXPORT fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                                const fmi2String value[]) { return n ? 3 : 0; }

EXPORT fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean discard) {
    return do_step(c, t, h);
}
EXPORT fmi2Status fmi2CancelStep(fmi2Component c) { return 3; }
EXPORT fmi2Status fmi2GetStatus(fmi2Component c, int kind, fmi2Status *value) { return 3; }
EXPORT fmi2Status fmi2GetRealStatus(fmi2Component c, int kind, fmi2Real *value) {
    if (kind == 2) { *value = (double)((Model *)c)->tick * DT; return 0; }  /* fmi2LastSuccessfulTime */
    return 3;
}
EXPORT fmi2Status fmi2GetIntegerStatus(fmi2Component c, int kind, fmi2Integer *value) { return 3; }
EXPORT fmi2Status fmi2GetBooleanStatus(fmi2Component c, int kind, fmi2Boolean *value) { return 3; }
EXPORT fmi2Status fmi2GetStringStatus(fmi2Component c, int kind, fmi2String *value) { return 3; }

/* Not supported (canGetAndSetFMUstate, providesDirectionalDerivative, canInterpolateInputs
 * are false in modelDescription.xml): they answer fmi2Error. */
EXPORT fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { return 3; }
EXPORT fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { return 3; }
EXPORT fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { return 3; }
EXPORT fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *n) { return 3; }
EXPORT fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, char b[], size_t n) { return 3; }
EXPORT fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const char b[], size_t n,
                                          fmi2FMUstate *s) { return 3; }
EXPORT fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[],
                                               size_t nu, const fmi2ValueReference z[], size_t nz,
                                               const fmi2Real du[], fmi2Real dz[]) { return 3; }
EXPORT fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                              size_t n, const fmi2Integer order[],
                                              const fmi2Real value[]) { return 3; }
EXPORT fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                               size_t n, const fmi2Integer order[],
                                               fmi2Real value[]) { return 3; }

#else
/* ------------------------------------------------------------------ FMI 3.0 co-simulation */
#include <stdbool.h>
typedef void *fmi3Instance;
typedef void *fmi3InstanceEnvironment;
typedef uint32_t fmi3ValueReference;
typedef double fmi3Float64;
typedef int32_t fmi3Int32;
typedef bool fmi3Boolean;
typedef const char *fmi3String;
typedef int fmi3Status;
typedef void (*fmi3LogMessageCallback)(fmi3InstanceEnvironment, fmi3Status, fmi3String,
                                       fmi3String);
#define EXPORT __attribute__((visibility("default")))

static void say(Model *m, int status, const char *fmt, ...) {
    char text[512];
    va_list args;
    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    if (m->logger) ((fmi3LogMessageCallback)m->logger)(m->env, status, "logStatusError", text);
}

EXPORT const char *fmi3GetVersion(void) { return "3.0"; }
EXPORT fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n,
                                      const fmi3String cats[]) { return 0; }

EXPORT fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String name, fmi3String token, fmi3String location, fmi3Boolean visible,
    fmi3Boolean logging, fmi3Boolean event_mode, fmi3Boolean early_return,
    const fmi3ValueReference required[], size_t n_required, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback log, void *intermediate) {
    if (token && strcmp(token, GUID) != 0) {
        if (log) log(env, 3, "logStatusError", "instantiationToken does not match " GUID);
        return NULL;
    }
    if (event_mode) {
        if (log) log(env, 3, "logStatusError", "this FMU has no event mode");
        return NULL;
    }
    return new_model(name, env, (void *)log);
}

EXPORT void fmi3FreeInstance(fmi3Instance c) {
    Model *m = c;
    if (m) { free(m->store); free(m); }
}

EXPORT fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean tol_on, fmi3Float64 tol,
                                              fmi3Float64 start, fmi3Boolean stop_on,
                                              fmi3Float64 stop) {
    if (start != 0.0) { say(c, 3, "the FMU starts at t = 0 (its start state)"); return 3; }
    ((Model *)c)->mode = MODE_INIT;
    return 0;
}
EXPORT fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { return start_step_mode(c); }
EXPORT fmi3Status fmi3Terminate(fmi3Instance c) {
    ((Model *)c)->mode = MODE_TERMINATED;
    return 0;
}
EXPORT fmi3Status fmi3Reset(fmi3Instance c) {
    reset_model(c);
    return 0;
}

EXPORT fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                 fmi3Float64 value[], size_t nv) {
    if (refs_of_type(vr, n, T_REAL)) return 3;
    for (size_t k = 0; k < n; k++) value[k] = value_of(c, vr[k]);
    return 0;
}
EXPORT fmi3Status fmi3GetInt32(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                               fmi3Int32 value[], size_t nv) {
    if (refs_of_type(vr, n, T_INT)) return 3;
    for (size_t k = 0; k < n; k++) value[k] = (fmi3Int32)value_of(c, vr[k]);
    return 0;
}
EXPORT fmi3Status fmi3GetBoolean(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                 fmi3Boolean value[], size_t nv) {
    if (refs_of_type(vr, n, T_BOOL)) return 3;
    for (size_t k = 0; k < n; k++) value[k] = value_of(c, vr[k]) != 0.0;
    return 0;
}
EXPORT fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                                 const fmi3Float64 value[], size_t nv) {
    return set_reals(c, "fmi3SetFloat64", vr, n, value);
}

EXPORT fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean no_set,
                             fmi3Boolean *event, fmi3Boolean *terminate, fmi3Boolean *early,
                             fmi3Float64 *last) {
    int status = do_step(c, t, h);
    *event = false;
    *terminate = status != 0;
    *early = false;
    *last = (double)((Model *)c)->tick * DT;
    return status;
}

/* Everything else FMI 3.0 names answers fmi3Error: this FMU has no model exchange, scheduled
 * execution, event mode, FMU state, derivatives, clocks or other value types (its
 * modelDescription.xml says so). Declared without arguments: in the x86-64 C calling
 * convention a caller may pass any. */
#define UNSUPPORTED(name) EXPORT fmi3Status name() { return 3; }
UNSUPPORTED(fmi3InstantiateModelExchange)
UNSUPPORTED(fmi3InstantiateScheduledExecution)
UNSUPPORTED(fmi3EnterEventMode)
UNSUPPORTED(fmi3GetFloat32) UNSUPPORTED(fmi3GetInt8) UNSUPPORTED(fmi3GetUInt8)
UNSUPPORTED(fmi3GetInt16) UNSUPPORTED(fmi3GetUInt16) UNSUPPORTED(fmi3GetUInt32)
UNSUPPORTED(fmi3GetInt64) UNSUPPORTED(fmi3GetUInt64) UNSUPPORTED(fmi3GetString)
UNSUPPORTED(fmi3GetBinary) UNSUPPORTED(fmi3GetClock)
UNSUPPORTED(fmi3SetFloat32) UNSUPPORTED(fmi3SetInt8) UNSUPPORTED(fmi3SetUInt8)
UNSUPPORTED(fmi3SetInt16) UNSUPPORTED(fmi3SetUInt16) UNSUPPORTED(fmi3SetInt32)
UNSUPPORTED(fmi3SetUInt32) UNSUPPORTED(fmi3SetInt64) UNSUPPORTED(fmi3SetUInt64)
UNSUPPORTED(fmi3SetBoolean) UNSUPPORTED(fmi3SetString) UNSUPPORTED(fmi3SetBinary)
UNSUPPORTED(fmi3SetClock)
UNSUPPORTED(fmi3GetNumberOfVariableDependencies) UNSUPPORTED(fmi3GetVariableDependencies)
UNSUPPORTED(fmi3GetFMUState) UNSUPPORTED(fmi3SetFMUState) UNSUPPORTED(fmi3FreeFMUState)
UNSUPPORTED(fmi3SerializedFMUStateSize) UNSUPPORTED(fmi3SerializeFMUState)
UNSUPPORTED(fmi3DeserializeFMUState)
UNSUPPORTED(fmi3GetDirectionalDerivative) UNSUPPORTED(fmi3GetAdjointDerivative)
UNSUPPORTED(fmi3EnterConfigurationMode) UNSUPPORTED(fmi3ExitConfigurationMode)
UNSUPPORTED(fmi3GetIntervalDecimal) UNSUPPORTED(fmi3GetIntervalFraction)
UNSUPPORTED(fmi3GetShiftDecimal) UNSUPPORTED(fmi3GetShiftFraction)
UNSUPPORTED(fmi3SetIntervalDecimal) UNSUPPORTED(fmi3SetIntervalFraction)
UNSUPPORTED(fmi3SetShiftDecimal) UNSUPPORTED(fmi3SetShiftFraction)
UNSUPPORTED(fmi3EvaluateDiscreteStates) UNSUPPORTED(fmi3UpdateDiscreteStates)
UNSUPPORTED(fmi3EnterContinuousTimeMode) UNSUPPORTED(fmi3CompletedIntegratorStep)
UNSUPPORTED(fmi3SetTime) UNSUPPORTED(fmi3SetContinuousStates)
UNSUPPORTED(fmi3GetContinuousStateDerivatives) UNSUPPORTED(fmi3GetEventIndicators)
UNSUPPORTED(fmi3GetContinuousStates) UNSUPPORTED(fmi3GetNominalsOfContinuousStates)
UNSUPPORTED(fmi3GetNumberOfEventIndicators) UNSUPPORTED(fmi3GetNumberOfContinuousStates)
UNSUPPORTED(fmi3EnterStepMode) UNSUPPORTED(fmi3GetOutputDerivatives)
UNSUPPORTED(fmi3ActivateModelPartition)
#endif
