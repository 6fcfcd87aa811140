/* The model layer's side of every FMI call (bearing_calls.h says what each answers), for the FMI
 * 2.0 and the FMI 3.0 layer alike. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bearing_calls.h"

#if BN_FMI3
#include "fmi3_config.h"
#define SEED_NAME "seed"
#define EXIT_PREFIX "fmi3ExitInitializationMode: "
#else
#define SEED_NAME "dvKnown"
#define EXIT_PREFIX "" /* the Python FMU's words: "bearing FMU initialisation failed: ..." */
#endif

/* ------------------------------------------------------------------------------ instances and modes */

Instance *bn_instance_new(const char *name, int model_exchange, int logging_on,
                          int (*emit)(Instance *, bn_status, char *), void *(*allocate)(size_t, size_t),
                          void (*release)(void *)) {
    if (!allocate || !release) {
        allocate = calloc;
        release = free;
    }
    Instance *m = allocate(1, sizeof(Instance));
    if (!m) return NULL;
    memset(m, 0, sizeof *m);
    m->allocate = allocate;
    m->release = release;
    m->emit = emit;
    m->model_exchange = model_exchange;
    m->logging_on = logging_on != 0;
    snprintf(m->name, sizeof m->name, "%s", name ? name : "");
    bn_reset(m);
    bn_live_add(m);
    return m;
}

void bn_instance_free(Instance *m, const char *call) {
    if (!bn_live_remove(m)) { /* freed already (or never ours): its memory is not touched */
        fprintf(stderr, "bearing FMU: %s(%p): not a live instance of this FMU (freed already?); nothing done\n", call,
                (void *)m);
        fflush(stderr);
        return;
    }
    bn_release(m); /* what the internal allocated (reynolds: the solver's memory) */
    m->release(m);
}

bn_status bn_start_time(Instance *m, const char *call, double start, int stop_defined, double stop) {
    char a[32], b[32];
    if (!isfinite(start)) return bn_fail(m, "%s: startTime = %s s must be finite", call, bn_num(a, 32, start, 17));
    if (stop_defined && !(start <= stop && stop < INFINITY))
        return bn_fail(m, "%s: stopTime = %s s must be finite and >= startTime = %s s", call,
                       bn_num(a, 32, stop, 17), bn_num(b, 32, start, 17));
    m->t = start;
#if BN_FMI3 /* FMI 2.0's stopTime is a hint: a master may step past it */
    m->stop_time = stop_defined ? stop : INFINITY;
#endif
    return BN_OK;
}

bn_status bn_enter_init(Instance *m) {
    m->mode = MODE_INIT;
    return BN_OK;
}

bn_status bn_exit_init(Instance *m, const char *call) {
    (void)call;
    if (bn_prepare(m)) return bn_fail(m, EXIT_PREFIX "%s", m->init_error);
    bn_show_choices(m); /* both the String and its enumeration show the choice that counts */
    /* outputs at the start time from the initial inputs, when they can be evaluated (still in
     * Initialization Mode: T_eff quasi-static, Model Exchange's state starts there): a master
     * may set the inputs only before the first step, so a refused state is no initialisation
     * error, but a warning (docs/fmu.md, "What each status means") */
    int refused = bn_evaluate(m);
    m->mode = m->model_exchange ? MODE_EVENT : MODE_STEP;
    if (refused) {
        bn_log(m, BN_WARNING, "outputs at the start time left at their start values: %s", m->msg);
        m->warn_pending = 1;
        m->dirty = 1;
    }
    return bn_warned(m);
}

bn_status bn_terminate(Instance *m) {
    m->mode = MODE_TERMINATED;
    bn_log_excursions(m);
    return BN_OK;
}

bn_status bn_reset(Instance *m) {
    bn_set_starts(m);
    m->stop_time = INFINITY;
    m->mode = MODE_INSTANTIATED;
    return BN_OK;
}

/* ------------------------------------------------------------------------------ getting values */

/* the outputs for a get: none before Initialization Mode (initial = calculated: no value yet) */
static bn_status outputs(Instance *m, const char *call, const char *name) {
    if (m->mode == MODE_INSTANTIATED)
        return bn_fail(m, "%s %s in Instantiated: an output has no value before Initialization Mode (initial = "
                       "calculated)", call, name);
    return bn_outputs(m, call, name);
}

bn_status bn_get_reals(Instance *m, const char *call, const unsigned vr[], size_t n, double values[]) {
    bn_status status = BN_OK;
    int computed = 0;
    for (size_t i = 0; i < n; i++) {
#if BN_FMI3
        if (vr[i] == BN3_VR_TIME) {
            values[i] = m->t;
            continue;
        }
#endif
        if (vr[i] >= (unsigned)N_REAL)
            return bn_fail(m, "%s: value reference %u is not a " BN_REAL_TYPE " variable of this FMU", call, vr[i]);
        if (bn_is_output_real((int)vr[i]) && !computed) {
            computed = 1;
            bn_status s = outputs(m, call, bn_real_name((int)vr[i]));
            if (s == BN_ERROR) return s;
            if (s > status) status = s;
        }
        values[i] = m->r[vr[i]];
    }
    return status;
}

bn_status bn_get_int(Instance *m, const char *call, unsigned vr, long long *value) {
    if (vr < VR_INT0 || vr >= VR_INT_PARAM0 + N_INT)
        return bn_fail(m, "%s: value reference %u is not an " BN_INT_TYPE " variable of this FMU", call, vr);
    *value = vr >= VR_INT_PARAM0 ? m->n[vr - VR_INT_PARAM0] : m->e[vr - VR_INT0];
    return BN_OK;
}

bn_status bn_get_bool(Instance *m, const char *call, unsigned vr, int *value) {
    bn_status status = BN_OK;
    if (vr < VR_BOOL0 || vr >= VR_BOOL0 + N_BOOL)
        return bn_fail(m, "%s: value reference %u is not a Boolean variable of this FMU", call, vr);
    int k = (int)(vr - VR_BOOL0);
    if (k == B_OUT_OF_DOMAIN) /* a discrete output: in Continuous-Time Mode, the value of the last event */
        status = outputs(m, call, "out_of_domain");
    if (status != BN_ERROR) *value = m->b[k] != 0;
    return status;
}

bn_status bn_get_strings(Instance *m, const char *call, const unsigned vr[], size_t n, const char *values[]) {
    for (size_t i = 0; i < n; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING)
            return bn_fail(m, "%s: value reference %u is not a String variable of this FMU", call, vr[i]);
        values[i] = m->s[vr[i] - VR_STRING0];
    }
    return BN_OK;
}

/* ------------------------------------------------------------------------------ setting values */

/* a parameter after initialisation (variability fixed): refused (1, logged), else 0 */
static int parameter_fixed(Instance *m, const char *call, const char *name, const char *keeps) {
    if (m->mode == MODE_INSTANTIATED || m->mode == MODE_INIT) return 0;
    bn_fail(m, "%s: parameter %s is fixed after initialisation (variability fixed); it keeps %s", call, name, keeps);
    return 1;
}

/* a parameter refused alone: remembered, so that exitInitializationMode fails until a valid one is set */
static bn_status refuse_parameter(Instance *m, int slot, const char *call, const char *why, const char *name,
                                  const char *keeps) {
    m->refused[slot] = 1;
    snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
    return bn_fail(m, "%s: %s; %s keeps %s", call, why, name, keeps);
}

bn_status bn_set_reals(Instance *m, const char *call, const unsigned vr[], size_t n, const double values[]) {
    bn_status status = BN_OK;
    char a[32], why[512];
    for (size_t i = 0; i < n; i++) {
        unsigned k = vr[i];
        if (BN_IS_INPUT(k)) { /* inputs: any finite value (a state the internal refuses: at the step) */
            if (!isfinite(values[i])) {
                status = bn_fail(m, "%s: input %s = %s is not finite; it keeps %s", call, bn_real_name((int)k),
                                 bn_num(a, sizeof a, values[i], 17), bn_num(why, sizeof why, m->r[k], 17));
                continue;
            }
            m->r[k] = values[i];
            m->dirty = 1;
            continue;
        }
#if BN_FMI3
        if (k == BN3_VR_TIME) {
            status = bn_fail(m, "%s: time is the independent variable: fmi3EnterInitializationMode, fmi3SetTime "
                             "(Model Exchange) and fmi3DoStep (Co-Simulation) set it", call);
            continue;
        }
#endif
        if (k >= (unsigned)N_REAL) {
            status = bn_fail(m, "%s: value reference %u is not a " BN_REAL_TYPE " variable of this FMU", call, k);
            continue;
        }
        if (bn_is_output_real((int)k)) {
            status = bn_fail(m, "%s: %s is an output and cannot be set", call, bn_real_name((int)k));
            continue;
        }
        bn_num(a, sizeof a, m->r[k], 17);
        if (parameter_fixed(m, call, bn_real_name((int)k), a)) {
            status = BN_ERROR;
            continue;
        }
        if (bn_check_real((int)k, values[i], why, sizeof why)) {
            status = refuse_parameter(m, (int)k, call, why, bn_real_name((int)k), a);
            continue;
        }
        m->refused[k] = 0;
        m->r[k] = values[i];
    }
    return status;
}

bn_status bn_set_integer(Instance *m, const char *call, unsigned vr, long long value) {
    char why[512], keeps[32];
    if (vr < VR_INT0 || vr >= VR_INT_PARAM0 + N_INT)
        return bn_fail(m, "%s: value reference %u is not an " BN_INT_TYPE " variable of this FMU", call, vr);
    if (vr >= VR_INT_PARAM0) { /* groove_count, lobes: the bore, checked against the data's at initialisation */
        int k = (int)(vr - VR_INT_PARAM0);
        snprintf(keeps, sizeof keeps, "%d", m->n[k]);
        if (parameter_fixed(m, call, bn_int_name(k), keeps)) return BN_ERROR;
        if (bn_set_int(m, k, value, why, sizeof why))
            return bn_fail(m, "%s: %s; %s keeps %s", call, why, bn_int_name(k), keeps);
        return BN_OK;
    }
    int j = (int)(vr - VR_INT0), slot = N_REAL + N_BOOL + N_STRING + j;
    snprintf(keeps, sizeof keeps, "%d", m->e[j]);
    if (parameter_fixed(m, call, bn_enum_name(j), keeps)) return BN_ERROR;
    /* an enumeration's value outside int (FMI 3.0's Int64): refused as any other unknown value */
    int v = value > INT_MAX || value < INT_MIN ? INT_MIN : (int)value;
    if (bn_check_enum(j, v, why, sizeof why)) return refuse_parameter(m, slot, call, why, bn_enum_name(j), keeps);
    m->refused[slot] = 0;
    m->e[j] = v;
    return BN_OK;
}

bn_status bn_set_bool(Instance *m, const char *call, unsigned vr, int value) {
    if (vr < VR_BOOL0 || vr >= VR_BOOL0 + N_BOOL)
        return bn_fail(m, "%s: value reference %u is not a Boolean variable of this FMU", call, vr);
    int k = (int)(vr - VR_BOOL0);
    if (k == B_OUT_OF_DOMAIN) return bn_fail(m, "%s: out_of_domain is an output and cannot be set", call);
    if (parameter_fixed(m, call, BN_BOOL_NAMES[k], m->b[k] ? BN_TRUE_TEXT : BN_FALSE_TEXT)) return BN_ERROR;
    m->b[k] = value != 0;
    return BN_OK;
}

bn_status bn_set_strings(Instance *m, const char *call, const unsigned vr[], size_t n, const char *const values[]) {
    bn_status status = BN_OK;
    char why[512], out[STRING_MAX], keeps[STRING_MAX + 2];
    for (size_t i = 0; i < n; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING) {
            status = bn_fail(m, "%s: value reference %u is not a String variable of this FMU", call, vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_STRING0), slot = N_REAL + N_BOOL + k;
        snprintf(keeps, sizeof keeps, "'%s'", m->s[k]);
        if (parameter_fixed(m, call, bn_string_name(k), keeps)) {
            status = BN_ERROR;
            continue;
        }
        if (bn_check_string(k, values[i] ? values[i] : "", out, why, sizeof why)) {
            status = refuse_parameter(m, slot, call, why, bn_string_name(k), keeps);
            continue;
        }
        m->refused[slot] = 0;
        snprintf(m->s[k], STRING_MAX, "%s", out);
    }
    return status;
}

/* ------------------------------------------------------------------------------ derivatives */

/* every Real output along the inputs (in any mode the calling sequence allows) and, in
 * Initialization Mode, the Real parameters: the model layer's bn_derivative (bearing_derivatives.c
 * says how each is computed). The adjoint sum_i seed_i dU_i/dk for each known k is made of the
 * directional derivatives along each known. */
bn_status bn_derivatives(Instance *m, const char *call, int adjoint, const unsigned unknowns[], size_t n_unknowns,
                         const unsigned knowns[], size_t n_knowns, const double seed[], size_t n_seed,
                         double sensitivity[], size_t n_sensitivity) {
    char a[32], why[512];
    double d[N_REAL], out[N_DERIVATIVES];
    int with_kc = 0;
    if (n_seed != (adjoint ? n_unknowns : n_knowns) || n_sensitivity != (adjoint ? n_knowns : n_unknowns))
        return bn_fail(m, "%s: nSeed = %lu and nSensitivity = %lu for %lu unknowns and %lu knowns (scalars: the "
                       "seed has one value per %s, the sensitivity per %s)", call, (unsigned long)n_seed,
                       (unsigned long)n_sensitivity, (unsigned long)n_unknowns, (unsigned long)n_knowns,
                       adjoint ? "unknown" : "known", adjoint ? "known" : "unknown");
    if (m->mode == MODE_INIT && bn_prepare(m)) return bn_fail(m, "%s in Initialization Mode: %s", call, m->init_error);
    for (size_t j = 0; j < n_knowns; j++) {
#if BN_FMI3
        if (knowns[j] == BN3_VR_TIME)
            return bn_fail(m, "%s: known time (value reference %u): no output depends on time", call, knowns[j]);
#endif
        if (bn_check_known(m, knowns[j], why, sizeof why)) return bn_fail(m, "%s: %s", call, why);
    }
    for (size_t i = 0; i < n_unknowns; i++) {
        if (unknowns[i] < (unsigned)N_REAL && BN_IS_PAD_REAL((int)unknowns[i]))
            return bn_fail(m, "%s: unknown %s: the pads' derivatives along the inputs are not provided (the force's, "
                           "K's and C's are)", call, bn_real_name((int)unknowns[i]));
        if (unknowns[i] < (unsigned)N_REAL && BN_IS_PEAK((int)unknowns[i]))
            return bn_fail(m, "%s: unknown %s: the peak pressure's derivatives are not provided (the force's, K's and "
                           "C's are)", call, bn_real_name((int)unknowns[i]));
        if (unknowns[i] >= (unsigned)N_REAL || !bn_is_output_real((int)unknowns[i]))
            return bn_fail(m, "%s: unknown %s (value reference %u) is not a " BN_REAL_TYPE " output of this FMU", call,
                           unknowns[i] < (unsigned)N_REAL ? bn_real_name((int)unknowns[i]) : "?", unknowns[i]);
        with_kc |= unknowns[i] >= VR_KYY && unknowns[i] <= VR_CZZ;
    }
    for (size_t k = 0; k < n_seed; k++)
        if (!isfinite(seed[k]))
            return bn_fail(m, "%s: " SEED_NAME "[%lu] = %s (the %s %s) must be finite", call, (unsigned long)k,
                           bn_num(a, sizeof a, seed[k], 17), adjoint ? "weight of" : "direction in",
                           bn_real_name((int)(adjoint ? unknowns[k] : knowns[k])));
    for (int k = 0; k < N_REAL; k++) d[k] = 0.0;
    if (!adjoint) { /* the direction in the knowns, then each unknown along it */
        for (size_t j = 0; j < n_knowns; j++) d[knowns[j]] += seed[j];
        if (bn_derivative(m, d, with_kc, out)) {
            bn_log(m, BN_DISCARD, "%s: %s", call, m->msg);
            return BN_DISCARD;
        }
        for (size_t i = 0; i < n_unknowns; i++) sensitivity[i] = BN_OUTPUT_DERIVATIVE(unknowns[i], d, out);
        return BN_OK;
    }
    for (size_t j = 0; j < n_knowns; j++) { /* adjoint: for each known, sum_i seed_i dU_i/dknown */
        double sum = 0.0;
        d[knowns[j]] = 1.0;
        if (bn_derivative(m, d, with_kc, out)) {
            bn_log(m, BN_DISCARD, "%s: %s", call, m->msg);
            return BN_DISCARD;
        }
        for (size_t i = 0; i < n_unknowns; i++) sum += seed[i] * BN_OUTPUT_DERIVATIVE(unknowns[i], d, out);
        d[knowns[j]] = 0.0;
        sensitivity[j] = sum;
    }
    return BN_OK;
}

/* ------------------------------------------------------------------------------ Co-Simulation */

/* the inputs a step is taken at (the journal state, T_supply), compared bit for bit */
static void step_inputs(const Instance *m, double v[N_INPUTS + 1]) {
    memcpy(v, m->r, N_INPUTS * sizeof *v);
    v[N_INPUTS] = m->r[VR_T_SUPPLY];
}

/* the internal set is memoryless (catalogue.py) and thermal = false: the outputs follow the inputs
 * alone, so a step may start at any currentCommunicationPoint (the vendor annotation Memoryless) */
static int memoryless(const Instance *m) {
    char word[STRING_MAX + 3];
    snprintf(word, sizeof word, " %s ", m->eff[S_INTERNAL]);
    return !m->b[B_THERMAL] && strstr(BN_MEMORYLESS, word) != NULL;
}

bn_status bn_do_step(Instance *m, const char *call, unsigned allowed, double t0, double h, double *t_done) {
    double t = t0 + h;
    char a[32], b[32];
    if (m->mode == MODE_INIT && m->init_error[0] && !m->model_exchange) /* the reason, not only the mode */
        return bn_fail(m, "%s: step to t = %s s refused: %s", call, bn_num(a, 32, t, 10), m->init_error);
    if (bn_order_refused(m, call, allowed, BN_CS_ONLY)) return BN_ERROR;
    *t_done = m->t;
    if (!(h > 0.0 && h < INFINITY))
        return bn_fail(m, "%s: communicationStepSize = %s s must be finite and > 0 (currentCommunicationPoint = %s s)",
                       call, bn_num(a, 32, h, 17), bn_num(b, 32, t0, 17));
    if (!isfinite(t0))
        return bn_fail(m, "%s: currentCommunicationPoint = %s s must be finite", call, bn_num(a, 32, t0, 17));
    if (!isfinite(t))
        return bn_fail(m, "%s: currentCommunicationPoint + communicationStepSize = %s + %s s is not finite", call,
                       bn_num(a, 32, t0, 17), bn_num(b, 32, h, 17));
    if (t > m->stop_time + 1e-9 * fmax(fabs(m->stop_time), h))
        return bn_fail(m, "%s: a step to t = %s s goes beyond the stopTime %s s given to "
                       "fmi3EnterInitializationMode", call, bn_num(a, 32, t, 17), bn_num(b, 32, m->stop_time, 17));
    /* where the last step ended (or the start time): a step from elsewhere would skip or repeat time
     * the FMU's state (T_eff, out_of_domain, Taylor's excursions, Reynolds's warm start) went through;
     * the memoryless internals with thermal = false declare any point allowed (docs/fmu.md) */
    if (!memoryless(m) && fabs(t0 - m->t) > 1e-9 * fmax(1.0, fabs(m->t)) + 1e-6 * h)
        return bn_fail(m, "%s: currentCommunicationPoint = %s s is not where the last step ended (t = %s s; the "
                       "start time before the first step): restore an FMU state to step from another time", call,
                       bn_num(a, 32, t0, 12), bn_num(b, 32, m->t, 12));
    double now[N_INPUTS + 1];
    step_inputs(m, now);
    /* no fmi2Terminated after a discard (other inputs or a restore can go on), so a master that
     * retries with the same inputs (fmpy's simulate_fmu sets them again) would loop forever */
    if (m->step_refused && memcmp(now, m->refused_inputs, sizeof now) == 0)
        return bn_fail(m, "%s: step to t = %s s refused: the step from t = %s s was discarded and the inputs are "
                       "unchanged (the state is refused again whatever the step size); set other inputs or restore "
                       "an FMU state", call, bn_num(a, 32, t, 10), bn_num(b, 32, m->refused_t, 10));
    m->thermal_lagged = 1; /* T_eff lags over the step (thermal = true) */
    m->thermal_dt = h;
    m->step_h = h; /* the pads' states are advanced over it (internal_tilting_pad.c) */
    int refused = bn_evaluate(m);
    m->thermal_lagged = 0;
    m->step_h = 0.0;
    if (refused) {
        /* the instance as before the call, not terminated: the same step from a restored state,
         * or with other inputs, can succeed */
        bn_log(m, BN_DISCARD, "%s at t = %s s", m->msg, bn_num(a, 32, t, 10));
        m->step_refused = 1;
        memcpy(m->refused_inputs, now, sizeof now);
        m->refused_t = t0;
        return BN_DISCARD;
    }
    m->step_refused = 0;
    if (BN_N_PADS) bn_pads_accept(m, h); /* the step's end is the pads' state */
    m->t = t;
    *t_done = t;
    return bn_warned(m);
}

/* ------------------------------------------------------------------------------ Model Exchange */
/* No event indicators; the outputs are a direct feedthrough of the inputs, computed when read
 * (bn_outputs). Continuous states: none, or (a build whose internal has the film's flows and whose
 * bearing an oil law: BN_N_STATES 1) T_eff, whose derivative is the heat balance's rate with
 * thermal = true and 0 (T_eff holds) with thermal = false. A refused state is logged once and
 * the get of an output answers BN_DISCARD; the calls that change or end a mode answer BN_OK. */

static bn_status not_discarded(bn_status s) { return s == BN_DISCARD ? BN_OK : s; }

bn_status bn_enter_event_mode(Instance *m) {
    m->mode = MODE_EVENT;
    if (!m->refused_state) m->b[B_OUT_OF_DOMAIN] = m->ood_now; /* a discrete output takes its value at the event */
    return BN_OK;
}

bn_status bn_discrete_states(Instance *m, const char *call) {
    bn_status s = bn_outputs(m, call, "out_of_domain"); /* in Event Mode it takes the state's value */
    if (!m->refused_state) m->b[B_OUT_OF_DOMAIN] = m->ood_now;
    return not_discarded(s);
}

bn_status bn_enter_continuous_mode(Instance *m, const char *call) {
    /* out_of_domain of the inputs set in Event Mode, before it holds */
    bn_status s = bn_outputs(m, call, "out_of_domain");
    m->mode = MODE_CONTINUOUS;
    return not_discarded(s);
}

bn_status bn_completed_step(Instance *m, const char *call, int *enter_event) {
    bn_status s = bn_outputs(m, call, "out_of_domain");
    /* a step event where the state crossed the fitted domain's edge: out_of_domain (discrete)
     * changes at the event that follows, never within Continuous-Time Mode */
    *enter_event = !m->refused_state && m->ood_now != m->b[B_OUT_OF_DOMAIN];
    return not_discarded(s);
}

bn_status bn_set_time(Instance *m, const char *call, double time) {
    char a[32], b[32];
    if (!isfinite(time))
        return bn_fail(m, "%s: time = %s s must be finite; the instance keeps t = %s s", call,
                       bn_num(a, 32, time, 17), bn_num(b, 32, m->t, 17));
    /* beyond stopTime too: a variable-step integrator steps past it and interpolates back (CVode),
     * and nothing here depends on time */
    m->t = time;
    return BN_OK;
}

bn_status bn_no_states(Instance *m, const char *call, size_t n, const char *what) {
    if (n != 0) return bn_fail(m, "%s: this FMU has no %s, got %lu", call, what, (unsigned long)n);
    return BN_OK;
}

/* the continuous states' array: n the FMU's number of states (BN_N_STATES), not NULL */
static int states_refused(Instance *m, const char *call, size_t n, const void *p) {
    if (n != BN_NX) {
        bn_fail(m, "%s: this FMU has %d continuous state(s), got %lu", call, BN_NX, (unsigned long)n);
        return 1;
    }
    if (n && !p) {
        bn_fail(m, "%s: the array is NULL", call);
        return 1;
    }
    return 0;
}

/* T_eff (BN_N_STATES), then the pads' tilts (and rates): VR_PAD0 .., their derivatives the next
 * BN_N_PAD_STATES pad Reals (bearing_native.h) */
bn_status bn_set_states(Instance *m, const char *call, const double x[], size_t n) {
    if (states_refused(m, call, n, x)) return BN_ERROR;
    if (BN_N_STATES) m->r[VR_T_EFF] = x[0];
    for (int i = 0; i < BN_N_PAD_STATES; i++) m->r[VR_PAD0 + i] = x[BN_N_STATES + i];
    if (n) m->dirty = 1;
    return BN_OK;
}

bn_status bn_get_states(Instance *m, const char *call, double x[], size_t n) {
    if (states_refused(m, call, n, x)) return BN_ERROR;
    if (!n) return BN_OK;
    bn_status s = m->mode == MODE_INIT ? bn_outputs(m, call, BN_N_STATES ? "T_eff" : "pad_tilt_1") : BN_OK; /* its start */
    if (BN_N_STATES) x[0] = m->r[VR_T_EFF];
    for (int i = 0; i < BN_N_PAD_STATES; i++) x[BN_N_STATES + i] = m->r[VR_PAD0 + i];
    return s;
}

bn_status bn_get_state_derivatives(Instance *m, const char *call, double dx[], size_t n) {
    if (states_refused(m, call, n, dx)) return BN_ERROR;
    if (!n) return BN_OK;
    bn_status s = bn_outputs(m, call, BN_N_STATES ? "der(T_eff)" : "der(pad_tilt_1)");
    if (BN_N_STATES) dx[0] = m->r[VR_DER_T_EFF];
    for (int i = 0; i < BN_N_PAD_STATES; i++) dx[BN_N_STATES + i] = m->r[VR_PAD0 + BN_N_PADS + i];
    return s;
}

bn_status bn_get_nominals(Instance *m, const char *call, double x[], size_t n) {
    if (states_refused(m, call, n, x)) return BN_ERROR;
    if (BN_N_STATES) x[0] = 1.0; /* the model description gives T_eff no nominal */
#if BN_N_PAD_STATES
    static const double pad_nominal[BN_N_PAD_STATES] = BN_PAD_NOMINALS; /* the pads' (model description) */
    for (int i = 0; i < BN_N_PAD_STATES; i++) x[BN_N_STATES + i] = pad_nominal[i];
#endif
    return BN_OK;
}
