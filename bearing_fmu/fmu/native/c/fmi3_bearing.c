/* The FMI 3.0 layer of the native bearing FMU (Model Exchange and Co-Simulation in one binary),
 * over the model layer (bearing_calls.h) and the internal compiled beside it, as the FMI 2.0
 * layer (fmi2_bearing.c) is: each function checks its instance and its place in the calling
 * sequence and makes one call into the model layer, so the variables, value references, checks,
 * evaluation, derivatives, words and statuses are the FMI 2.0 FMU's (docs/fmu.md, "FMI status").
 *
 * What FMI 3.0 changes:
 *   - the variables are Float64, Boolean, String and Enumeration (fmi3GetInt64/fmi3SetInt64),
 *     and time is the independent variable (value reference BN3_VR_TIME, fmi3GetFloat64 only);
 *   - errors reach the logger even with logging off (FMI 3.0.2, section 2.3.1), warnings and
 *     discards as their log category is on (fmi3SetDebugLogging); '#' doubled in a message;
 *   - a refused doStep (fmi3_modes.c) leaves the instance as before the call, with
 *     terminateSimulation false: the importer may restore a state and go on;
 *   - adjoint derivatives beside the directional ones; nValues given with every array.
 * After an fmi3Error the instance stays usable (the standard lets the importer only reset or
 * free it then; both work).
 *
 * This file: logging, instances, modes, values, FMU states, derivatives. fmi3_modes.c: the
 * variables' dependencies, Model Exchange, Co-Simulation and what this FMU does not provide. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_layer.h"

static const char *const CATEGORIES[] = {"logStatusOK", "logStatusWarning", "logStatusDiscard", "logStatusError",
                                         "logStatusFatal"};
#define FIRST_CATEGORY 1 /* the categories declared: warning, discard, error (modelDescription.xml) */
#define LAST_CATEGORY 3

/* ------------------------------------------------------------------------------ logging */

/* the model layer's log line to logMessage: an error always, the others as their category is on;
 * 0 when none received it */
static int emit(Instance *m, bn_status status, char *text) {
    char out[4096];
    size_t k = 0;
    int on = m->logging_on && !(m->log_off & (1u << status));
    if (!m->log_message || !(on || status >= fmi3Error)) return 0;
    for (const char *p = text; *p && k + 2 < sizeof out; p++) { /* '#' starts a variable reference (#<vr>#): doubled */
        if (*p == '#') out[k++] = '#';
        out[k++] = *p;
    }
    out[k] = 0;
    m->log_message(m->env, (fmi3Status)status, CATEGORIES[status], out);
    return 1;
}

/* ------------------------------------------------------------------------------ instances */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    INSTANCE;
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
            return bn_fail(m, "fmi3SetDebugLogging: unknown log category '%s'; this FMU has logStatusWarning, "
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
    Instance *m = bn_instance_new(name, model_exchange, loggingOn, emit, NULL, NULL);
    if (!m) return refuse_instance(name, env, log, "out of memory");
    m->env = env;
    m->log_message = log;
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
    if (instance) bn_instance_free(instance, "fmi3FreeInstance");
}

/* ------------------------------------------------------------------------------ modes */

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    (void)toleranceDefined; /* no integrator inside */
    (void)tolerance;
    INSTANCE;
    ORDER3(EnterInitializationMode, BN_ANY_TYPE);
    fmi3Status s = bn_start_time(m, "fmi3EnterInitializationMode", startTime, stopTimeDefined, stopTime);
    return s == fmi3OK ? bn_enter_init(m) : s;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    INSTANCE;
    ORDER3(ExitInitializationMode, BN_ANY_TYPE);
    return bn_exit_init(m, "fmi3ExitInitializationMode");
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    INSTANCE;
    ORDER3(Terminate, BN_ANY_TYPE);
    return bn_terminate(m);
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    INSTANCE;
    ORDER3(Reset, BN_ANY_TYPE);
    return bn_reset(m);
}

/* ------------------------------------------------------------------------------ values */

/* every variable of this FMU is a scalar: as many values as value references */
#define COUNTS(call) \
    if (nValues != nvr) \
        return bn_fail(m, "fmi3" #call ": %lu value references but nValues = %lu (every variable of this FMU is a " \
                       "scalar)", (unsigned long)nvr, (unsigned long)nValues)

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 values[],
                          size_t nValues) {
    INSTANCE;
    ORDER3(GetFloat64, BN_ANY_TYPE);
    COUNTS(GetFloat64);
    return bn_get_reals(m, "fmi3GetFloat64", vr, nvr, values);
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 values[],
                        size_t nValues) {
    INSTANCE;
    ORDER3(GetInt64, BN_ANY_TYPE);
    COUNTS(GetInt64);
    for (size_t i = 0; i < nvr; i++) {
        long long v = 0;
        if (bn_get_int(m, "fmi3GetInt64", vr[i], &v) != fmi3OK) return fmi3Error;
        values[i] = (fmi3Int64)v;
    }
    return fmi3OK;
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Boolean values[],
                          size_t nValues) {
    INSTANCE;
    ORDER3(GetBoolean, BN_ANY_TYPE);
    COUNTS(GetBoolean);
    fmi3Status status = fmi3OK;
    for (size_t i = 0; i < nvr; i++) {
        int v = 0;
        fmi3Status s = bn_get_bool(m, "fmi3GetBoolean", vr[i], &v);
        if (s == fmi3Error) return s;
        if (s > status) status = s;
        values[i] = v ? true : false;
    }
    return status;
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3String values[],
                         size_t nValues) {
    INSTANCE;
    ORDER3(GetString, BN_ANY_TYPE);
    COUNTS(GetString);
    return bn_get_strings(m, "fmi3GetString", vr, nvr, values);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 values[], size_t nValues) {
    INSTANCE;
    ORDER3(SetFloat64, BN_ANY_TYPE);
    COUNTS(SetFloat64);
    return bn_set_reals(m, "fmi3SetFloat64", vr, nvr, values);
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Int64 values[],
                        size_t nValues) {
    INSTANCE;
    ORDER3(SetInt64, BN_ANY_TYPE);
    COUNTS(SetInt64);
    fmi3Status status = fmi3OK;
    for (size_t i = 0; i < nvr; i++)
        if (bn_set_integer(m, "fmi3SetInt64", vr[i], (long long)values[i]) != fmi3OK) status = fmi3Error;
    return status;
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Boolean values[], size_t nValues) {
    INSTANCE;
    ORDER3(SetBoolean, BN_ANY_TYPE);
    COUNTS(SetBoolean);
    fmi3Status status = fmi3OK;
    for (size_t i = 0; i < nvr; i++)
        if (bn_set_bool(m, "fmi3SetBoolean", vr[i], values[i] ? 1 : 0) != fmi3OK) status = fmi3Error;
    return status;
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3String values[],
                         size_t nValues) {
    INSTANCE;
    ORDER3(SetString, BN_ANY_TYPE);
    COUNTS(SetString);
    return bn_set_strings(m, "fmi3SetString", vr, nvr, values);
}

/* ------------------------------------------------------------------------------ FMU states */

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    INSTANCE;
    ORDER3(GetFMUState, BN_ANY_TYPE);
    return bn_fmu_state_get(m, "fmi3GetFMUState", FMUState);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    INSTANCE;
    ORDER3(SetFMUState, BN_ANY_TYPE);
    return bn_fmu_state_set(m, "fmi3SetFMUState", FMUState);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    INSTANCE;
    ORDER3(FreeFMUState, BN_ANY_TYPE);
    return bn_fmu_state_free(m, "fmi3FreeFMUState", FMUState);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size) {
    INSTANCE;
    ORDER3(SerializedFMUStateSize, BN_ANY_TYPE);
    return bn_fmu_state_size(m, "fmi3SerializedFMUStateSize", FMUState, size);
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size) {
    INSTANCE;
    ORDER3(SerializeFMUState, BN_ANY_TYPE);
    return bn_fmu_state_serialize(m, "fmi3SerializeFMUState", FMUState, serializedState, size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState) {
    INSTANCE;
    ORDER3(DeserializeFMUState, BN_ANY_TYPE);
    return bn_fmu_state_deserialize(m, "fmi3DeserializeFMUState", serializedState, size, FMUState);
}

/* ------------------------------------------------------------------------------ derivatives */

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    INSTANCE;
    ORDER3(GetDirectionalDerivative, BN_ANY_TYPE);
    return bn_derivatives(m, "fmi3GetDirectionalDerivative", 0, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed,
                          sensitivity, nSensitivity);
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    INSTANCE;
    ORDER3(GetAdjointDerivative, BN_ANY_TYPE);
    return bn_derivatives(m, "fmi3GetAdjointDerivative", 1, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed,
                          sensitivity, nSensitivity);
}
