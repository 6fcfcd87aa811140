/* The FMI 3.0 bearing FMU's interfaces over the model layer (bearing_calls.h): the variables'
 * dependencies, Model Exchange (no event indicators; the outputs a direct feedthrough of the
 * inputs), Co-Simulation (no Event Mode), and what this FMU does not provide (other variable
 * types, clocks, configuration mode, output derivatives, Scheduled Execution): fmi3Error saying
 * so. Each function checks its place in the calling sequence (fmi3.py ALLOWED3) and makes one
 * call into the model layer. */
#include <stdio.h>
#include <string.h>

#include "fmi3_layer.h"

static const char *const MODE_NAMES[] = BN_MODE_NAMES;

/* ------------------------------------------------------------------------------ dependencies */

/* the inputs and states a variable depends on after initialisation (into deps, their number):
 * fmi3.py's output_dependencies, the ModelStructure's Output and ContinuousStateDerivative elements.
 * A build with the state T_eff (BN_N_STATES): the force, K, C and P_loss on the journal state and
 * T_eff, Q_side on the journal state, mu_eff on T_eff, T_eff on T_supply and itself, der(T_eff) on
 * the journal state, T_supply and T_eff; else T_eff on T_supply, P_loss, Q_side, mu_eff on nothing. */
#define MAX_DEPENDENCIES (8 + BN_N_PAD_STATES)
static int dependencies(fmi3ValueReference v, fmi3ValueReference deps[MAX_DEPENDENCIES]) {
    /* the peak pressure: as the force (the Reynolds internal's field), none without a field (always 0) */
    int n = 0, k, force = (v >= VR_FY && v < VR_D && v != VR_ECC && v != VR_HMIN) || (BN_HOLDS_REYNOLDS && BN_IS_PEAK((int)v));
    if (BN_N_PADS && (force || BN_IS_PAD_REAL((int)v))) { /* tilting pads: the journal state and the pads' states */
        for (k = 0; k < 5; k++) deps[n++] = (fmi3ValueReference)k;
        for (k = 0; k < BN_N_PAD_STATES; k++) deps[n++] = (fmi3ValueReference)(VR_PAD0 + k);
        return n;
    }
    if (v == VR_ECC || v == VR_HMIN) n = 2;                                  /* y, z */
    else if (v == VR_BOOL0 + B_OUT_OF_DOMAIN) n = BN3_FITTED_DOMAIN ? 4 : 0; /* y, z, vy, vz */
    else if (force || (BN_N_STATES && (v == VR_P_LOSS || v == VR_Q_SIDE || v == VR_DER_T_EFF))) n = 5;
    for (k = 0; k < n; k++) deps[k] = (fmi3ValueReference)k;                 /* the journal state */
    if (v == VR_T_EFF || (BN_N_STATES && v == VR_DER_T_EFF)) deps[n++] = VR_T_SUPPLY;
    if (BN_N_STATES && (force || v == VR_P_LOSS || v == VR_MU_EFF || v == VR_T_EFF || v == VR_DER_T_EFF))
        deps[n++] = VR_T_EFF;
    return n;
}

static int known_variable(fmi3ValueReference v) {
    return v < (fmi3ValueReference)N_REAL || v == BN3_VR_TIME || (v >= VR_BOOL0 && v < VR_BOOL0 + N_BOOL)
           || (v >= VR_STRING0 && v < VR_STRING0 + N_STRING) || (v >= VR_INT0 && v < VR_INT_PARAM0 + N_INT);
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetNumberOfVariableDependencies, BN_ANY_TYPE);
    if (!known_variable(valueReference) || !nDependencies)
        return bn_fail(m, "fmi3GetNumberOfVariableDependencies: value reference %u is not a variable of this FMU%s",
                        valueReference, nDependencies ? "" : " (or nDependencies is NULL)");
    fmi3ValueReference deps[MAX_DEPENDENCIES];
    *nDependencies = (size_t)dependencies(valueReference, deps);
    return fmi3OK;
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetVariableDependencies, BN_ANY_TYPE);
    if (!known_variable(dependent))
        return bn_fail(m, "fmi3GetVariableDependencies: value reference %u is not a variable of this FMU", dependent);
    fmi3ValueReference deps[MAX_DEPENDENCIES];
    int n = dependencies(dependent, deps);
    if (nDependencies != (size_t)n)
        return bn_fail(m, "fmi3GetVariableDependencies: nDependencies = %lu, but %s has %d (ask "
                        "fmi3GetNumberOfVariableDependencies)", (unsigned long)nDependencies,
                        dependent < (fmi3ValueReference)N_REAL ? bn_real_name((int)dependent) : "the variable", n);
    for (int k = 0; k < n; k++) { /* scalars: element index 0, the whole variable */
        elementIndicesOfDependent[k] = 0;
        independents[k] = deps[k];
        elementIndicesOfIndependents[k] = 0;
        dependencyKinds[k] = fmi3Dependent;
    }
    return fmi3OK;
}

/* ------------------------------------------------------------------------------ Model Exchange */

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    INSTANCE;
    ORDER3(EnterEventMode, BN_ME_ONLY);
    return bn_enter_event_mode(m);
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    INSTANCE;
    ORDER3(UpdateDiscreteStates, BN_ME_ONLY);
    if (!discreteStatesNeedUpdate || !terminateSimulation || !nominalsOfContinuousStatesChanged
        || !valuesOfContinuousStatesChanged || !nextEventTimeDefined || !nextEventTime)
        return bn_fail(m, "fmi3UpdateDiscreteStates: an output argument is NULL");
    *discreteStatesNeedUpdate = false;
    *terminateSimulation = false;
    *nominalsOfContinuousStatesChanged = false;
    *valuesOfContinuousStatesChanged = false;
    *nextEventTimeDefined = false;
    *nextEventTime = 0.0;
    return bn_discrete_states(m, "fmi3UpdateDiscreteStates");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    INSTANCE;
    ORDER3(EvaluateDiscreteStates, BN_ME_ONLY);
    return fmi3OK; /* providesEvaluateDiscreteStates is false: ignored (FMI 3.0.2, section 2.3.5) */
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    INSTANCE;
    ORDER3(EnterContinuousTimeMode, BN_ME_ONLY);
    return bn_enter_continuous_mode(m, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    INSTANCE;
    ORDER3(CompletedIntegratorStep, BN_ME_ONLY);
    if (!enterEventMode || !terminateSimulation)
        return bn_fail(m, "fmi3CompletedIntegratorStep: an output argument is NULL");
    int event = 0;
    fmi3Status s = bn_completed_step(m, "fmi3CompletedIntegratorStep", &event);
    *enterEventMode = event ? true : false;
    *terminateSimulation = false;
    return s;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    INSTANCE;
    ORDER3(SetTime, BN_ME_ONLY);
    return bn_set_time(m, "fmi3SetTime", time);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t n) {
    (void)eventIndicators;
    INSTANCE;
    ORDER3(GetEventIndicators, BN_ME_ONLY);
    return bn_no_states(m, "fmi3GetEventIndicators", n, "event indicators");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    INSTANCE;
    ORDER3(GetNumberOfEventIndicators, BN_ME_ONLY);
    if (nEventIndicators) *nEventIndicators = 0;
    return fmi3OK;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[], size_t n) {
    INSTANCE;
    ORDER3(SetContinuousStates, BN_ME_ONLY);
    return bn_set_states(m, "fmi3SetContinuousStates", continuousStates, n);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t n) {
    INSTANCE;
    ORDER3(GetContinuousStateDerivatives, BN_ME_ONLY);
    return bn_get_state_derivatives(m, "fmi3GetContinuousStateDerivatives", derivatives, n);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t n) {
    INSTANCE;
    ORDER3(GetContinuousStates, BN_ME_ONLY);
    return bn_get_states(m, "fmi3GetContinuousStates", continuousStates, n);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t n) {
    INSTANCE;
    ORDER3(GetNominalsOfContinuousStates, BN_ME_ONLY);
    return bn_get_nominals(m, "fmi3GetNominalsOfContinuousStates", nominals, n);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    INSTANCE;
    ORDER3(GetNumberOfContinuousStates, BN_ME_ONLY);
    if (nContinuousStates) *nContinuousStates = BN_NX;
    return fmi3OK;
}

/* ------------------------------------------------------------------------------ Co-Simulation */

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    INSTANCE;
    if (!m->model_exchange) /* never in Event Mode here */
        return bn_fail(m, "fmi3EnterStepMode in %s: this FMU has no Event Mode in Co-Simulation (hasEventMode is "
                       "false): fmi3ExitInitializationMode enters Step Mode", MODE_NAMES[m->mode]);
    ORDER3(EnterStepMode, BN_CS_ONLY);
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime) {
    (void)noSetFMUStatePriorToCurrentPoint;
    INSTANCE;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime)
        return bn_fail(m, "fmi3DoStep: an output argument is NULL");
    *eventHandlingNeeded = false;
    *terminateSimulation = false;
    *earlyReturn = false;
    *lastSuccessfulTime = m->t;
    return bn_do_step(m, "fmi3DoStep", BN3_ALLOW_DoStep, currentCommunicationPoint, communicationStepSize,
                      lastSuccessfulTime);
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues) {
    (void)valueReferences; (void)nValueReferences; (void)orders; (void)values; (void)nValues;
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetOutputDerivatives, BN_CS_ONLY);
    return bn_fail(m, "fmi3GetOutputDerivatives: not provided (maxOutputDerivativeOrder is 0)");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    (void)clockReference; (void)activationTime;
    if (!instance) return fmi3Error;
    return bn_fail(instance, "fmi3ActivateModelPartition: this FMU has no Scheduled Execution");
}

/* ------------------------------------------------------------------------------ not provided */

static fmi3Status no_such(Instance *m, const char *call, unsigned allowed, size_t nvr, const fmi3ValueReference vr[],
                          const char *type) {
    if (!m) return fmi3Error;
    if (allowed && bn_order_refused(m, call, allowed, BN_ANY_TYPE)) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    return bn_fail(m, "%s: value reference %u is not a%s %s variable of this FMU (it has Float64, Boolean, String "
                    "and Enumeration variables; an Enumeration is read and set with fmi3GetInt64, fmi3SetInt64)", call,
                    vr ? vr[0] : 0u, strchr("IU", type[0]) ? "n" : "", type);
}

#define NO_GET(T)                                                                                                   \
    fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3##T values[],      \
                          size_t nValues) {                                                                         \
        (void)values; (void)nValues;                                                                                \
        return no_such(instance, "fmi3Get" #T, BN3_ALLOW_Get##T, nvr, vr, #T);                                      \
    }
#define NO_SET(T)                                                                                                   \
    fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3##T values[], \
                          size_t nValues) {                                                                         \
        (void)values; (void)nValues;                                                                                \
        return no_such(instance, "fmi3Set" #T, BN3_ALLOW_Set##T, nvr, vr, #T);                                      \
    }
NO_GET(Float32) NO_GET(Int8) NO_GET(UInt8) NO_GET(Int16) NO_GET(UInt16) NO_GET(Int32) NO_GET(UInt32) NO_GET(UInt64)
NO_SET(Float32) NO_SET(Int8) NO_SET(UInt8) NO_SET(Int16) NO_SET(UInt16) NO_SET(Int32) NO_SET(UInt32) NO_SET(UInt64)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, size_t valueSizes[],
                         fmi3Binary values[], size_t nValues) {
    (void)valueSizes; (void)values; (void)nValues;
    return no_such(instance, "fmi3GetBinary", BN3_ALLOW_GetBinary, nvr, vr, "Binary");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues) {
    (void)valueSizes; (void)values; (void)nValues;
    return no_such(instance, "fmi3SetBinary", BN3_ALLOW_SetBinary, nvr, vr, "Binary");
}

/* clocks: none, nor structural parameters (so no Configuration Mode) */
fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock values[]) {
    (void)values;
    return no_such(instance, "fmi3GetClock", 0, nvr, vr, "Clock");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock values[]) {
    (void)values;
    return no_such(instance, "fmi3SetClock", 0, nvr, vr, "Clock");
}

#define NO_INTERVAL(call, ...)                                                                                      \
    fmi3Status call(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, __VA_ARGS__)
NO_INTERVAL(fmi3GetIntervalDecimal, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]) {
    (void)intervals; (void)qualifiers;
    return no_such(instance, "fmi3GetIntervalDecimal", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3GetIntervalFraction, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
            fmi3IntervalQualifier qualifiers[]) {
    (void)counters; (void)resolutions; (void)qualifiers;
    return no_such(instance, "fmi3GetIntervalFraction", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3GetShiftDecimal, fmi3Float64 shifts[]) {
    (void)shifts;
    return no_such(instance, "fmi3GetShiftDecimal", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3GetShiftFraction, fmi3UInt64 counters[], fmi3UInt64 resolutions[]) {
    (void)counters; (void)resolutions;
    return no_such(instance, "fmi3GetShiftFraction", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3SetIntervalDecimal, const fmi3Float64 intervals[]) {
    (void)intervals;
    return no_such(instance, "fmi3SetIntervalDecimal", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3SetIntervalFraction, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
    (void)counters; (void)resolutions;
    return no_such(instance, "fmi3SetIntervalFraction", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3SetShiftDecimal, const fmi3Float64 shifts[]) {
    (void)shifts;
    return no_such(instance, "fmi3SetShiftDecimal", 0, nvr, vr, "Clock");
}
NO_INTERVAL(fmi3SetShiftFraction, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[]) {
    (void)counters; (void)resolutions;
    return no_such(instance, "fmi3SetShiftFraction", 0, nvr, vr, "Clock");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    if (!instance) return fmi3Error;
    return bn_fail(instance, "fmi3EnterConfigurationMode: this FMU has no structural parameters (no Configuration "
                    "Mode)");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    if (!instance) return fmi3Error;
    return bn_fail(instance, "fmi3ExitConfigurationMode: this FMU has no structural parameters (no Configuration "
                    "Mode)");
}
