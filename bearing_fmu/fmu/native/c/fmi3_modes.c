/* The FMI 3.0 bearing FMU's calling sequence and its interfaces: the check every function makes
 * first (bearing_fmu/fmu/native/fmi3.py: ALLOWED3, generated into fmi3_config.h as one bit mask
 * per function), Model Exchange (no continuous states, no event indicators:
 * the outputs are a direct feedthrough of the inputs), Co-Simulation (no Event Mode), the
 * variables' dependencies, and what this FMU does not provide (other variable types, clocks,
 * configuration mode, output derivatives, Scheduled Execution): fmi3Error saying so. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fmi3_layer.h"

/* ------------------------------------------------------------------------------ calling sequence */

static const char *const MODE_NAMES[] = BN_MODE_NAMES;
static const int STAGE[] = {0, 1, 2, 2, 2, 3}; /* each mode's place in an instance's life (order.MODES) */

int bn3_refused(Instance *m, const char *call, unsigned allowed, int kind) {
    const char *mode = MODE_NAMES[m->mode];
    int me = m->model_exchange;
    if ((kind == BN_CS_ONLY && me) || (kind == BN_ME_ONLY && !me)) { /* whatever the mode */
        int event = strstr(call, "EventMode") || strstr(call, "DiscreteStates");
        bn3_fail(m, "%s in %s: a %s function; this instance is a %s one%s", call, mode,
                 me ? "Co-Simulation" : "Model Exchange", me ? "Model Exchange" : "Co-Simulation",
                 !me && event ? " (this FMU has no Event Mode in Co-Simulation: hasEventMode is false)" : "");
        return 1;
    }
    if (allowed & (1u << m->mode)) return 0;
    unsigned never = me ? 1u << MODE_STEP : (1u << MODE_EVENT) | (1u << MODE_CONTINUOUS);
    char here[200] = "";
    int lo = 3, hi = 0, stage = STAGE[m->mode];
    for (int k = 0; k <= MODE_TERMINATED; k++) {
        if (!(allowed & (1u << k)) || (never & (1u << k))) continue;
        lo = STAGE[k] < lo ? STAGE[k] : lo;
        hi = STAGE[k] > hi ? STAGE[k] : hi;
        size_t n = strlen(here);
        snprintf(here + n, sizeof here - n, "%s%s", n ? " or " : "", MODE_NAMES[k]);
    }
    /* what to do instead, from where the instance is: before, after or beside the allowed modes */
    const char *hint;
    if (strcmp(call, "fmi3Terminate") == 0 && stage < 2)
        hint = "nothing to terminate: the instance was never initialised (free it, or fmi3Reset)";
    else if (stage > hi)
        hint = m->mode == MODE_TERMINATED ? "too late: the instance is terminated (fmi3Reset starts it over)"
               : stage == 2 ? "too late: the instance is initialised (fmi3Reset starts it over)"
                            : "too late: the instance is in Initialization Mode (fmi3Reset starts it over)";
    else if (stage < lo)
        hint = stage == 1 ? "call fmi3ExitInitializationMode first"
               : (allowed & (1u << MODE_INIT)) ? "call fmi3EnterInitializationMode first"
               : "initialise it first (fmi3EnterInitializationMode, then fmi3ExitInitializationMode)";
    else
        hint = m->mode == MODE_EVENT ? "call fmi3EnterContinuousTimeMode first"
               : m->mode == MODE_CONTINUOUS ? "call fmi3EnterEventMode first" : "call fmi3ExitInitializationMode first";
    bn3_fail(m, "%s in %s: not allowed there (FMI 3.0: in %s only); %s", call, mode, here, hint);
    return 1;
}

/* ------------------------------------------------------------------------------ dependencies */

/* the inputs and states a variable depends on after initialisation (into deps, their number):
 * fmi3.py's output_dependencies, the ModelStructure's Output and ContinuousStateDerivative elements.
 * A build with the state T_eff (BN_N_STATES): the force, K, C and P_loss on the journal state and
 * T_eff, Q_side on the journal state, mu_eff on T_eff, T_eff on T_supply and itself, der(T_eff) on
 * the journal state, T_supply and T_eff; else T_eff on T_supply, P_loss, Q_side, mu_eff on nothing. */
static int dependencies(fmi3ValueReference v, fmi3ValueReference deps[8]) {
    int n = 0, k, force = v >= VR_FY && v < VR_D && v != VR_ECC && v != VR_HMIN;
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
        return bn3_fail(m, "fmi3GetNumberOfVariableDependencies: value reference %u is not a variable of this FMU%s",
                        valueReference, nDependencies ? "" : " (or nDependencies is NULL)");
    fmi3ValueReference deps[8];
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
        return bn3_fail(m, "fmi3GetVariableDependencies: value reference %u is not a variable of this FMU", dependent);
    fmi3ValueReference deps[8];
    int n = dependencies(dependent, deps);
    if (nDependencies != (size_t)n)
        return bn3_fail(m, "fmi3GetVariableDependencies: nDependencies = %lu, but %s has %d (ask "
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
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(EnterEventMode, BN_ME_ONLY);
    m->mode = MODE_EVENT;
    if (!m->refused_state) m->b[B_OUT_OF_DOMAIN] = m->ood_now; /* a discrete output takes its value at the event */
    return fmi3OK;
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(UpdateDiscreteStates, BN_ME_ONLY);
    if (!discreteStatesNeedUpdate || !terminateSimulation || !nominalsOfContinuousStatesChanged
        || !valuesOfContinuousStatesChanged || !nextEventTimeDefined || !nextEventTime)
        return bn3_fail(m, "fmi3UpdateDiscreteStates: an output argument is NULL");
    *discreteStatesNeedUpdate = false;
    *terminateSimulation = false;
    *nominalsOfContinuousStatesChanged = false;
    *valuesOfContinuousStatesChanged = false;
    *nextEventTimeDefined = false;
    *nextEventTime = 0.0;
    return bn_outputs(m, "fmi3UpdateDiscreteStates", "out_of_domain"); /* in Event Mode it takes the state's value */
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(EvaluateDiscreteStates, BN_ME_ONLY);
    return fmi3OK; /* providesEvaluateDiscreteStates is false: ignored (FMI 3.0.2, section 2.3.5) */
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(EnterContinuousTimeMode, BN_ME_ONLY);
    /* out_of_domain of the inputs set in Event Mode, before it holds (a refused state: fmi3Discard at the next get) */
    bn_status s = bn_outputs(m, "fmi3EnterContinuousTimeMode", "out_of_domain");
    m->mode = MODE_CONTINUOUS;
    return s == fmi3Discard ? fmi3OK : s;
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(CompletedIntegratorStep, BN_ME_ONLY);
    if (!enterEventMode || !terminateSimulation)
        return bn3_fail(m, "fmi3CompletedIntegratorStep: an output argument is NULL");
    *enterEventMode = false;
    *terminateSimulation = false;
    bn_status s = bn_outputs(m, "fmi3CompletedIntegratorStep", "out_of_domain");
    if (s == fmi3Discard || s == fmi3Error) return s;
    /* a step event where the state crossed the fitted domain's edge: out_of_domain changes there */
    *enterEventMode = m->ood_now != m->b[B_OUT_OF_DOMAIN];
    return s;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    Instance *m = instance;
    char a[32], b[32];
    if (!m) return fmi3Error;
    ORDER3(SetTime, BN_ME_ONLY);
    if (!isfinite(time))
        return bn3_fail(m, "fmi3SetTime: time = %s s must be finite; the instance keeps t = %s s",
                        bn_num(a, 32, time, 17), bn_num(b, 32, m->t, 17));
    /* beyond stopTime too: a variable-step integrator steps past it and interpolates back (CVode),
     * and nothing here depends on time */
    m->t = time;
    return fmi3OK;
}

static fmi3Status no_states(Instance *m, const char *call, unsigned allowed, size_t n, const char *what) {
    if (!m) return fmi3Error;
    if (bn3_refused(m, call, allowed, BN_ME_ONLY)) return fmi3Error;
    if (n != 0) return bn3_fail(m, "%s: this FMU has no %s, got %lu", call, what, (unsigned long)n);
    return fmi3OK;
}
#define NO_STATES(call, n, what) no_states(instance, "fmi3" #call, BN3_ALLOW_##call, n, what)

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t n) {
    (void)eventIndicators;
    return NO_STATES(GetEventIndicators, n, "event indicators");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    fmi3Status s = NO_STATES(GetNumberOfEventIndicators, 0, "event indicators");
    if (s == fmi3OK && nEventIndicators) *nEventIndicators = 0;
    return s;
}

/* the continuous states (fmi2_modes.c says which): n the FMU's number (BN_N_STATES) */
static int states_refused(Instance *m, const char *call, unsigned allowed, size_t n, const void *p) {
    if (bn3_refused(m, call, allowed, BN_ME_ONLY)) return 1;
    if (n != BN_N_STATES) {
        bn3_fail(m, "%s: this FMU has %d continuous state(s), got %lu", call, BN_N_STATES, (unsigned long)n);
        return 1;
    }
    if (n && !p) {
        bn3_fail(m, "%s: the array is NULL", call);
        return 1;
    }
    return 0;
}
#define STATES_REFUSED(call, n, p) states_refused(m, "fmi3" #call, BN3_ALLOW_##call, n, p)

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[], size_t n) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    if (STATES_REFUSED(SetContinuousStates, n, continuousStates)) return fmi3Error;
    if (n) {
        m->r[VR_T_EFF] = continuousStates[0];
        m->dirty = 1;
    }
    return fmi3OK;
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t n) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    if (STATES_REFUSED(GetContinuousStateDerivatives, n, derivatives)) return fmi3Error;
    if (!n) return fmi3OK;
    fmi3Status s = bn_outputs(m, "fmi3GetContinuousStateDerivatives", "der(T_eff)");
    derivatives[0] = m->r[VR_DER_T_EFF];
    return s;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t n) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    if (STATES_REFUSED(GetContinuousStates, n, continuousStates)) return fmi3Error;
    if (!n) return fmi3OK;
    fmi3Status s = m->mode == MODE_INIT ? bn_outputs(m, "fmi3GetContinuousStates", "T_eff") : fmi3OK; /* its start */
    continuousStates[0] = m->r[VR_T_EFF];
    return s;
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t n) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    if (STATES_REFUSED(GetNominalsOfContinuousStates, n, nominals)) return fmi3Error;
    if (n) nominals[0] = 1.0; /* the model description gives T_eff no nominal */
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    fmi3Status s = NO_STATES(GetNumberOfContinuousStates, 0, "continuous states");
    if (s == fmi3OK && nContinuousStates) *nContinuousStates = BN_N_STATES;
    return s;
}

/* ------------------------------------------------------------------------------ Co-Simulation */

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    if (!m->model_exchange) /* never in Event Mode here */
        return bn3_fail(m, "fmi3EnterStepMode in %s: this FMU has no Event Mode in Co-Simulation (hasEventMode is "
                        "false): fmi3ExitInitializationMode enters Step Mode", MODE_NAMES[m->mode]);
    ORDER3(EnterStepMode, BN_CS_ONLY);
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime) {
    Instance *m = instance;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!m) return fmi3Error;
    double t0 = currentCommunicationPoint, h = communicationStepSize, t = t0 + h;
    char a[32], b[32];
    if (m->mode == MODE_INIT && m->init_error[0] && !m->model_exchange) /* the reason, not only the mode */
        return bn3_fail(m, "fmi3DoStep: step to t = %s s refused: %s", bn_num(a, 32, t, 10), m->init_error);
    ORDER3(DoStep, BN_CS_ONLY);
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime)
        return bn3_fail(m, "fmi3DoStep: an output argument is NULL");
    *eventHandlingNeeded = false;
    *terminateSimulation = false;
    *earlyReturn = false;
    *lastSuccessfulTime = m->t;
    if (!(h > 0.0 && h < INFINITY))
        return bn3_fail(m, "fmi3DoStep: communicationStepSize = %s s must be finite and > 0 "
                        "(currentCommunicationPoint = %s s)", bn_num(a, 32, h, 17), bn_num(b, 32, t0, 17));
    if (!isfinite(t0))
        return bn3_fail(m, "fmi3DoStep: currentCommunicationPoint = %s s must be finite", bn_num(a, 32, t0, 17));
    if (!isfinite(t))
        return bn3_fail(m, "fmi3DoStep: currentCommunicationPoint + communicationStepSize = %s + %s s is not finite",
                        bn_num(a, 32, t0, 17), bn_num(b, 32, h, 17));
    if (t > m->stop_time + 1e-9 * fmax(fabs(m->stop_time), h))
        return bn3_fail(m, "fmi3DoStep: a step to t = %s s goes beyond the stopTime %s s given to "
                        "fmi3EnterInitializationMode", bn_num(a, 32, t, 17), bn_num(b, 32, m->stop_time, 17));
    if (m->step_refused) /* a master retrying unchanged would loop forever */
        return bn3_fail(m, "fmi3DoStep: step to t = %s s refused: the inputs of the step discarded just before, "
                        "unchanged (the state is refused again whatever the step size); set the inputs or restore "
                        "an FMU state", bn_num(a, 32, t, 10));
    m->thermal_lagged = 1; /* T_eff lags over the step (thermal = true) */
    m->thermal_dt = h;
    int refused = bn_evaluate(m);
    m->thermal_lagged = 0;
    if (refused) { /* the instance as before the call: the importer may restore a state and go on */
        bn_log(m, fmi3Discard, "%s at t = %s s", m->msg, bn_num(a, 32, t, 10));
        m->step_refused = 1;
        return fmi3Discard;
    }
    m->t = t;
    *lastSuccessfulTime = t;
    return bn_warned(m);
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues) {
    (void)valueReferences; (void)nValueReferences; (void)orders; (void)values; (void)nValues;
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetOutputDerivatives, BN_CS_ONLY);
    return bn3_fail(m, "fmi3GetOutputDerivatives: not provided (maxOutputDerivativeOrder is 0)");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    (void)clockReference; (void)activationTime;
    if (!instance) return fmi3Error;
    return bn3_fail(instance, "fmi3ActivateModelPartition: this FMU has no Scheduled Execution");
}

/* ------------------------------------------------------------------------------ not provided */

static fmi3Status no_such(Instance *m, const char *call, unsigned allowed, size_t nvr, const fmi3ValueReference vr[],
                          const char *type) {
    if (!m) return fmi3Error;
    if (allowed && bn3_refused(m, call, allowed, BN_ANY_TYPE)) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    return bn3_fail(m, "%s: value reference %u is not a%s %s variable of this FMU (it has Float64, Boolean, String "
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
    return bn3_fail(instance, "fmi3EnterConfigurationMode: this FMU has no structural parameters (no Configuration "
                    "Mode)");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    if (!instance) return fmi3Error;
    return bn3_fail(instance, "fmi3ExitConfigurationMode: this FMU has no structural parameters (no Configuration "
                    "Mode)");
}
