/* The FMI 2.0 bearing FMU's FMU states, directional derivatives, Co-Simulation and Model
 * Exchange, over the model layer (bearing_values.h: bn_state_*, bn_derivative, bn_evaluate,
 * bn_outputs). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_layer.h"

#define STATE_TAG "bearing-native/1"

/* ------------------------------------------------------------------------------ FMU state */
/* the model layer's BnState (the time, the inputs and outputs), tagged with this build's GUID */

static void *alloc_state(Instance *m) {
    return m->cb.allocateMemory ? m->cb.allocateMemory(1, sizeof(BnState)) : calloc(1, sizeof(BnState));
}

static int valid_state(const void *s) { return bn_state_valid(s, STATE_TAG, BN_GUID); }

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    Instance *m = c;
    if (!m || !FMUstate) return fmi2Error;
    BnState *s = *FMUstate;
    if (!s) {
        s = alloc_state(m);
        if (!s) return bn2_fail(m, "getFMUstate: out of memory");
        *FMUstate = s;
    }
    bn_state_save(m, s, STATE_TAG, BN_GUID);
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    Instance *m = c;
    if (!m) return fmi2Error;
    if (!valid_state(FMUstate))
        return bn2_fail(m, "setFMUstate: not a %s state of this FMU; the instance keeps its state", STATE_TAG);
    bn_state_restore(m, FMUstate);
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    Instance *m = c;
    if (!m || !FMUstate) return fmi2Error;
    if (*FMUstate) {
        /* no tag left: a stale copy of the pointer used soon after is likely refused, not restored
         * (not a guarantee: the memory is freed; the master's own pointer is set to NULL below) */
        memset(((BnState *)*FMUstate)->tag, 0, sizeof ((BnState *)*FMUstate)->tag);
        if (m->cb.freeMemory)
            m->cb.freeMemory(*FMUstate);
        else
            free(*FMUstate);
    }
    *FMUstate = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
    Instance *m = c;
    if (!m || !size) return fmi2Error;
    if (!valid_state(FMUstate)) return bn2_fail(m, "serializedFMUstateSize: not a %s state of this FMU", STATE_TAG);
    *size = sizeof(BnState);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size) {
    Instance *m = c;
    char why[200];
    if (!m) return fmi2Error;
    if (bn_state_serialize(FMUstate, (unsigned char *)serializedState, size, STATE_TAG, BN_GUID, why, sizeof why))
        return bn2_fail(m, "serializeFMUstate: %s", why);
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate) {
    Instance *m = c;
    BnState s;
    char why[200];
    if (!m || !FMUstate) return fmi2Error;
    if (bn_state_deserialize((const unsigned char *)serializedState, size, &s, STATE_TAG, BN_GUID, why, sizeof why))
        return bn2_fail(m, "deSerializeFMUstate: %s", why);
    if (!*FMUstate && !(*FMUstate = alloc_state(m))) return bn2_fail(m, "deSerializeFMUstate: out of memory");
    *(BnState *)*FMUstate = s;
    return fmi2OK;
}

/* ------------------------------------------------------------------------------ derivatives */

/* FMI 2.0 directional derivatives of every Real output with respect to the inputs (any mode
 * where getDirectionalDerivative is allowed) and, in Initialization Mode, to the Real parameters:
 * the model layer's bn_derivative (bearing_derivatives.c says how each is computed). */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    Instance *m = c;
    char a[32], why[512];
    double d[N_REAL], out[N_DERIVATIVES];
    int with_kc = 0;
    if (!m) return fmi2Error;
    ORDER(getDirectionalDerivative, BN_ANY_TYPE);
    if (m->mode == MODE_INIT && bn_prepare(m))
        return bn2_fail(m, "getDirectionalDerivative in Initialization Mode: %s", m->init_error);
    for (int k = 0; k < N_REAL; k++) d[k] = 0.0;
    for (size_t j = 0; j < nKnown; j++) {
        fmi2ValueReference k = vKnown_ref[j];
        if (bn_check_known(m, k, why, sizeof why)) return bn2_fail(m, "getDirectionalDerivative: %s", why);
        if (!isfinite(dvKnown[j]))
            return bn2_fail(m, "getDirectionalDerivative: dvKnown[%lu] = %s (the direction in %s) must be finite",
                            (unsigned long)j, bn_num(a, sizeof a, dvKnown[j], 17), bn_real_name((int)k));
        d[k] += dvKnown[j];
    }
    for (size_t i = 0; i < nUnknown; i++) {
        fmi2ValueReference u = vUnknown_ref[i];
        if (u >= (fmi2ValueReference)N_REAL || !bn_is_output_real((int)u))
            return bn2_fail(m, "getDirectionalDerivative: unknown %s (value reference %u) is not a Real output",
                            u < (fmi2ValueReference)N_REAL ? bn_real_name((int)u) : "?", u);
        with_kc |= u >= VR_KYY && u <= VR_CZZ;
    }
    if (bn_derivative(m, d, with_kc, out)) {
        bn_log(m, fmi2Discard, "getDirectionalDerivative: %s", m->msg);
        return fmi2Discard;
    }
    for (size_t i = 0; i < nUnknown; i++) dvUnknown[i] = BN_OUTPUT_DERIVATIVE(vUnknown_ref[i], d, out);
    return fmi2OK;
}

/* ------------------------------------------------------------------------------ FMI: Co-Simulation */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setRealInputDerivatives, BN_CS_ONLY);
    return bn2_fail(m, "setRealInputDerivatives: not supported (canInterpolateInputs is false)");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getRealOutputDerivatives, BN_CS_ONLY);
    return bn2_fail(m, "getRealOutputDerivatives: not supported (maxOutputDerivativeOrder is 0)");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Instance *m = c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!m) return fmi2Error;
    double t0 = currentCommunicationPoint, h = communicationStepSize, t = t0 + h;
    char a[32], b[32];
    if (m->mode == MODE_INIT && m->init_error[0] && m->type != fmi2ModelExchange) /* the reason, not only the mode */
        return bn2_fail(m, "doStep: step to t = %s s refused: %s", bn_num(a, 32, t, 10), m->init_error);
    ORDER(doStep, BN_CS_ONLY);
    if (!(h > 0.0 && h < INFINITY))
        return bn2_fail(m, "doStep: communicationStepSize = %s s must be finite and > 0 (currentCommunicationPoint = "
                        "%s s)",
                        bn_num(a, 32, h, 17), bn_num(b, 32, t0, 17));
    if (!isfinite(t0))
        return bn2_fail(m, "doStep: currentCommunicationPoint = %s s must be finite", bn_num(a, 32, t0, 17));
    if (!isfinite(t))
        return bn2_fail(m, "doStep: currentCommunicationPoint + communicationStepSize = %s + %s s is not finite",
                        bn_num(a, 32, t0, 17), bn_num(b, 32, h, 17));
    if (m->step_refused) /* a master retrying unchanged (fmpy's simulate_fmu) would loop forever */
        return bn2_fail(m, "doStep: step to t = %s s refused: the inputs of the step discarded just before, "
                        "unchanged (the state is refused again whatever the step size); set the inputs or restore "
                        "an FMU state", bn_num(a, 32, t, 10));
    m->thermal_lagged = 1; /* T_eff lags over the step (thermal = true) */
    m->thermal_dt = h;
    int refused = bn_evaluate(m);
    m->thermal_lagged = 0;
    if (refused) {
        /* not fmi2Terminated: the same step from a restored state, or with other inputs, can succeed */
        bn_log(m, fmi2Discard, "%s at t = %s s", m->msg, bn_num(a, 32, t, 10));
        m->step_refused = 1;
        return fmi2Discard;
    }
    m->t = t;
    return bn_warned(m);
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    if (!c) return fmi2Error;
    return bn2_fail(c, "cancelStep: doStep never runs asynchronously here");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getStatus, BN_CS_ONLY);
    return bn2_fail(m, "getStatus: status kind %d is not provided (doStep never returns fmi2Pending)", (int)s);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getRealStatus, BN_CS_ONLY);
    if (s != fmi2LastSuccessfulTime) return bn2_fail(m, "getRealStatus: status kind %d is not provided", (int)s);
    *value = m->t;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getIntegerStatus, BN_CS_ONLY);
    return bn2_fail(m, "getIntegerStatus: status kind %d is not provided", (int)s);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getBooleanStatus, BN_CS_ONLY);
    if (s != fmi2Terminated) return bn2_fail(m, "getBooleanStatus: status kind %d is not provided", (int)s);
    *value = m->terminated ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getStringStatus, BN_CS_ONLY);
    return bn2_fail(m, "getStringStatus: status kind %d is not provided", (int)s);
}

/* ------------------------------------------------------------------------------ FMI: Model Exchange */
/* No event indicators; the outputs are a direct feedthrough of the inputs, computed when read
 * (the model layer's bn_outputs). Continuous states: none, or (a build whose internal has the film's flows and
 * whose bearing an oil law: BN_N_STATES 1) T_eff, whose derivative is the heat balance's rate with
 * thermal = true and 0 (T_eff holds) with thermal = false. */

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(enterEventMode, BN_ME_ONLY);
    m->mode = MODE_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(newDiscreteStates, BN_ME_ONLY);
    if (!info) return bn2_fail(m, "newDiscreteStates: fmi2EventInfo* is NULL");
    /* the discrete output out_of_domain takes the state's value here, at an event only */
    if (m->dirty) bn_outputs(m, "newDiscreteStates", "out_of_domain");
    if (!m->refused_state) m->b[B_OUT_OF_DOMAIN] = m->ood_now;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(enterContinuousTimeMode, BN_ME_ONLY);
    m->mode = MODE_CONTINUOUS;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(completedIntegratorStep, BN_ME_ONLY);
    /* a step event when the state crossed the fitted domain's edge: out_of_domain (discrete)
     * changes at the event that follows, never within Continuous-Time Mode */
    fmi2Status s = m->dirty ? bn_outputs(m, "completedIntegratorStep", "out_of_domain") : fmi2OK;
    if (enterEventMode) *enterEventMode = !m->refused_state && m->ood_now != m->b[B_OUT_OF_DOMAIN];
    if (terminateSimulation) *terminateSimulation = fmi2False;
    return s == fmi2Discard ? fmi2OK : s; /* the refused state was logged; the master finds it at getReal */
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setTime, BN_ME_ONLY);
    if (!isfinite(time)) {
        char a[32], b[32];
        return bn2_fail(m, "setTime: time = %s s must be finite; the instance keeps t = %s s", bn_num(a, 32, time, 17),
                        bn_num(b, 32, m->t, 17));
    }
    m->t = time;
    return fmi2OK;
}

static fmi2Status no_states(Instance *m, const char *call, unsigned allowed, size_t n, const char *what) {
    if (!m) return fmi2Error;
    if (bn_order_refused(m, call, allowed, BN_ME_ONLY)) return fmi2Error;
    if (n != 0) return bn2_fail(m, "%s: this FMU has no %s, got %lu", call, what, (unsigned long)n);
    return fmi2OK;
}
#define NO_STATES(call, n, what) no_states(c, #call, BN_ALLOW_##call, n, what)

/* the continuous states' calls: allowed here, nx the FMU's number of states (BN_N_STATES) */
static int states_refused(Instance *m, const char *call, unsigned allowed, size_t nx, const void *p) {
    if (bn_order_refused(m, call, allowed, BN_ME_ONLY)) return 1;
    if (nx != BN_N_STATES) {
        bn2_fail(m, "%s: this FMU has %d continuous state(s), got nx = %lu", call, BN_N_STATES, (unsigned long)nx);
        return 1;
    }
    if (nx && !p) {
        bn2_fail(m, "%s: the array is NULL", call);
        return 1;
    }
    return 0;
}
#define STATES_REFUSED(call, nx, p) states_refused(m, #call, BN_ALLOW_##call, nx, p)

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *m = c;
    if (!m) return fmi2Error;
    if (STATES_REFUSED(setContinuousStates, nx, x)) return fmi2Error;
    if (nx) {
        m->r[VR_T_EFF] = x[0];
        m->dirty = 1;
    }
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    Instance *m = c;
    if (!m) return fmi2Error;
    if (STATES_REFUSED(getDerivatives, nx, derivatives)) return fmi2Error;
    if (!nx) return fmi2OK;
    fmi2Status s = bn_outputs(m, "getDerivatives", "der(T_eff)");
    derivatives[0] = m->r[VR_DER_T_EFF];
    return s;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    (void)eventIndicators;
    return NO_STATES(getEventIndicators, ni, "event indicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *m = c;
    if (!m) return fmi2Error;
    if (STATES_REFUSED(getContinuousStates, nx, x)) return fmi2Error;
    if (!nx) return fmi2OK;
    fmi2Status s = m->mode == MODE_INIT ? bn_outputs(m, "getContinuousStates", "T_eff") : fmi2OK; /* its start */
    x[0] = m->r[VR_T_EFF];
    return s;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    Instance *m = c;
    if (!m) return fmi2Error;
    if (STATES_REFUSED(getNominalsOfContinuousStates, nx, x_nominal)) return fmi2Error;
    if (nx) x_nominal[0] = 1.0; /* the model description gives T_eff no nominal */
    return fmi2OK;
}
