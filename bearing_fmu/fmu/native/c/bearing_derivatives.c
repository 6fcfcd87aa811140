/* The derivatives of the native bearing FMU's Real outputs along its inputs and, in Initialization
 * Mode, its Real parameters, whatever its FMI version (the model layer: bearing_values.h; FMI 2.0:
 * fmi2GetDirectionalDerivative, FMI 3.0: fmi3GetDirectionalDerivative and
 * fmi3GetAdjointDerivative):
 *   Fy, Fz         the internal's analytic Jacobian (the same bits as the K, C outputs); along
 *                  omega the map's is analytic, the Taylor and linear models', defined at one
 *                  speed only, 0
 *   Kyy .. Czz     central differences of that Jacobian, a step of 1e-6 of each input's scale (CR
 *                  for y, z; CR |omega| for vy, vz; |omega| for omega): ~1e-9 relative; one-sided
 *                  where one side is refused (the wall, the map's edge); 0 when compute_tangent is
 *                  false (the outputs are 0 then)
 *   eccentricity, h_min   analytic (0 along the velocities and the speed; at the centre, 0)
 *   D, L, CR, mu   the map: F = S P(q/CR, v/CR, omega) with S = mu L D^3 / (8 CR^2), so a change
 *                  of the bearing is a scale and, for CR, a move of the state along (q, v); the
 *                  Reynolds solver (BN_BEARING_IN_FORCE 2): the same, and P depends on L/D too
 *                  (the map holds one L/D): its part along ln(L/D) from the internal,
 *                  bn_shape_derivative; the Taylor and linear models hold their own bearing: 0
 *                  (eccentricity, h_min follow CR)
 *   the internal's Real options   bn_option_derivative (the linear model's coefficients)
 *   P_loss, Q_side, T_eff, mu_eff, der(T_eff)   thermal = false: 0, 0, along T_supply (Model
 *                  Exchange after initialisation: along the state T_eff), along mu, 0
 * thermal = true (thermal_derivative, docs/thermal.md "Directional derivatives"): the film runs at
 * mu_eff = mu(T), so every force output is (mu_eff / mu) times the isoviscous one at the parameter
 * mu; T is the quasi-static root of T = T*(T) in Initialization Mode (dT by the implicit function
 * theorem: dT = (dT_supply + mu dg) / (1 - g dmu/dT), T* = T_supply + g mu(T)), Model Exchange's
 * state after it (a known), Co-Simulation's internal state after it (held: dT = 0). dmu/dT is the
 * oil law's, analytic; the film report's friction power and flows (in g = k P / (mu rho c_p (Q -
 * Qs / 2)) and t_res = 2 pi R CR L / Q) by central differences along the input direction with the
 * step of K, C (~1e-8 relative: the report's sums to round-off over a step of 1e-6); along the
 * Real parameters (Initialization Mode) the outputs evaluated anew at the parameters +- 1e-6 of
 * their values, central differences (~1e-6 relative: the root of the heat balance to 1e-10 K).
 * The states a difference evaluates are evaluated quietly: no log line, no excursion counted. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bearing_values.h"

/* the internal's F (and, with want_jac, J) at x, quietly (a derivative's evaluation is no state of
 * the run): 0, or 1 (m->msg) */
static int eval_quiet(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2]) {
    int ood, refused;
    Work saved = m->work;
    m->work.quiet = 1;
    m->mute = 1;
    refused = bn_eval(m, x, want_jac, F, J, dw, &ood);
    m->mute = 0;
    m->work = saved;
    for (int i = 0; want_jac && !refused && i < 8; i++)
        if (!isfinite(J[i])) {
            snprintf(m->msg, sizeof m->msg, "the %s internal returned a non-finite tangent", m->eff[S_INTERNAL]);
            refused = 1;
        }
    return refused;
}

/* the derivative from the values at x (mid) and x +- h dx (up, down): central, or one-sided when
 * a side is refused (bad[0]: up, bad[1]: down) */
static double difference(const int bad[2], double h, double mid, double up, double down) {
    return bad[0] ? (mid - down) / h : bad[1] ? (up - mid) / h : (up - down) / (2.0 * h);
}

/* dJ (non-NULL: with J, the analytic Jacobian at x) and drep (non-NULL: with rep, the film report at
 * x; thermal = true) along the input direction dx, by central differences (one-sided next to a
 * state the internal refuses): the force has no second derivative in closed form, the film
 * report no derivative. 0, or 1 (m->msg) when neither side evaluates. */
static int state_differences(Instance *m, const double x[5], const double J[8], double dJ[8], const double rep[5],
                             double drep[5], const double dx[5]) {
    double w = fmax(fabs(x[4]), 1.0), CR = m->r[VR_CR];
    double scale[5] = {CR, CR, w * CR, w * CR, w};
    double big = 0.0, xs[2][5], Fs[2][2], Js[2][8], ws[2][2], rs[2][5];
    int bad[2];
    for (int i = 0; i < 5; i++) big = fmax(big, fabs(dx[i]) / scale[i]);
    for (int i = 0; dJ && i < 8; i++) dJ[i] = 0.0;
    for (int i = 0; drep && i < 5; i++) drep[i] = 0.0;
    if (big == 0.0) return 0;
    double h = 1e-6 / big;
    for (int k = 0; k < 2; k++) {
        for (int i = 0; i < 5; i++) xs[k][i] = x[i] + (k ? -h : h) * dx[i];
        bad[k] = eval_quiet(m, xs[k], dJ != NULL, Fs[k], Js[k], ws[k]);
#if BN_FILM_FLOW
        if (drep && !bad[k]) bad[k] = bn_film(m, xs[k], rs[k]);
#endif
    }
    if (bad[0] && bad[1]) return 1;
    for (int i = 0; dJ && i < 8; i++) dJ[i] = difference(bad, h, J[i], Js[0][i], Js[1][i]);
    for (int i = 0; drep && i < 5; i++) drep[i] = difference(bad, h, rep[i], rs[0][i], rs[1][i]);
    return 0;
}

/* Model Exchange after initialisation, a build with the state T_eff: T_eff is the state */
#define STATE_T_EFF(m) (BN_N_STATES > 0 && BN_IS_ME(m) && (m)->mode != MODE_INIT)

int bn_check_known(const Instance *m, unsigned vr, char *why, size_t n) {
    const char *name = vr < (unsigned)N_REAL ? bn_real_name((int)vr) : "?";
    if (vr == VR_T_EFF && STATE_T_EFF(m)) return 0; /* the continuous state: a known of Model Exchange */
    if (vr >= (unsigned)N_REAL || bn_is_output_real((int)vr)) {
        snprintf(why, n, "known %s (value reference %u) is not an input or a Real parameter", name, vr);
        return 1;
    }
    if (vr >= VR_D && !BN_IS_INPUT(vr) && m->mode != MODE_INIT) {
        snprintf(why, n, "known %s is a parameter: " BN_FMI_TEXT " gives derivatives with respect to parameters in "
                 "Initialization Mode only", name);
        return 1;
    }
    return 0;
}

static const int jac_index[8] = {0, 1, 4, 5, 2, 3, 6, 7}; /* Kyy Kyz Kzy Kzz Cyy Cyz Czy Czz in J */

/* m->msg for a K, C that cannot be differentiated */
static int kc_refused(Instance *m) {
    char msg[sizeof m->msg];
    snprintf(msg, sizeof msg, "%s", m->msg);
    snprintf(m->msg, sizeof m->msg, "K, C cannot be differentiated here: the internal refuses the states on both "
             "sides (%.1900s)", msg);
    return 1;
}

/* thermal = false: the isoviscous film (see above) */
static int isoviscous(Instance *m, const double x[5], const double d[N_REAL], int with_kc,
                      double out[N_DERIVATIVES]) {
    double F[2], J[8], dw[2], dJ[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    if (eval_quiet(m, x, 1, F, J, dw)) return 1;
    const double *dx = d, *db = d + VR_D; /* the inputs; D, L, CR, mu */
    double CR = m->r[VR_CR];
    /* the bearing: a scale of F (S) and J (S / CR), and for CR a move along (q, v) (see above) */
    double gain = 0.0, along = 0.0;
    int bearing_in_force, speed_in_force;
    bn_force_depends(m, &bearing_in_force, &speed_in_force);
    if (bearing_in_force) {
        gain = 3.0 * db[0] / m->r[VR_D] + db[1] / m->r[VR_L] + db[3] / m->r[VR_MU];
        along = -db[2] / CR;
    }
    double d_eff[5];
    for (int i = 0; i < 4; i++) d_eff[i] = dx[i] + along * x[i];
    d_eff[4] = speed_in_force ? dx[4] : 0.0; /* a model of one speed: its force does not move with omega */
    for (int r = 0; r < 2; r++) {
        const double *row = J + 4 * r;
        out[r] = row[0] * d_eff[0] + row[1] * d_eff[1] + row[2] * d_eff[2] + row[3] * d_eff[3] + dw[r] * d_eff[4]
                 + F[r] * (gain + 2.0 * along); /* S ~ CR^-2 */
    }
    int tangent = with_kc && m->b[B_COMPUTE_TANGENT];
    if (tangent) {
        if (state_differences(m, x, J, dJ, NULL, NULL, d_eff)) return kc_refused(m);
        for (int i = 0; i < 8; i++) dJ[i] += J[i] * (gain + 3.0 * along); /* J ~ S / CR */
    }
#if BN_BEARING_IN_FORCE == 2 /* an internal of the build's (several: the largest) */
    double s_ld = db[1] / m->r[VR_L] - db[0] / m->r[VR_D]; /* d ln(L/D) */
    if (bearing_in_force == 2 && s_ld != 0.0) {
        double gF[2], gJ[8];
        if (bn_shape_derivative(m, x, tangent, gF, gJ)) return 1;
        for (int r = 0; r < 2; r++) out[r] += gF[r] * s_ld;
        for (int i = 0; tangent && i < 8; i++) dJ[i] += gJ[i] * s_ld;
    }
#endif
    for (int k = 0; k < BN_N_REAL_OPTIONS; k++)
        if (d[VR_REAL_OPTIONS + k] != 0.0) {
            double oF[2], oJ[8];
            bn_option_derivative(m, x, k, oF, oJ);
            for (int r = 0; r < 2; r++) out[r] += oF[r] * d[VR_REAL_OPTIONS + k];
            for (int i = 0; tangent && i < 8; i++) dJ[i] += oJ[i] * d[VR_REAL_OPTIONS + k];
        }
    double e = hypot(x[0], x[1]);
    double de = e > 0.0 ? (x[0] * dx[0] + x[1] * dx[1]) / e : 0.0; /* d|q| */
    out[VR_ECC - VR_FY] = de / CR - e / CR * db[2] / CR;
    out[VR_HMIN - VR_FY] = db[2] - de;
    for (int i = 0; tangent && i < 8; i++) out[VR_KYY - VR_FY + i] = -dJ[jac_index[i]]; /* Lund's sign */
    /* T_eff is T_supply (Model Exchange after initialisation: the state, holding), mu_eff mu;
     * P_loss, Q_side are not computed (0), der(T_eff) is 0 */
    out[D_T_EFF] = STATE_T_EFF(m) ? d[VR_T_EFF] : d[VR_T_SUPPLY];
    out[D_MU_EFF] = d[VR_MU];
    return 0;
}

#if BN_FILM_FLOW
/* is vr a Real parameter (a known in Initialization Mode)? */
static int real_parameter(int vr) { return vr >= VR_D && !BN_IS_INPUT(vr) && !bn_is_output_real(vr); }

/* thermal = true, along the Real parameters in d (Initialization Mode): the outputs evaluated anew
 * (bn_prepare, bn_evaluate: the quasi-static film temperature) at the parameters p +- h d, h =
 * 1e-6 of each one's value (1 for a zero) over the largest, central differences added to out; the
 * instance as before (its parameters, outputs, solver and oil). 0, or 1 (m->msg) when a side is
 * refused. */
static int parameter_differences(Instance *m, const double d[N_REAL], double out[N_DERIVATIVES]) {
    double saved[N_REAL], rows[2][N_DERIVATIVES], big = 0.0;
    int bad[2], flags[5] = {m->b[B_OUT_OF_DOMAIN], m->ood_now, m->still, m->warn_pending, m->dirty};
    memcpy(saved, m->r, sizeof saved);
    for (int k = 0; k < N_REAL; k++)
        if (real_parameter(k) && d[k] != 0.0) big = fmax(big, fabs(d[k]) / (saved[k] != 0.0 ? fabs(saved[k]) : 1.0));
    if (big == 0.0) return 0;
    double h = 1e-6 / big;
    int quiet = m->work.quiet;
    m->mute = 1;
    m->work.quiet = 1;
    for (int s = 0; s < 2; s++) {
        for (int k = 0; k < N_REAL; k++)
            if (real_parameter(k)) m->r[k] = saved[k] + (s ? -h : h) * d[k];
        int prepared = !bn_prepare(m);
        bad[s] = !prepared || bn_evaluate(m);
        if (!prepared) snprintf(m->msg, sizeof m->msg, "%.1900s", m->init_error);
        for (int i = 0; i < N_OUTPUTS_REAL; i++) rows[s][i] = m->r[VR_FY + i];
        for (int i = 0; i < 4; i++) rows[s][D_P_LOSS + i] = m->r[VR_P_LOSS + i];
        rows[s][D_DER_T_EFF] = m->r[VR_DER_T_EFF];
        memcpy(m->r, saved, sizeof saved);
    }
    char why[sizeof m->msg];
    snprintf(why, sizeof why, "%s", m->msg);
    int lost = bn_prepare(m); /* the solver and the oil of the parameters as set, again */
    m->mute = 0;
    m->work.quiet = quiet;
    m->b[B_OUT_OF_DOMAIN] = flags[0];
    m->ood_now = flags[1];
    m->still = flags[2];
    m->warn_pending = flags[3];
    m->dirty = flags[4];
    if (lost) {
        snprintf(m->msg, sizeof m->msg, "%.1900s", m->init_error);
        return 1;
    }
    if (bad[0] || bad[1]) {
        snprintf(m->msg, sizeof m->msg, "the outputs' derivative along the parameters (thermal = true: differences "
                 "of the outputs) needs the parameters on both sides of those set, refused at %s h: %.1800s",
                 bad[0] ? "+" : "-", why);
        return 1;
    }
    for (int i = 0; i < N_DERIVATIVES; i++) out[i] += (rows[0][i] - rows[1][i]) / (2.0 * h);
    return 0;
}

/* thermal = true (see above) */
static int thermal_derivative(Instance *m, const double x[5], const double d[N_REAL], int with_kc,
                              double out[N_DERIVATIVES]) {
    double F[2], J[8], dw[2], dJ[8], rep[5], drep[5], hb[8], dx[5];
    int tangent = with_kc && m->b[B_COMPUTE_TANGENT], held = m->mode != MODE_INIT, bearing_in_force, speed_in_force;
    if (eval_quiet(m, x, 1, F, J, dw) || bn_film(m, x, rep) || bn_heat_balance(m, rep, !held, hb)) return 1;
    bn_force_depends(m, &bearing_in_force, &speed_in_force);
    for (int i = 0; i < 5; i++) dx[i] = d[i];
    if (!speed_in_force) dx[4] = 0.0;
    if (state_differences(m, x, J, tangent ? dJ : NULL, rep, drep, dx)) return tangent ? kc_refused(m) : 1;
    double mu_ref = m->r[VR_MU], mu = hb[1], dmu_dT = hb[2], g = hb[3], den = hb[4], tau = hb[5], shift = hb[7];
    const ot_oil *oil = &m->oil;
    double per_mu = rep[2] / mu_ref, dper_mu = drep[2] / mu_ref, dTs = d[VR_T_SUPPLY];
    /* ot_balance_terms: g = k per_mu / den, shift = -k h A (T_supply - T_amb) / den, den = rho c_p carried + k h A */
    double dden = oil->density * oil->heat_capacity * (drep[3] - oil->outflow_share * drep[4]);
    double dg = den > 0.0 ? g * (dper_mu / per_mu - dden / den) : 0.0;
    double dexcess = oil->T_ambient > 0.0 ? dTs : 0.0; /* T_amb 0: the supply's, no excess */
    double dshift = den > 0.0 ? -(oil->rise_factor * oil->ambient_W_K * dexcess + shift * dden) / den : 0.0;
    double dstar = dTs + dshift + dg * mu;                             /* T*'s at a fixed T */
    double dT = STATE_T_EFF(m) ? d[VR_T_EFF]                           /* Model Exchange: the state, a known */
                : held ? 0.0                                           /* Co-Simulation: the step's, held */
                : dstar / (1.0 - g * dmu_dT);                          /* the root of T = T*(T) */
    double s = mu / mu_ref, dmu = dmu_dT * dT, ds = dmu / mu_ref;
    for (int r = 0; r < 2; r++) {
        const double *row = J + 4 * r;
        double dF = row[0] * dx[0] + row[1] * dx[1] + row[2] * dx[2] + row[3] * dx[3] + dw[r] * dx[4];
        out[r] = s * dF + F[r] * ds;
    }
    for (int i = 0; tangent && i < 8; i++)
        out[VR_KYY - VR_FY + i] = -(s * dJ[jac_index[i]] + J[jac_index[i]] * ds); /* Lund's sign */
    double e = hypot(x[0], x[1]), CR = m->r[VR_CR];
    double de = e > 0.0 ? (x[0] * dx[0] + x[1] * dx[1]) / e : 0.0; /* d|q| */
    out[VR_ECC - VR_FY] = de / CR;
    out[VR_HMIN - VR_FY] = -de;
    out[D_P_LOSS] = dper_mu * mu + per_mu * dmu;
    out[D_Q_SIDE] = drep[4];
    out[D_T_EFF] = dT;
    out[D_MU_EFF] = dmu;
    if (den > 0.0 && tau < INFINITY) /* der(T_eff) = (T* - T) / t_res, t_res ~ 1 / inflow; else 0 (T holds) */
        out[D_DER_T_EFF] = (dstar + g * dmu - dT) / tau + hb[6] * drep[3] / rep[3];
    for (int k = 0; k < N_REAL; k++)
        if (real_parameter(k) && d[k] != 0.0) return parameter_differences(m, d, out);
    return 0;
}
#endif

int bn_derivative(Instance *m, const double d[N_REAL], int with_kc, double out[N_DERIVATIVES]) {
    double x[5];
    for (int i = 0; i < N_DERIVATIVES; i++) out[i] = 0.0;
    for (int i = 0; i < 5; i++) {
        x[i] = m->r[i];
        if (!isfinite(x[i])) {
            char v[32];
            snprintf(m->msg, sizeof m->msg, "bearing input %s = %s is not finite", bn_real_name(i),
                     bn_num(v, sizeof v, x[i], 17));
            return 1;
        }
    }
#if BN_FILM_FLOW
    if (m->b[B_THERMAL]) return thermal_derivative(m, x, d, with_kc, out);
#endif
    return isoviscous(m, x, d, with_kc, out);
}
