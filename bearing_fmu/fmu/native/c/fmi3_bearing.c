/* The FMI 3.0 layer of the native bearing FMU (Model Exchange and Co-Simulation in one binary),
 * over the model layer (bearing_values.h) and the internal compiled beside it, as the FMI 2.0
 * layer (fmi2_*.c) is: the same variables and value references, the same checks, evaluation,
 * derivatives and words (the model layer's code), the same statuses (docs/fmu.md, "FMI
 * status"): a parameter refused alone or together, an unknown value reference, a call out of the
 * calling sequence -> fmi3Error; a state the internal refuses -> fmi3Discard with the reason
 * (logged once), the outputs kept; a force asked at omega = 0 with no squeeze -> fmi3Warning.
 *
 * What FMI 3.0 changes:
 *   - the variables are Float64, Boolean, String and Enumeration (fmi3GetInt64/fmi3SetInt64),
 *     and time is the independent variable (value reference BN3_VR_TIME, fmi3GetFloat64 only);
 *   - errors reach the logger even with logging off (FMI 3.0.2, section 2.3.1), warnings and
 *     discards as their log category is on (fmi3SetDebugLogging);
 *   - a refused doStep (fmi3_modes.c) leaves the instance as before the call, with
 *     terminateSimulation false: the importer may restore a state and go on;
 *   - adjoint derivatives beside the directional ones (fmi3_derivatives.c).
 * After an fmi3Error the instance stays usable (the standard lets the importer only reset or
 * free it then; both work).
 *
 * This file: logging, instances, modes, values. fmi3_state.c: FMU states; fmi3_derivatives.c:
 * the derivatives; fmi3_modes.c: the calling sequence, Model Exchange, Co-Simulation and what
 * this FMU does not provide. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_layer.h"

static const char *const STATUS_NAMES[] = {"ok", "warning", "discard", "error", "fatal"};
static const char *const CATEGORIES[] = {"logStatusOK", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                         "logStatusFatal"};
#define FIRST_CATEGORY 1 /* the categories declared: warning, discard, error (modelDescription.xml) */
#define LAST_CATEGORY 3

/* ------------------------------------------------------------------------------ logging */

static void echo(Instance *m, bn_status status, const char *text) {
    /* logging off: the first warning, discard and error of this instance to stderr */
    int bit = 1 << (int)status;
    if (status == fmi3OK || (m->echoed & bit)) return;
    int first = m->echoed == 0;
    m->echoed |= bit;
    fprintf(stderr, "bearing FMU '%s' [%s]: %s\n", m->name, STATUS_NAMES[status], text);
    if (first)
        fprintf(stderr, "  (logging is off, so this FMU instance prints its first warning, discard and error "
                        "here; instantiate it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to "
                        "receive every message)\n");
    fflush(stderr);
}

void bn_log(Instance *m, bn_status status, const char *fmt, ...) {
    char text[2048], out[4096];
    va_list ap;
    if (m->mute) return;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    /* '#' starts a variable reference (#<value reference>#) in an FMI 3.0 message: doubled */
    size_t k = 0;
    for (const char *p = text; *p && k + 2 < sizeof out; p++) {
        if (*p == '#') out[k++] = '#';
        out[k++] = *p;
    }
    out[k] = 0;
    int on = m->logging_on && !(m->log_off & (1u << status));
    if (m->log_message && (on || status >= fmi3Error))
        m->log_message(m->env, (fmi3Status)status, CATEGORIES[status], out);
    else if (!m->logging_on)
        echo(m, status, text);
}

fmi3Status bn3_fail(Instance *m, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    bn_log(m, fmi3Error, "%s", text);
    return fmi3Error;
}

/* ------------------------------------------------------------------------------ instances */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SetDebugLogging, BN_ANY_TYPE);
    if (nCategories == 0) { /* every category */
        m->logging_on = loggingOn != 0;
        m->log_off = 0;
        return fmi3OK;
    }
    for (size_t i = 0; i < nCategories; i++) {
        int c = FIRST_CATEGORY;
        while (c <= LAST_CATEGORY && !(categories[i] && strcmp(categories[i], CATEGORIES[c]) == 0)) c++;
        if (c > LAST_CATEGORY)
            return bn3_fail(m, "fmi3SetDebugLogging: unknown log category '%s'; this FMU has logStatusWarning, "
                            "logStatusDiscard and logStatusError", categories[i] ? categories[i] : "(null)");
    }
    if (loggingOn && !m->logging_on) { /* from none: only the categories named */
        m->logging_on = 1;
        m->log_off = ~0u;
    }
    for (size_t i = 0; i < nCategories; i++)
        for (int c = FIRST_CATEGORY; c <= LAST_CATEGORY; c++)
            if (strcmp(categories[i], CATEGORIES[c]) == 0) {
                if (loggingOn)
                    m->log_off &= ~(1u << c);
                else
                    m->log_off |= 1u << c;
            }
    return fmi3OK;
}

static void fmi3_starts(Instance *m) {
    bn_set_starts(m);
    m->stop_time = INFINITY;
}

/* no instance: the reason to the logger given, else to stderr (there is no instance to keep it) */
static fmi3Instance refuse_instance(const char *name, fmi3InstanceEnvironment env, fmi3LogMessageCallback log,
                                    const char *text) {
    if (log)
        log(env, fmi3Error, "logStatusError", text);
    else
        fprintf(stderr, "bearing FMU '%s' [error]: %s\n", name, text);
    return NULL;
}

static fmi3Instance instantiate(const char *call, fmi3String instanceName, fmi3String token, fmi3Boolean loggingOn,
                                fmi3InstanceEnvironment env, fmi3LogMessageCallback log, int model_exchange) {
    const char *name = instanceName ? instanceName : "";
    char text[400];
    if (!token || strcmp(token, BN3_TOKEN) != 0) {
        snprintf(text, sizeof text, "%s: the instantiationToken given is not this FMU's (" BN3_TOKEN "): the "
                 "binary and modelDescription.xml come from different builds", call);
        return refuse_instance(name, env, log, text);
    }
    Instance *m = calloc(1, sizeof(Instance));
    if (!m) return refuse_instance(name, env, log, "out of memory");
    m->model_exchange = model_exchange;
    m->env = env;
    m->log_message = log;
    m->logging_on = loggingOn != 0;
    snprintf(m->name, sizeof m->name, "%s", name);
    fmi3_starts(m);
    m->mode = MODE_INSTANTIATED;
    bn_live_add(m);
    return m;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)resourcePath; /* the data are compiled in */
    (void)visible;
    return instantiate("fmi3InstantiateModelExchange", instanceName, instantiationToken, loggingOn,
                       instanceEnvironment, logMessage, 1);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate) {
    (void)resourcePath;
    (void)visible;
    (void)earlyReturnAllowed; /* doStep never returns early */
    (void)requiredIntermediateVariables;
    (void)intermediateUpdate;
    const char *name = instanceName ? instanceName : "";
    if (eventModeUsed)
        return refuse_instance(name, instanceEnvironment, logMessage, "fmi3InstantiateCoSimulation: eventModeUsed "
                               "is true, but this FMU has no Event Mode in Co-Simulation (hasEventMode is false)");
    if (nRequiredIntermediateVariables > 0)
        return refuse_instance(name, instanceEnvironment, logMessage, "fmi3InstantiateCoSimulation: "
                               "requiredIntermediateVariables given, but no variable of this FMU has "
                               "intermediateUpdate (doStep has no intermediate updates)");
    return instantiate("fmi3InstantiateCoSimulation", instanceName, instantiationToken, loggingOn,
                       instanceEnvironment, logMessage, 0);
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    return refuse_instance(instanceName ? instanceName : "", instanceEnvironment, logMessage,
                           "fmi3InstantiateScheduledExecution: this FMU has Model Exchange and Co-Simulation, no "
                           "Scheduled Execution");
}

void fmi3FreeInstance(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return;
    if (!bn_live_remove(m)) { /* freed already (or never ours): its memory is not touched */
        fprintf(stderr, "bearing FMU: fmi3FreeInstance(%p): not a live instance of this FMU (freed already?); "
                        "nothing done\n", instance);
        fflush(stderr);
        return;
    }
    bn_release(m); /* what the internal allocated (reynolds: the solver's memory) */
    free(m);
}

/* ------------------------------------------------------------------------------ modes */

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    Instance *m = instance;
    char a[32], b[32];
    (void)toleranceDefined; /* no integrator inside */
    (void)tolerance;
    if (!m) return fmi3Error;
    ORDER3(EnterInitializationMode, BN_ANY_TYPE);
    if (!isfinite(startTime))
        return bn3_fail(m, "fmi3EnterInitializationMode: startTime = %s s must be finite",
                        bn_num(a, 32, startTime, 17));
    if (stopTimeDefined && !(startTime <= stopTime && stopTime < INFINITY))
        return bn3_fail(m, "fmi3EnterInitializationMode: stopTime = %s s must be finite and >= startTime = %s s",
                        bn_num(a, 32, stopTime, 17), bn_num(b, 32, startTime, 17));
    m->t = startTime;
    m->stop_time = stopTimeDefined ? stopTime : INFINITY;
    m->mode = MODE_INIT;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(ExitInitializationMode, BN_ANY_TYPE);
    if (bn_prepare(m)) return bn3_fail(m, "fmi3ExitInitializationMode: %s", m->init_error);
    m->initialized = 1;
    bn_show_choices(m);
    /* outputs at the start time from the initial inputs when they can be evaluated (still in
     * Initialization Mode: T_eff quasi-static, Model Exchange's state starts there): a master
     * may set the inputs only before the first step, so a refused state is no initialisation error */
    int refused = bn_evaluate(m);
    m->mode = m->model_exchange ? MODE_EVENT : MODE_STEP;
    if (refused) { /* logged; the initialisation itself succeeded */
        bn_log(m, fmi3Warning, "outputs at the start time left at their start values: %s", m->msg);
        m->dirty = 1;
        return fmi3OK;
    }
    return bn_warned(m);
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(Terminate, BN_ANY_TYPE);
    m->mode = MODE_TERMINATED;
    bn_log_excursions(m);
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(Reset, BN_ANY_TYPE);
    fmi3_starts(m);
    m->mode = MODE_INSTANTIATED;
    return fmi3OK;
}

/* ------------------------------------------------------------------------------ getting values */

fmi3Status bn3_outputs(Instance *m, const char *call, const char *name) {
    if (m->mode == MODE_INSTANTIATED)
        return bn3_fail(m, "%s %s in Instantiated: an output has no value before Initialization Mode (initial = "
                        "calculated)", call, name);
    return bn_outputs(m, call, name);
}

static fmi3Status counts_differ(Instance *m, const char *call, size_t nvr, size_t nValues) {
    return bn3_fail(m, "%s: %lu value references but nValues = %lu (every variable of this FMU is a scalar)", call,
                    (unsigned long)nvr, (unsigned long)nValues);
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 values[],
                          size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetFloat64, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3GetFloat64", nvr, nValues);
    fmi3Status status = fmi3OK;
    int computed = 0;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] == BN3_VR_TIME) {
            values[i] = m->t;
            continue;
        }
        if (vr[i] >= (fmi3ValueReference)N_REAL)
            return bn3_fail(m, "fmi3GetFloat64: value reference %u is not a Float64 variable of this FMU", vr[i]);
        if (bn_is_output_real((int)vr[i]) && !computed) {
            computed = 1;
            fmi3Status s = bn3_outputs(m, "fmi3GetFloat64", bn_real_name((int)vr[i]));
            if (s == fmi3Error) return s;
            if (s > status) status = s;
        }
        values[i] = m->r[vr[i]];
    }
    return status;
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 values[],
                        size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetInt64, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3GetInt64", nvr, nValues);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_INT0 || vr[i] >= VR_INT_PARAM0 + N_INT)
            return bn3_fail(m, "fmi3GetInt64: value reference %u is not an Int64 or Enumeration variable of this FMU",
                            vr[i]);
        values[i] = vr[i] >= VR_INT_PARAM0 ? m->n[vr[i] - VR_INT_PARAM0] : m->e[vr[i] - VR_INT0];
    }
    return fmi3OK;
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Boolean values[],
                          size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetBoolean, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3GetBoolean", nvr, nValues);
    fmi3Status status = fmi3OK;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_BOOL0 || vr[i] >= VR_BOOL0 + N_BOOL)
            return bn3_fail(m, "fmi3GetBoolean: value reference %u is not a Boolean variable of this FMU", vr[i]);
        int k = (int)(vr[i] - VR_BOOL0);
        if (k == B_OUT_OF_DOMAIN) { /* a discrete output: in Continuous-Time Mode, the value of the last event */
            fmi3Status s = bn3_outputs(m, "fmi3GetBoolean", "out_of_domain");
            if (s == fmi3Error) return s;
            if (s > status) status = s;
        }
        values[i] = m->b[k] ? true : false;
    }
    return status;
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3String values[],
                         size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetString, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3GetString", nvr, nValues);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING)
            return bn3_fail(m, "fmi3GetString: value reference %u is not a String variable of this FMU", vr[i]);
        values[i] = m->s[vr[i] - VR_STRING0];
    }
    return fmi3OK;
}

/* ------------------------------------------------------------------------------ setting values */

/* a parameter after initialisation (variability fixed): refused (1, logged), else 0 */
static int parameter_fixed(Instance *m, const char *call, const char *name, const char *keeps) {
    if (m->mode == MODE_INSTANTIATED || m->mode == MODE_INIT) return 0;
    bn3_fail(m, "%s: parameter %s is fixed after initialisation (variability fixed); it keeps %s", call, name, keeps);
    return 1;
}

/* a parameter refused alone: remembered, so that fmi3ExitInitializationMode fails until a valid one is set */
static fmi3Status refuse_parameter(Instance *m, int slot, const char *call, const char *why, const char *name,
                                   const char *keeps) {
    m->refused[slot] = 1;
    snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
    return bn3_fail(m, "%s: %s; %s keeps %s", call, why, name, keeps);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 values[], size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SetFloat64, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3SetFloat64", nvr, nValues);
    fmi3Status status = fmi3OK;
    char a[32], why[512];
    for (size_t i = 0; i < nvr; i++) {
        fmi3ValueReference k = vr[i];
        if (BN_IS_INPUT(k)) { /* inputs: any value; a non-finite one is refused when evaluated */
            m->r[k] = values[i];
            m->dirty = 1;
            m->step_refused = 0;
            continue;
        }
        if (k == BN3_VR_TIME) {
            status = bn3_fail(m, "fmi3SetFloat64: time is the independent variable: fmi3EnterInitializationMode, "
                              "fmi3SetTime (Model Exchange) and fmi3DoStep (Co-Simulation) set it");
            continue;
        }
        if (k >= (fmi3ValueReference)N_REAL) {
            status = bn3_fail(m, "fmi3SetFloat64: value reference %u is not a Float64 variable of this FMU", k);
            continue;
        }
        if (bn_is_output_real((int)k)) {
            status = bn3_fail(m, "fmi3SetFloat64: %s is an output and cannot be set", bn_real_name((int)k));
            continue;
        }
        bn_num(a, sizeof a, m->r[k], 17);
        if (parameter_fixed(m, "fmi3SetFloat64", bn_real_name((int)k), a)) {
            status = fmi3Error;
            continue;
        }
        if (bn_check_real((int)k, values[i], why, sizeof why)) {
            status = refuse_parameter(m, (int)k, "fmi3SetFloat64", why, bn_real_name((int)k), a);
            continue;
        }
        m->refused[k] = 0;
        m->r[k] = values[i];
    }
    return status;
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int64 values[],
                        size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SetInt64, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3SetInt64", nvr, nValues);
    fmi3Status status = fmi3OK;
    char why[512], keeps[32];
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_INT0 || vr[i] >= VR_INT_PARAM0 + N_INT) {
            status = bn3_fail(m, "fmi3SetInt64: value reference %u is not an Int64 or Enumeration variable of this FMU",
                              vr[i]);
            continue;
        }
        if (vr[i] >= VR_INT_PARAM0) { /* groove_count, lobes: the bore, checked against the data's at initialisation */
            int k = (int)(vr[i] - VR_INT_PARAM0);
            snprintf(keeps, sizeof keeps, "%d", m->n[k]);
            if (parameter_fixed(m, "fmi3SetInt64", bn_int_name(k), keeps))
                status = fmi3Error;
            else if (bn_set_int(m, k, (long long)values[i], why, sizeof why))
                status = bn3_fail(m, "fmi3SetInt64: %s; %s keeps %s", why, bn_int_name(k), keeps);
            continue;
        }
        int j = (int)(vr[i] - VR_INT0), slot = N_REAL + N_BOOL + N_STRING + j;
        snprintf(keeps, sizeof keeps, "%d", m->e[j]);
        if (parameter_fixed(m, "fmi3SetInt64", bn_enum_name(j), keeps)) {
            status = fmi3Error;
            continue;
        }
        /* the enumerations' values are small: one outside int is refused as any other unknown value */
        int v = values[i] > 1000000 || values[i] < -1000000 ? -1000001 : (int)values[i];
        if (bn_check_enum(j, v, why, sizeof why)) {
            status = refuse_parameter(m, slot, "fmi3SetInt64", why, bn_enum_name(j), keeps);
            continue;
        }
        m->refused[slot] = 0;
        m->e[j] = v;
    }
    return status;
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Boolean values[], size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SetBoolean, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3SetBoolean", nvr, nValues);
    fmi3Status status = fmi3OK;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_BOOL0 || vr[i] >= VR_BOOL0 + N_BOOL) {
            status = bn3_fail(m, "fmi3SetBoolean: value reference %u is not a Boolean variable of this FMU", vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_BOOL0);
        if (k == B_OUT_OF_DOMAIN) {
            status = bn3_fail(m, "fmi3SetBoolean: out_of_domain is an output and cannot be set");
            continue;
        }
        if (parameter_fixed(m, "fmi3SetBoolean", BN_BOOL_NAMES[k], m->b[k] ? "true" : "false")) {
            status = fmi3Error;
            continue;
        }
        m->b[k] = values[i] ? 1 : 0;
    }
    return status;
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3String values[],
                         size_t nValues) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(SetString, BN_ANY_TYPE);
    if (nValues != nvr) return counts_differ(m, "fmi3SetString", nvr, nValues);
    fmi3Status status = fmi3OK;
    char why[512], out[STRING_MAX], keeps[STRING_MAX + 2];
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING) {
            status = bn3_fail(m, "fmi3SetString: value reference %u is not a String variable of this FMU", vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_STRING0), slot = N_REAL + N_BOOL + k;
        snprintf(keeps, sizeof keeps, "'%s'", m->s[k]);
        if (parameter_fixed(m, "fmi3SetString", bn_string_name(k), keeps)) {
            status = fmi3Error;
            continue;
        }
        if (bn_check_string(k, values[i] ? values[i] : "", out, why, sizeof why)) {
            status = refuse_parameter(m, slot, "fmi3SetString", why, bn_string_name(k), keeps);
            continue;
        }
        m->refused[slot] = 0;
        snprintf(m->s[k], STRING_MAX, "%s", out);
    }
    return status;
}
