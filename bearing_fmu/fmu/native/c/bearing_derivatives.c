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
 *   P_loss, Q_side, T_eff, mu_eff   the thermal ports, off: 0, 0, along T_supply, along mu; with
 *                  thermal = true no derivative is given (refused, naming why)
 * The states a difference evaluates are evaluated quietly: no log line, no excursion counted. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bearing_values.h"

/* the internal's F, J at x, quietly (a derivative's evaluation is no state of the run): 0, or 1 (m->msg) */
static int eval_quiet(Instance *m, const double x[5], double F[2], double J[8], double dw[2]) {
    int ood, refused;
    Work saved = m->work;
    m->work.quiet = 1;
    m->mute = 1;
    refused = bn_eval(m, x, 1, F, J, dw, &ood);
    m->mute = 0;
    m->work = saved;
    for (int i = 0; !refused && i < 8; i++)
        if (!isfinite(J[i])) {
            snprintf(m->msg, sizeof m->msg, "the %s internal returned a non-finite tangent", m->eff[S_INTERNAL]);
            refused = 1;
        }
    return refused;
}

/* dJ: the derivative of the analytic Jacobian J along the input direction dx, by central
 * differences (one-sided next to a state the internal refuses): the force has no second
 * derivative in closed form. 0, or 1 (m->msg) when neither side evaluates. */
static int jacobian_derivative(Instance *m, const double x[5], const double J[8], const double dx[5], double dJ[8]) {
    double w = fmax(fabs(x[4]), 1.0), CR = m->r[VR_CR];
    double scale[5] = {CR, CR, w * CR, w * CR, w};
    double big = 0.0, xp[5], xm[5], Fp[2], Fm[2], Jp[8], Jm[8], wp[2], wm[2];
    for (int i = 0; i < 5; i++) big = fmax(big, fabs(dx[i]) / scale[i]);
    for (int i = 0; i < 8; i++) dJ[i] = 0.0;
    if (big == 0.0) return 0;
    double h = 1e-6 / big;
    for (int i = 0; i < 5; i++) {
        xp[i] = x[i] + h * dx[i];
        xm[i] = x[i] - h * dx[i];
    }
    int bad_p = eval_quiet(m, xp, Fp, Jp, wp), bad_m = eval_quiet(m, xm, Fm, Jm, wm);
    if (bad_p && bad_m) return 1;
    for (int i = 0; i < 8; i++)
        dJ[i] = bad_p ? (J[i] - Jm[i]) / h : bad_m ? (Jp[i] - J[i]) / h : (Jp[i] - Jm[i]) / (2.0 * h);
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

int bn_derivative(Instance *m, const double d[N_REAL], int with_kc, double out[N_OUTPUTS_REAL]) {
    double x[5], F[2], J[8], dw[2], dJ[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (int i = 0; i < N_OUTPUTS_REAL; i++) out[i] = 0.0;
    for (int i = 0; i < 5; i++) {
        x[i] = m->r[i];
        if (!isfinite(x[i])) {
            char v[32];
            snprintf(m->msg, sizeof m->msg, "bearing input %s = %s is not finite", bn_real_name(i),
                     bn_num(v, sizeof v, x[i], 17));
            return 1;
        }
    }
    if (m->b[B_THERMAL]) { /* the heat balance's derivatives (P_loss, Q_side, T_eff's lag) are not ported */
        snprintf(m->msg, sizeof m->msg, "directional derivatives with thermal = true are not provided by this native "
                 "FMU (the film temperature's dependence on the inputs is not differentiated): use thermal = false "
                 "or differences of doStep results");
        return 1;
    }
    if (eval_quiet(m, x, F, J, dw)) return 1;
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
        if (jacobian_derivative(m, x, J, d_eff, dJ)) {
            char msg[sizeof m->msg];
            snprintf(msg, sizeof msg, "%s", m->msg);
            snprintf(m->msg, sizeof m->msg, "K, C cannot be differentiated here: the internal refuses the states on "
                     "both sides (%.1900s)", msg);
            return 1;
        }
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
    static const int jac_index[8] = {0, 1, 4, 5, 2, 3, 6, 7}; /* Kyy Kyz Kzy Kzz Cyy Cyz Czy Czz in J */
    for (int i = 0; tangent && i < 8; i++) out[VR_KYY - VR_FY + i] = -dJ[jac_index[i]]; /* Lund's sign */
    return 0;
}

double bn_thermal_derivative(const Instance *m, const double d[N_REAL], int vr) {
    if (vr == VR_DER_T_EFF) return 0.0; /* the thermal model off: T_eff holds */
    if (vr == VR_T_EFF) return STATE_T_EFF(m) ? d[VR_T_EFF] : d[VR_T_SUPPLY];
    if (vr == VR_MU_EFF) return d[VR_MU];
    return 0.0; /* P_loss, Q_side: not computed (0) */
}
