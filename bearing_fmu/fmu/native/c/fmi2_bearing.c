/* The FMI 2.0 layer of the native bearing FMU (Co-Simulation and Model Exchange in one binary).
 *
 * The journal state (y, z, vy, vz, omega) goes in, the film force and its tangent come out,
 * computed by the internal compiled beside this file (internal_<name>.c). It has no state of
 * its own apart from its inputs and outputs, so fmi2GetFMUstate is a copy of those.
 *
 * Statuses (docs/fmu.md, "FMI status"), as the Python FMU gives them:
 *   a parameter that can never be valid        -> that fmi2SetX: fmi2Error, value not stored, and
 *                                                 exitInitializationMode fails until a valid one is set
 *   parameters valid alone but not together     -> fmi2ExitInitializationMode: fmi2Error
 *   an unknown value reference, setting an output, a parameter after initialisation,
 *   a bad step size or time, doStep before initialisation, a foreign FMU state -> fmi2Error
 *   a state the internal refuses (non-finite input, the wall, far outside a surrogate's domain)
 *                                               -> doStep (CS) / getReal of an output (ME): fmi2Discard,
 *                                                 outputs keep their last values, logged with the reason
 *   a call out of the FMI 2.0 calling sequence, a non-finite time (setTime) or direction
 *   (getDirectionalDerivative)                  -> fmi2Error naming the call; nothing changes
 * The calling sequence is bearing_fmu/fmi_order.py's table, the Python FMU's too (fmi2_order.c).
 * After an error the instance stays usable. A second fmi2FreeInstance of the same instance is
 * recognised and does nothing (the model layer lists the live instances). With logging off, the
 * first warning, discard and error of each instance are printed to stderr, so a user of a master
 * without a logger still learns the first thing that went wrong.
 *
 * This file: logging, instances, modes, values; fmi2_modes.c: FMU states, derivatives,
 * Co-Simulation and Model Exchange; fmi2_order.c: the calling sequence. The variables, the
 * parameters' checks, the evaluation and its derivatives are the model layer's (bearing_values.h),
 * the same code under the FMI 3.0 layer. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_layer.h"

static const char *const STATUS_NAMES[] = {"ok", "warning", "discard", "error", "fatal", "pending"};

/* ------------------------------------------------------------------------------ logging */

static void echo(Instance *m, fmi2Status status, const char *text) {
    /* logging off: print the first warning, discard and error of this instance to stderr */
    int bit = 1 << (int)status;
    if (m->logging_on || status == fmi2OK || (m->echoed & bit)) return;
    int first = m->echoed == 0;
    m->echoed |= bit;
    fprintf(stderr, "bearing FMU '%s' [%s]: %s\n", m->name, STATUS_NAMES[status], text);
    if (first)
        fprintf(stderr, "  (logging is off, so this FMU instance prints its first warning, discard and error "
                        "here; instantiate it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to "
                        "receive every message)\n");
    fflush(stderr);
}

void bn_log(Instance *m, fmi2Status status, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    if (m->mute) return; /* the states a derivative's differences evaluate */
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    /* the logger takes a printf format: no '%' may reach it (messages never write one; names might) */
    for (char *p = text; *p; p++)
        if (*p == '%') *p = '?';
    if (m->logging_on && m->cb.logger)
        m->cb.logger(m->cb.componentEnvironment, m->name, status, STATUS_NAMES[status], text);
    echo(m, status, text);
}

fmi2Status bn2_fail(Instance *m, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    bn_log(m, fmi2Error, "%s", text);
    return fmi2Error;
}

/* refuse `call` (an FMI 2.0 function without "fmi2") unless the instance's mode allows it (fmi2_order.c) */
#define ORDER(call, kind) \
    if (bn_order_refused(m, #call, BN_ALLOW_##call, kind)) return fmi2Error
/* ------------------------------------------------------------------------------ FMI: common */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    if (!c) return fmi2Error;
    ((Instance *)c)->logging_on = loggingOn != 0;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)fmuResourceLocation;
    (void)visible;
    const char *name = instanceName ? instanceName : "";
    if (!fmuGUID || strcmp(fmuGUID, BN_GUID) != 0) {
        if (functions && functions->logger)
            functions->logger(functions->componentEnvironment, name, fmi2Error, "error",
                              "fmi2Instantiate: the GUID given is not this FMU's (" BN_GUID ")");
        else
            fprintf(stderr, "bearing FMU '%s' [error]: fmi2Instantiate: the GUID given is not this FMU's\n", name);
        return NULL;
    }
    Instance *m = (functions && functions->allocateMemory) ? functions->allocateMemory(1, sizeof(Instance))
                                                           : calloc(1, sizeof(Instance));
    if (!m) return NULL;
    memset(m, 0, sizeof *m);
    if (functions) m->cb = *functions;
    m->type = fmuType;
    m->logging_on = loggingOn != 0;
    snprintf(m->name, sizeof m->name, "%s", name);
    bn_set_starts(m);
    m->mode = MODE_INSTANTIATED;
    bn_live_add(m);
    return m;
}

void fmi2FreeInstance(fmi2Component c) {
    Instance *m = c;
    if (!m) return;
    if (!bn_live_remove(m)) { /* freed already (or never ours): its memory is not touched */
        fprintf(stderr, "bearing FMU: fmi2FreeInstance(%p): not a live instance of this FMU (freed already?); "
                        "nothing done\n", c);
        fflush(stderr);
        return;
    }
    bn_release(m); /* what the internal allocated (reynolds: the solver's memory) */
    if (m->cb.freeMemory) {
        fmi2CallbackFreeMemory release = m->cb.freeMemory;
        release(m);
    } else {
        free(m);
    }
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Instance *m = c;
    char a[32], b[32];
    (void)toleranceDefined;
    (void)tolerance;
    if (!m) return fmi2Error;
    ORDER(setupExperiment, BN_ANY_TYPE);
    if (!isfinite(startTime))
        return bn2_fail(m, "setupExperiment: startTime = %s s must be finite", bn_num(a, 32, startTime, 17));
    if (stopTimeDefined && !(startTime <= stopTime && stopTime < INFINITY))
        return bn2_fail(m, "setupExperiment: stopTime = %s s must be finite and >= startTime = %s s",
                        bn_num(a, 32, stopTime, 17), bn_num(b, 32, startTime, 17));
    m->t = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(enterInitializationMode, BN_ANY_TYPE);
    m->mode = MODE_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(exitInitializationMode, BN_ANY_TYPE);
    m->initialized = 1;
    if (bn_prepare(m)) return bn2_fail(m, "%s", m->init_error);
    bn_show_choices(m); /* both the String and its enumeration show the choice that counts */
    /* outputs at the start time from the initial inputs, when they can be evaluated (still in
     * Initialization Mode: T_eff quasi-static, Model Exchange's state starts there): a master
     * may set the inputs only before the first step, so a refused state is no initialisation error */
    int refused = bn_evaluate(m);
    m->mode = m->type == fmi2ModelExchange ? MODE_EVENT : MODE_STEP;
    if (refused) {
        bn_log(m, fmi2Warning, "outputs at the start time left at their start values: %s", m->msg);
        m->warn_pending = 1;
        m->dirty = 1;
    }
    return bn_warned(m);
}

fmi2Status fmi2Terminate(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(terminate, BN_ANY_TYPE);
    m->mode = MODE_TERMINATED;
    bn_log_excursions(m);
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    bn_set_starts(m);
    m->mode = MODE_INSTANTIATED;
    return fmi2OK;
}

/* ------------------------------------------------------------------------------ getters and setters */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getReal, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    int computed = 0;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= (fmi2ValueReference)N_REAL)
            return bn2_fail(m, "getReal: value reference %u is not a Real variable of this FMU", vr[i]);
        if (bn_is_output_real((int)vr[i]) && !computed) {
            computed = 1;
            fmi2Status s = bn_outputs(m, "getReal", bn_real_name((int)vr[i]));
            if (s == fmi2Error) return s;
            if (s > status) status = s;
        }
        value[i] = m->r[vr[i]];
    }
    return status;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getInteger, BN_ANY_TYPE);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_INT0 || vr[i] >= VR_INT_PARAM0 + N_INT)
            return bn2_fail(m, "getInteger: value reference %u is not an Integer variable of this FMU", vr[i]);
        value[i] = vr[i] >= VR_INT_PARAM0 ? m->n[vr[i] - VR_INT_PARAM0] : m->e[vr[i] - VR_INT0];
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getBoolean, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_BOOL0 || vr[i] >= VR_BOOL0 + N_BOOL)
            return bn2_fail(m, "getBoolean: value reference %u is not a Boolean variable of this FMU", vr[i]);
        if (vr[i] == VR_BOOL0 + B_OUT_OF_DOMAIN) {
            fmi2Status s = bn_outputs(m, "getBoolean", "out_of_domain");
            if (s == fmi2Error) return s;
            if (s > status) status = s;
        }
        value[i] = m->b[vr[i] - VR_BOOL0] ? fmi2True : fmi2False;
    }
    return status;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getString, BN_ANY_TYPE);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING)
            return bn2_fail(m, "getString: value reference %u is not a String variable of this FMU", vr[i]);
        value[i] = m->s[vr[i] - VR_STRING0];
    }
    return fmi2OK;
}

/* a parameter set after initialisation: refused (1, logged), else 0 */
static int parameter_fixed(Instance *m, const char *call, const char *name, const char *keeps) {
    if (!m->initialized) return 0;
    bn2_fail(m, "%s: parameter %s is fixed after initialisation (variability fixed); it keeps %s", call, name, keeps);
    return 1;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setReal, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    char a[32], why[512];
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference k = vr[i];
        if (BN_IS_INPUT(k)) { /* inputs: any value; a non-finite one is refused when evaluated */
            m->r[k] = value[i];
            m->dirty = 1;
            m->step_refused = 0;
            continue;
        }
        if (k >= (fmi2ValueReference)N_REAL) {
            status = bn2_fail(m, "setReal: value reference %u is not a Real variable of this FMU", k);
            continue;
        }
        if (bn_is_output_real((int)k)) {
            status = bn2_fail(m, "setReal: %s is an output and cannot be set", bn_real_name((int)k));
            continue;
        }
        if (parameter_fixed(m, "setReal", bn_real_name((int)k), bn_num(a, sizeof a, m->r[k], 17))) {
            status = fmi2Error;
            continue;
        }
        if (bn_check_real((int)k, value[i], why, sizeof why)) {
            m->refused[k] = 1;
            snprintf(m->refused_msg[k], sizeof m->refused_msg[k], "%s", why);
            status = bn2_fail(m, "setReal: %s; %s keeps %s", why, bn_real_name((int)k),
                              bn_num(a, sizeof a, m->r[k], 17));
            continue;
        }
        m->refused[k] = 0;
        m->r[k] = value[i];
    }
    return status;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setInteger, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    char why[512], keeps[32];
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_INT0 || vr[i] >= VR_INT_PARAM0 + N_INT) {
            status = bn2_fail(m, "setInteger: value reference %u is not an Integer variable of this FMU", vr[i]);
            continue;
        }
        if (vr[i] >= VR_INT_PARAM0) { /* groove_count, lobes: the bore, checked against the data's at initialisation */
            int k = (int)(vr[i] - VR_INT_PARAM0);
            snprintf(keeps, sizeof keeps, "%d", m->n[k]);
            if (parameter_fixed(m, "setInteger", bn_int_name(k), keeps))
                status = fmi2Error;
            else if (bn_set_int(m, k, value[i], why, sizeof why))
                status = bn2_fail(m, "setInteger: %s; %s keeps %s", why, bn_int_name(k), keeps);
            continue;
        }
        int j = (int)(vr[i] - VR_INT0);
        int slot = N_REAL + N_BOOL + N_STRING + j;
        snprintf(keeps, sizeof keeps, "%d", m->e[j]);
        if (parameter_fixed(m, "setInteger", bn_enum_name(j), keeps)) {
            status = fmi2Error;
            continue;
        }
        if (bn_check_enum(j, value[i], why, sizeof why)) {
            m->refused[slot] = 1;
            snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
            status = bn2_fail(m, "setInteger: %s; %s keeps %s", why, bn_enum_name(j), keeps);
            continue;
        }
        m->refused[slot] = 0;
        m->e[j] = value[i];
    }
    return status;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setBoolean, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_BOOL0 || vr[i] >= VR_BOOL0 + N_BOOL) {
            status = bn2_fail(m, "setBoolean: value reference %u is not a Boolean variable of this FMU", vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_BOOL0);
        if (k == B_OUT_OF_DOMAIN) {
            status = bn2_fail(m, "setBoolean: out_of_domain is an output and cannot be set");
            continue;
        }
        if (parameter_fixed(m, "setBoolean", BN_BOOL_NAMES[k], m->b[k] ? "True" : "False")) {
            status = fmi2Error;
            continue;
        }
        m->b[k] = value[i] != fmi2False;
    }
    return status;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setString, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    char why[512], out[STRING_MAX], keeps[STRING_MAX + 2];
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING) {
            status = bn2_fail(m, "setString: value reference %u is not a String variable of this FMU", vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_STRING0);
        int slot = N_REAL + N_BOOL + k;
        snprintf(keeps, sizeof keeps, "'%s'", m->s[k]);
        if (parameter_fixed(m, "setString", bn_string_name(k), keeps)) {
            status = fmi2Error;
            continue;
        }
        if (bn_check_string(k, value[i] ? value[i] : "", out, why, sizeof why)) {
            m->refused[slot] = 1;
            snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
            status = bn2_fail(m, "setString: %s; %s keeps %s", why, bn_string_name(k), keeps);
            continue;
        }
        m->refused[slot] = 0;
        snprintf(m->s[k], STRING_MAX, "%s", out);
    }
    return status;
}
