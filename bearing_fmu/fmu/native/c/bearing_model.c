/* The native bearing FMU's model at the inputs, whatever its FMI version (the model layer:
 * bearing_values.h): the evaluation into the outputs, the outputs for a get and the list of live
 * instances (FMU states: bearing_state.c). The FMI layers (fmi2_*.c, fmi3_*.c) turn what it answers into their
 * calls' statuses (bearing_calls.c); the thermal model is bearing_thermal.c's. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bearing_values.h"

/* ------------------------------------------------------------------------------ evaluation */

int bn_evaluate(Instance *m) {
    double x[5], F[2], J[8], dw[2];
    int ood = 0;
    char a[32], b[32], c[32], d[32], e[32];
    for (int i = 0; i < 5; i++) {
        x[i] = m->r[i];
        if (!isfinite(x[i])) {
            snprintf(m->msg, sizeof m->msg, "bearing input %s = %s is not finite", bn_real_name(i),
                     bn_num(a, sizeof a, x[i], 17));
            return 1;
        }
    }
    int jac = m->b[B_COMPUTE_TANGENT];
    if (bn_eval(m, x, jac, F, J, dw, &ood)) return 1;
    double heat[6] = {1.0, m->r[VR_T_SUPPLY], m->r[VR_MU], 0.0, 0.0, 0.0}; /* thermal off: the isoviscous film */
    if (BN_N_STATES > 0 && BN_IS_ME(m) && m->mode != MODE_INIT) heat[1] = m->r[VR_T_EFF]; /* the state holds */
    if (m->b[B_THERMAL]) { /* the film at its effective viscosity: F ~ mu at a fixed state */
        if (bn_thermal_state(m, x, heat)) return 1;
        F[0] *= heat[0];
        F[1] *= heat[0];
        for (int i = 0; jac && i < 8; i++) J[i] *= heat[0];
    }
    int finite = isfinite(F[0]) && isfinite(F[1]);
    for (int i = 0; jac && i < 8; i++) finite = finite && isfinite(J[i]);
    if (!finite) {
        snprintf(m->msg, sizeof m->msg, "the %s internal returned a non-finite force or tangent at y = %s m, "
                 "z = %s m, vy = %s m/s, vz = %s m/s, omega = %s rad/s", m->eff[S_INTERNAL], bn_num(a, 32, x[0], 6),
                 bn_num(b, 32, x[1], 6), bn_num(c, 32, x[2], 6), bn_num(d, 32, x[3], 6), bn_num(e, 32, x[4], 6));
        return 1;
    }
    double eps = hypot(x[0], x[1]) / m->r[VR_CR];
    m->r[VR_FY] = F[0];
    m->r[VR_FZ] = F[1];
    m->r[VR_ECC] = eps;
    m->r[VR_HMIN] = m->r[VR_CR] * (1.0 - eps);
    m->ood_now = ood;
    if (m->mode != MODE_CONTINUOUS) m->b[B_OUT_OF_DOMAIN] = ood;
    m->r[VR_T_EFF] = heat[1];
    m->r[VR_MU_EFF] = heat[2];
    m->r[VR_P_LOSS] = heat[3];
    m->r[VR_Q_SIDE] = heat[4];
    m->r[VR_DER_T_EFF] = heat[5];
    double peak[2] = {0.0, 0.0}; /* an internal without a pressure field: 0, as the Python FMU's */
#if BN_HOLDS_REYNOLDS
    bn_peak(m, peak);
#endif
    m->r[VR_PEAK] = peak[0] * heat[0]; /* at the effective viscosity the field scales as the force does */
    m->r[VR_PEAK_ANGLE] = peak[1];
    if (BN_N_PADS) { /* the pads' Reals (internal_tilting_pad.c); a static evaluation's tilts become their state */
        memcpy(m->r + VR_PAD0, m->work.pad_out, BN_N_PAD_REALS * sizeof(double));
        if (m->mode == MODE_INIT && !m->mute) bn_pads_static(m);
    }
    if (jac) { /* Lund's sign: K = -dF/dq, C = -dF/dv */
        m->r[VR_KYY] = -J[0]; m->r[VR_KYZ] = -J[1]; m->r[VR_CYY] = -J[2]; m->r[VR_CYZ] = -J[3];
        m->r[VR_KZY] = -J[4]; m->r[VR_KZZ] = -J[5]; m->r[VR_CZY] = -J[6]; m->r[VR_CZZ] = -J[7];
    }
    /* a shaft at rest with no squeeze carries no load: most likely omega is not connected (a film fed
     * at a supply pressure carries load at rest: its force is not zero, nothing to warn) */
    int still = x[4] == 0.0 && x[2] == 0.0 && x[3] == 0.0 && F[0] == 0.0 && F[1] == 0.0;
    if (still && !m->still) {
        bn_log(m, BN_WARNING, "the force was asked at omega = 0 rad/s with no squeeze velocity (vy = vz = 0): the "
               "film carries no load, the force is zero; is the input omega connected? (warned once, until the "
               "journal moves or turns)");
        m->warn_pending = 1;
    }
    m->still = still;
    m->dirty = 0;
    return 0;
}

void bn_log_excursions(Instance *m) {
    if (m->work.excursions > 0) { /* the count of what was warned once per excursion */
        char a[32], b[32];
        bn_log(m, BN_WARNING, "terminate: the state left the surrogate's fitted domain %d time(s) in this run (each "
               "excursion warned when it began; the first at t = %s s, the last at t = %s s)", m->work.excursions,
               bn_num(a, sizeof a, m->work.excursion_t[0], 10), bn_num(b, sizeof b, m->work.excursion_t[1], 10));
    }
}

bn_status bn_warned(Instance *m) {
    bn_status s = m->warn_pending ? BN_WARNING : BN_OK;
    m->warn_pending = 0;
    return s;
}

bn_status bn_outputs(Instance *m, const char *call, const char *name) {
    int me = m->mode == MODE_EVENT || m->mode == MODE_CONTINUOUS;
    if (m->mode == MODE_INIT) {
        if (bn_prepare(m)) {
            bn_log(m, BN_ERROR, "%s %s in Initialization Mode: the outputs cannot be computed: %s", call, name,
                   m->init_error);
            return BN_ERROR;
        }
        if (bn_evaluate(m)) {
            bn_log(m, BN_ERROR, "%s %s in Initialization Mode: the outputs cannot be computed at the inputs set: %s "
                   "(set valid inputs and read again)", call, name, m->msg);
            return BN_ERROR;
        }
        return bn_warned(m);
    }
    if (me && m->dirty) {
        m->refused_state = bn_evaluate(m);
        if (m->refused_state) {
            char t[32];
            m->dirty = 0; /* until the inputs change */
            bn_log(m, BN_DISCARD, "%s at t = %s s (outputs keep their last values)", m->msg,
                   bn_num(t, sizeof t, m->t, 10));
        }
    }
    if (me && m->refused_state) return BN_DISCARD;
    return bn_warned(m);
}

/* ------------------------------------------------------------------------------ live instances */

/* fmi2FreeInstance and fmi3FreeInstance get only a pointer: a second free of the same instance
 * would free freed memory and abort the host. So the live instances are listed (linked through
 * next_live, changed under a spin lock: importers may make and free instances on several
 * threads), and a pointer not in the list is left alone. What this cannot tell: a pointer whose
 * memory a later instantiation got again is live again; and any other call on a freed instance
 * reads freed memory, as with any FMU. */
#if defined(_MSC_VER)
#include <intrin.h>
static volatile long live_lock;
static void lock_live(void) { while (_InterlockedExchange(&live_lock, 1)) {} }
static void unlock_live(void) { _InterlockedExchange(&live_lock, 0); }
#else
static volatile char live_lock;
static void lock_live(void) { while (__atomic_test_and_set(&live_lock, __ATOMIC_ACQUIRE)) {} }
static void unlock_live(void) { __atomic_clear(&live_lock, __ATOMIC_RELEASE); }
#endif
static Instance *live;

void bn_live_add(Instance *m) {
    lock_live();
    m->next_live = live;
    live = m;
    unlock_live();
}

int bn_live_remove(Instance *m) {
    int found = 0;
    lock_live();
    for (Instance **p = &live; *p; p = &(*p)->next_live)
        if (*p == m) {
            *p = m->next_live;
            found = 1;
            break;
        }
    unlock_live();
    return found;
}
