/* The native bearing FMU's thermal model (the model layer: bearing_values.h): the oil of the
 * parameters, the film's temperature at a state and the heat balance, over the oil laws and the
 * film temperature of oil_thermal.c and the internal's film report (bn_film). */
#include <stdio.h>

#include "bearing_values.h"

int bn_thermal_setup(Instance *m, char *why, size_t n) {
    const double *o = m->r + VR_OIL0;
    char reason[600];
    int me = BN_IS_ME(m);
    if (BN_OIL_LAW == OT_NONE) {
        snprintf(why, n, "thermal = true needs the oil's viscosity law: this native FMU was built from a bearing "
                 "without one; build it with --bearing FILE whose [oil] gives the law");
        return 1;
    }
    if (me && BN_N_STATES == 0) {
        snprintf(why, n, "thermal = true in Model Exchange needs T_eff as a continuous state, which this build "
                 "does not have: use Co-Simulation, or thermal = false");
        return 1;
    }
    /* a circumferential groove (the bore's last Real, circumferential_groove): all the lands' oil leaves by their
     * ends at the full rise whatever oil_outflow_share says (ports.oil_of's grooved; params.groove_problem) */
    double share = m->r[VR_GEOMETRY0 + N_GEOMETRY_REALS - 1] > 0.0 ? 0.0 : o[12];
    if (ot_oil_of(&m->oil, BN_OIL_LAW, o[0], o[1], o[2], o[3], o[4], o[5], o[6], o[7], o[8], o[9], o[10], o[11],
                  share, o[13], o[14], reason, sizeof reason)) {
        snprintf(why, n, "the oil parameters (the law %s, oil_...) do not fit together: %s",
                 BN_OIL_LAW == OT_WALTHER ? "walther" : "vogel", reason);
        return 1;
    }
    return 0;
}

/* thermal = true: the film's temperature at x, as the Python FMU (ports.thermal_state): Co-Simulation
 * and Initialization Mode quasi-static, or lagged over the step (m->thermal_lagged); Model Exchange
 * after it the state T_eff as set. out = factor mu_eff / mu, T_eff, mu_eff, P_loss, Q_side,
 * der(T_eff) (the heat balance's rate at T_eff). 0, or 1 with the reason in m->msg. */
int bn_thermal_state(Instance *m, const double x[5], double out[6]) {
#if BN_FILM_FLOW
    double rep[5], t[3], rate[3], mu = m->r[VR_MU], R = 0.5 * m->r[VR_D], CR = m->r[VR_CR], L = m->r[VR_L];
    double Ts = m->r[VR_T_SUPPLY];
    char why[700];
    if (bn_film(m, x, rep)) return 1;
    int state = BN_ME_THERMAL(m) && BN_IS_ME(m) && m->mode != MODE_INIT; /* T_eff as the integrator set it */
    if (state) {
        t[0] = m->r[VR_T_EFF];
    } else if (ot_film_temperature(&m->oil, mu, R, CR, L, rep[2], rep[3], rep[4], Ts, m->thermal_lagged,
                                   m->r[VR_T_EFF], m->thermal_dt, t, why, sizeof why)) {
        snprintf(m->msg, sizeof m->msg, "thermal model: %s", why);
        return 1;
    }
    if (ot_film_rate(&m->oil, mu, R, CR, L, rep[2], rep[3], rep[4], Ts, t[0], rate, why, sizeof why)) {
        snprintf(m->msg, sizeof m->msg, "thermal model: %s", why);
        return 1;
    }
    out[0] = rate[0] / mu;
    out[1] = t[0];
    out[2] = rate[0];
    out[3] = rep[2] * out[0];
    out[4] = rep[4];
    out[5] = rate[2];
    return 0;
#else
    (void)x;
    (void)out;
    snprintf(m->msg, sizeof m->msg, "thermal model: %s", BN_FILM_FLOW_WHY);
    return 1;
#endif
}

#if BN_FILM_FLOW
int bn_heat_balance(Instance *m, const double rep[5], int quasi, double out[8]) {
    double mu = m->r[VR_MU], R = 0.5 * m->r[VR_D], CR = m->r[VR_CR], L = m->r[VR_L], Ts = m->r[VR_T_SUPPLY];
    double t[3] = {m->r[VR_T_EFF], 0.0, 0.0}, rate[3], per_mu = rep[2] / mu;
    double carried = rep[3] - m->oil.outflow_share * rep[4], terms[3] = {0.0, 0.0, 0.0}; /* 0: T* = T_supply */
    char why[700];
    if ((quasi && ot_film_temperature(&m->oil, mu, R, CR, L, rep[2], rep[3], rep[4], Ts, 0, Ts, 0.0, t, why,
                                      sizeof why))
        || ot_film_rate(&m->oil, mu, R, CR, L, rep[2], rep[3], rep[4], Ts, t[0], rate, why, sizeof why)) {
        snprintf(m->msg, sizeof m->msg, "thermal model: %s", why);
        return 1;
    }
    out[0] = t[0];
    out[1] = rate[0];
    out[2] = ot_dmu_dT(&m->oil, t[0]);
    if (per_mu > 0.0 && carried > 0.0) ot_balance_terms(&m->oil, per_mu, carried, Ts, terms);
    out[3] = terms[0];
    out[4] = terms[2];
    out[5] = rate[1];
    out[6] = rate[2];
    out[7] = terms[1];
    return 0;
}
#endif

