/* Directional and adjoint derivatives of the FMI 3.0 bearing FMU: every Float64 output (Fy, Fz,
 * eccentricity, h_min, K.., C..) along the inputs y, z, vy, vz, omega, at the inputs set.
 *
 *   Fy, Fz      the internal's analytic Jacobian (the same bits as the K, C outputs, and as the
 *               FMI 2.0 FMU's fmi2GetDirectionalDerivative); along omega the map's is analytic,
 *               the Taylor and linear models', defined at one speed only, are 0;
 *   eccentricity, h_min   analytic (0 along the velocities and the speed; at the centre, 0);
 *   K.., C..    central differences of that Jacobian, a step of 1e-6 of each input's scale (CR for
 *               y, z; CR |omega| for vy, vz; |omega| for omega): ~1e-9 relative; one-sided where one
 *               side is refused (the wall, the map's edge), and none along omega for a model
 *               defined at one speed (0, as its force's); 0 when compute_tangent is false (the
 *               outputs are 0 then). The difference points are evaluated quietly: no log line,
 *               no excursion counted.
 * Derivatives along the parameters (the knowns of Initialization Mode besides the inputs) are
 * not provided: fmi3Error naming the parameter. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fmi3_layer.h"

static const int KC_OF_J[8] = {0, 1, 4, 5, 2, 3, 6, 7}; /* Kyy Kyz Kzy Kzz Cyy Cyz Czy Czz <- J (row-major dF/dx) */

/* the Jacobian at x + h dx, quietly: 0, or 1 when the internal refuses that state */
static int quiet_jacobian(Instance *m, const double x[5], const double dx[5], double h, double J[8]) {
    double xp[5], F[2], dw[2];
    int ood, bad;
    for (int i = 0; i < 5; i++) xp[i] = x[i] + h * dx[i];
    Work saved = m->work;
    char msg[sizeof m->msg];
    memcpy(msg, m->msg, sizeof msg);
    m->mute = 1;
    bad = bn_eval(m, xp, 1, F, J, dw, &ood);
    m->mute = 0;
    m->work = saved;
    memcpy(m->msg, msg, sizeof msg);
    for (int i = 0; !bad && i < 8; i++) bad = !isfinite(J[i]);
    return bad;
}

/* d(K.., C..)/ds along dx at x (J0: the Jacobian there): 0, or 1 when no difference can be taken */
static int kc_along(Instance *m, const double x[5], const double J0[8], const double dx_in[5], double out[8]) {
    double dx[5], Jp[8], Jm[8], CR = m->r[VR_CR], w = fmax(fabs(x[4]), 1.0), big = 0.0;
    double scale[5] = {CR, CR, CR * w, CR * w, w};
    memcpy(dx, dx_in, sizeof dx);
    for (int pass = 0; pass < 2; pass++) {
        big = 0.0;
        for (int i = 0; i < 5; i++) big = fmax(big, fabs(dx[i]) / scale[i]);
        if (big == 0.0) {
            for (int i = 0; i < 8; i++) out[i] = 0.0;
            return 0;
        }
        double h = 1e-6 / big;
        int bp = quiet_jacobian(m, x, dx, h, Jp), bm = quiet_jacobian(m, x, dx, -h, Jm);
        if (!bp || !bm) {
            for (int i = 0; i < 8; i++) {
                double d = !bp && !bm ? (Jp[KC_OF_J[i]] - Jm[KC_OF_J[i]]) / (2.0 * h)
                           : !bp ? (Jp[KC_OF_J[i]] - J0[KC_OF_J[i]]) / h : (J0[KC_OF_J[i]] - Jm[KC_OF_J[i]]) / h;
                out[i] = -d; /* Lund's sign: K = -dF/dq, C = -dF/dv */
            }
            return 0;
        }
        if (dx[4] == 0.0) break;
        dx[4] = 0.0; /* both speeds refused: a model defined at this speed only; its K, C do not move along it */
    }
    return 1;
}

static int is_float_output(fmi3ValueReference u) { return u >= VR_FY && u < VR_D; }

static fmi3Status derivatives(Instance *m, const char *call, int adjoint, const fmi3ValueReference unknowns[],
                              size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns,
                              const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    char a[32];
    if (nSeed != (adjoint ? nUnknowns : nKnowns) || nSensitivity != (adjoint ? nKnowns : nUnknowns))
        return bn3_fail(m, "%s: nSeed = %lu and nSensitivity = %lu for %lu unknowns and %lu knowns (scalars: the "
                        "seed has one value per %s, the sensitivity per %s)", call, (unsigned long)nSeed,
                        (unsigned long)nSensitivity, (unsigned long)nUnknowns, (unsigned long)nKnowns,
                        adjoint ? "unknown" : "known", adjoint ? "known" : "unknown");
    if (m->mode == MODE_INIT && bn_prepare(m)) return bn3_fail(m, "%s in Initialization Mode: %s", call, m->init_error);
    for (size_t j = 0; j < nKnowns; j++)
        if (knowns[j] >= N_INPUTS) {
            int real = knowns[j] < (fmi3ValueReference)N_REAL, time = knowns[j] == BN3_VR_TIME;
            return bn3_fail(m, "%s: known %s (value reference %u) is not an input: the derivatives are along the "
                            "inputs y, z, vy, vz, omega%s", call,
                            real ? bn_real_name((int)knowns[j]) : time ? "time" : "?", knowns[j],
                            time ? " (no output depends on time)" : " (along a parameter: not provided)");
        }
    for (size_t i = 0; i < nUnknowns; i++)
        if (!is_float_output(unknowns[i]))
            return bn3_fail(m, "%s: unknown %s (value reference %u) is not a Float64 output of this FMU", call,
                            unknowns[i] < (fmi3ValueReference)N_REAL ? bn_real_name((int)unknowns[i]) : "?",
                            unknowns[i]);
    for (size_t k = 0; k < nSeed; k++)
        if (!isfinite(seed[k]))
            return bn3_fail(m, "%s: seed[%lu] = %s must be finite", call, (unsigned long)k,
                            bn_num(a, sizeof a, seed[k], 17));
    double x[5], F[2], J[8], dw[2];
    int ood;
    for (int i = 0; i < 5; i++) {
        x[i] = m->r[i];
        if (!isfinite(x[i])) {
            bn_log(m, fmi3Discard, "%s: bearing input %s = %s is not finite", call, bn_real_name(i),
                   bn_num(a, sizeof a, x[i], 17));
            return fmi3Discard;
        }
    }
    if (bn_eval(m, x, 1, F, J, dw, &ood)) {
        bn_log(m, fmi3Discard, "%s: %s", call, m->msg);
        return fmi3Discard;
    }
    double e = hypot(x[0], x[1]), CR = m->r[VR_CR];
    int tangent = m->b[B_COMPUTE_TANGENT];
    if (!adjoint) { /* the direction in the inputs, then each unknown along it */
        double dx[5] = {0, 0, 0, 0, 0}, kc[8];
        int have_kc = 0;
        for (size_t j = 0; j < nKnowns; j++) dx[knowns[j]] += seed[j];
        double decc = e > 0.0 ? (x[0] * dx[0] + x[1] * dx[1]) / (e * CR) : 0.0;
        for (size_t i = 0; i < nUnknowns; i++) {
            fmi3ValueReference u = unknowns[i];
            if (u == VR_FY || u == VR_FZ) {
                const double *row = J + 4 * (u - VR_FY);
                sensitivity[i] = row[0] * dx[0] + row[1] * dx[1] + row[2] * dx[2] + row[3] * dx[3]
                                 + dw[u - VR_FY] * dx[4];
            } else if (u == VR_ECC) {
                sensitivity[i] = decc;
            } else if (u == VR_HMIN) {
                sensitivity[i] = -CR * decc;
            } else if (!tangent) {
                sensitivity[i] = 0.0;
            } else {
                if (!have_kc && kc_along(m, x, J, dx, kc)) {
                    bn_log(m, fmi3Discard, "%s: K, C cannot be differentiated here: the internal refuses the states "
                           "on both sides (%s)", call, m->msg);
                    return fmi3Discard;
                }
                have_kc = 1;
                sensitivity[i] = kc[u - VR_KYY];
            }
        }
        return fmi3OK;
    }
    /* adjoint: for each known input j, sum_i seed_i dU_i/dx_j */
    for (size_t j = 0; j < nKnowns; j++) {
        int v = (int)knowns[j];
        double ej[5] = {0, 0, 0, 0, 0}, kc[8], sum = 0.0;
        int have_kc = 0;
        ej[v] = 1.0;
        for (size_t i = 0; i < nUnknowns; i++) {
            fmi3ValueReference u = unknowns[i];
            double d;
            if (u == VR_FY || u == VR_FZ)
                d = v < 4 ? J[4 * (u - VR_FY) + v] : dw[u - VR_FY];
            else if (u == VR_ECC || u == VR_HMIN)
                d = (v < 2 && e > 0.0 ? x[v] / (e * CR) : 0.0) * (u == VR_HMIN ? -CR : 1.0);
            else if (!tangent)
                d = 0.0;
            else {
                if (!have_kc && kc_along(m, x, J, ej, kc)) {
                    bn_log(m, fmi3Discard, "%s: K, C cannot be differentiated here: the internal refuses the states "
                           "on both sides (%s)", call, m->msg);
                    return fmi3Discard;
                }
                have_kc = 1;
                d = kc[u - VR_KYY];
            }
            sum += seed[i] * d;
        }
        sensitivity[j] = sum;
    }
    return fmi3OK;
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetDirectionalDerivative, BN_ANY_TYPE);
    return derivatives(m, "fmi3GetDirectionalDerivative", 0, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed,
                       sensitivity, nSensitivity);
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    Instance *m = instance;
    if (!m) return fmi3Error;
    ORDER3(GetAdjointDerivative, BN_ANY_TYPE);
    return derivatives(m, "fmi3GetAdjointDerivative", 1, unknowns, nUnknowns, knowns, nKnowns, seed, nSeed,
                       sensitivity, nSensitivity);
}
