/* The FMI 2.0 layer of the native bearing FMU (Co-Simulation and Model Exchange in one binary).
 *
 * The journal state (y, z, vy, vz, omega) goes in, the film force and its tangent come out,
 * computed by the internal compiled beside this file (internal_<name>.c). As in the FMI Reference
 * FMUs, each function here checks its instance and its place in the calling sequence (ORDER: the
 * table of bearing_fmu/fmu/order.py, the Python FMU's too) and makes one call into the model layer
 * (bearing_calls.h), the same code under the FMI 3.0 layer: the statuses (docs/fmu.md, "FMI
 * status") are the model layer's. What is FMI 2.0's own: the logger callback (no '%' may reach its
 * printf format), the importer's memory functions, the fmi2 types and the status kinds.
 *
 * After an error the instance stays usable. A second fmi2FreeInstance of the same instance is
 * recognised and does nothing (the model layer lists the live instances). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bearing_calls.h"

#if BN_FMI3
#error "the FMI 2.0 layer is compiled without BN_FMI_VERSION=3"
#endif

static const char *const STATUS_NAMES[] = {"ok", "warning", "discard", "error", "fatal", "pending"};

/* refuse `call` unless the instance's mode allows it, for an instance of `kind` (BN_ANY_TYPE,
 * BN_CS_ONLY, BN_ME_ONLY); `call` the FMI 2.0 name without "fmi2" as the messages write it */
#define INSTANCE Instance *m = c; if (!m) return fmi2Error
#define ORDER(call, kind) if (bn_order_refused(m, #call, BN_ALLOW_##call, kind)) return fmi2Error

/* the model layer's log line to the logger callback (logging on); 0 when none received it */
static int emit(Instance *m, bn_status status, char *text) {
    for (char *p = text; *p; p++) /* the logger takes a printf format: no '%' may reach it */
        if (*p == '%') *p = '?';
    if (!m->logging_on || !m->cb.logger) return 0;
    m->cb.logger(m->cb.componentEnvironment, m->name, status, STATUS_NAMES[status], text);
    return 1;
}

/* ------------------------------------------------------------------------------ instances and modes */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    INSTANCE;
    ORDER(setDebugLogging, BN_ANY_TYPE);
    m->logging_on = loggingOn != 0;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)fmuResourceLocation; /* the data are compiled in */
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
    int own = functions && functions->allocateMemory && functions->freeMemory;
    Instance *m = bn_instance_new(name, fmuType == fmi2ModelExchange, loggingOn, emit,
                                  own ? functions->allocateMemory : NULL, own ? functions->freeMemory : NULL);
    if (m && functions) m->cb = *functions;
    return m;
}

void fmi2FreeInstance(fmi2Component c) {
    if (c) bn_instance_free(c, "fmi2FreeInstance");
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    (void)toleranceDefined; /* no integrator inside */
    (void)tolerance;
    INSTANCE;
    ORDER(setupExperiment, BN_ANY_TYPE);
    return bn_start_time(m, "setupExperiment", startTime, stopTimeDefined, stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    INSTANCE;
    ORDER(enterInitializationMode, BN_ANY_TYPE);
    return bn_enter_init(m);
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    INSTANCE;
    ORDER(exitInitializationMode, BN_ANY_TYPE);
    return bn_exit_init(m, "exitInitializationMode");
}

fmi2Status fmi2Terminate(fmi2Component c) {
    INSTANCE;
    ORDER(terminate, BN_ANY_TYPE);
    return bn_terminate(m);
}

fmi2Status fmi2Reset(fmi2Component c) {
    INSTANCE;
    ORDER(reset, BN_ANY_TYPE);
    return bn_reset(m);
}

/* ------------------------------------------------------------------------------ getting and setting values */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    INSTANCE;
    ORDER(getReal, BN_ANY_TYPE);
    return bn_get_reals(m, "getReal", vr, nvr, value);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    INSTANCE;
    ORDER(getInteger, BN_ANY_TYPE);
    for (size_t i = 0; i < nvr; i++) {
        long long v = 0;
        if (bn_get_int(m, "getInteger", vr[i], &v) != fmi2OK) return fmi2Error;
        value[i] = (fmi2Integer)v;
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    INSTANCE;
    ORDER(getBoolean, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++) {
        int v = 0;
        fmi2Status s = bn_get_bool(m, "getBoolean", vr[i], &v);
        if (s == fmi2Error) return s;
        if (s > status) status = s;
        value[i] = v ? fmi2True : fmi2False;
    }
    return status;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    INSTANCE;
    ORDER(getString, BN_ANY_TYPE);
    return bn_get_strings(m, "getString", vr, nvr, value);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    INSTANCE;
    ORDER(setReal, BN_ANY_TYPE);
    return bn_set_reals(m, "setReal", vr, nvr, value);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    INSTANCE;
    ORDER(setInteger, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++)
        if (bn_set_integer(m, "setInteger", vr[i], value[i]) != fmi2OK) status = fmi2Error;
    return status;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    INSTANCE;
    ORDER(setBoolean, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++)
        if (bn_set_bool(m, "setBoolean", vr[i], value[i] != fmi2False) != fmi2OK) status = fmi2Error;
    return status;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    INSTANCE;
    ORDER(setString, BN_ANY_TYPE);
    return bn_set_strings(m, "setString", vr, nvr, value);
}

/* ------------------------------------------------------------------------------ FMU states */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    INSTANCE;
    ORDER(getFMUstate, BN_ANY_TYPE);
    return bn_fmu_state_get(m, "getFMUstate", FMUstate);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    INSTANCE;
    ORDER(setFMUstate, BN_ANY_TYPE);
    return bn_fmu_state_set(m, "setFMUstate", FMUstate);
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    INSTANCE;
    ORDER(freeFMUstate, BN_ANY_TYPE);
    return bn_fmu_state_free(m, "freeFMUstate", FMUstate);
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
    INSTANCE;
    ORDER(serializedFMUstateSize, BN_ANY_TYPE);
    return bn_fmu_state_size(m, "serializedFMUstateSize", FMUstate, size);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size) {
    INSTANCE;
    ORDER(serializeFMUstate, BN_ANY_TYPE);
    return bn_fmu_state_serialize(m, "serializeFMUstate", FMUstate, (unsigned char *)serializedState, size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate) {
    INSTANCE;
    ORDER(deSerializeFMUstate, BN_ANY_TYPE);
    return bn_fmu_state_deserialize(m, "deSerializeFMUstate", (const unsigned char *)serializedState, size, FMUstate);
}

/* ------------------------------------------------------------------------------ derivatives */

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    INSTANCE;
    ORDER(getDirectionalDerivative, BN_ANY_TYPE);
    return bn_derivatives(m, "getDirectionalDerivative", 0, vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown,
                          nKnown, dvUnknown, nUnknown);
}

/* ------------------------------------------------------------------------------ Co-Simulation */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    INSTANCE;
    ORDER(setRealInputDerivatives, BN_CS_ONLY);
    return bn_fail(m, "setRealInputDerivatives: not supported (canInterpolateInputs is false)");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    INSTANCE;
    ORDER(getRealOutputDerivatives, BN_CS_ONLY);
    return bn_fail(m, "getRealOutputDerivatives: not supported (maxOutputDerivativeOrder is 0)");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    (void)noSetFMUStatePriorToCurrentPoint;
    double t_done;
    INSTANCE;
    return bn_do_step(m, "doStep", BN_ALLOW_doStep, currentCommunicationPoint, communicationStepSize, &t_done);
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    INSTANCE;
    return bn_fail(m, "cancelStep: doStep never runs asynchronously here");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)value;
    INSTANCE;
    ORDER(getStatus, BN_CS_ONLY);
    return bn_fail(m, "getStatus: status kind %d is not provided (doStep never returns fmi2Pending)", (int)s);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    INSTANCE;
    ORDER(getRealStatus, BN_CS_ONLY);
    if (s != fmi2LastSuccessfulTime) return bn_fail(m, "getRealStatus: status kind %d is not provided", (int)s);
    *value = m->t;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)value;
    INSTANCE;
    ORDER(getIntegerStatus, BN_CS_ONLY);
    return bn_fail(m, "getIntegerStatus: status kind %d is not provided", (int)s);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    INSTANCE;
    ORDER(getBooleanStatus, BN_CS_ONLY);
    if (s != fmi2Terminated) return bn_fail(m, "getBooleanStatus: status kind %d is not provided", (int)s);
    *value = m->terminated ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)value;
    INSTANCE;
    ORDER(getStringStatus, BN_CS_ONLY);
    return bn_fail(m, "getStringStatus: status kind %d is not provided", (int)s);
}

/* ------------------------------------------------------------------------------ Model Exchange */

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    INSTANCE;
    ORDER(enterEventMode, BN_ME_ONLY);
    return bn_enter_event_mode(m);
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    INSTANCE;
    ORDER(newDiscreteStates, BN_ME_ONLY);
    if (!info) return bn_fail(m, "newDiscreteStates: fmi2EventInfo* is NULL");
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return bn_discrete_states(m, "newDiscreteStates");
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    INSTANCE;
    ORDER(enterContinuousTimeMode, BN_ME_ONLY);
    return bn_enter_continuous_mode(m, "enterContinuousTimeMode");
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    INSTANCE;
    ORDER(completedIntegratorStep, BN_ME_ONLY);
    if (!enterEventMode || !terminateSimulation)
        return bn_fail(m, "completedIntegratorStep: an output argument is NULL");
    int event = 0;
    fmi2Status s = bn_completed_step(m, "completedIntegratorStep", &event);
    *enterEventMode = event ? fmi2True : fmi2False;
    *terminateSimulation = fmi2False;
    return s;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    INSTANCE;
    ORDER(setTime, BN_ME_ONLY);
    return bn_set_time(m, "setTime", time);
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    INSTANCE;
    ORDER(setContinuousStates, BN_ME_ONLY);
    return bn_set_states(m, "setContinuousStates", x, nx);
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    INSTANCE;
    ORDER(getDerivatives, BN_ME_ONLY);
    return bn_get_state_derivatives(m, "getDerivatives", derivatives, nx);
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    (void)eventIndicators;
    INSTANCE;
    ORDER(getEventIndicators, BN_ME_ONLY);
    return bn_no_states(m, "getEventIndicators", ni, "event indicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    INSTANCE;
    ORDER(getContinuousStates, BN_ME_ONLY);
    return bn_get_states(m, "getContinuousStates", x, nx);
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    INSTANCE;
    ORDER(getNominalsOfContinuousStates, BN_ME_ONLY);
    return bn_get_nominals(m, "getNominalsOfContinuousStates", x_nominal, nx);
}
