/* Directional and adjoint derivatives of the FMI 3.0 bearing FMU: every Float64 output (Fy, Fz,
 * eccentricity, h_min, K.., C.., the thermal ports') along the inputs y, z, vy, vz, omega, T_supply, and in Initialization Mode
 * along the Float64 parameters too (D, L, CR, mu, the internal's Real options): the model layer's
 * bn_derivative (bearing_derivatives.c says how each is computed), the FMI 2.0 FMU's code. The
 * adjoint derivative sum_i seed_i dU_i/dk for each known k is made of the directional derivatives
 * along each known. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fmi3_layer.h"

static fmi3Status derivatives(Instance *m, const char *call, int adjoint, const fmi3ValueReference unknowns[],
                              size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns,
                              const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    char a[32], why[512];
    double d[N_REAL], out[N_DERIVATIVES];
    int with_kc = 0;
    if (nSeed != (adjoint ? nUnknowns : nKnowns) || nSensitivity != (adjoint ? nKnowns : nUnknowns))
        return bn3_fail(m, "%s: nSeed = %lu and nSensitivity = %lu for %lu unknowns and %lu knowns (scalars: the "
                        "seed has one value per %s, the sensitivity per %s)", call, (unsigned long)nSeed,
                        (unsigned long)nSensitivity, (unsigned long)nUnknowns, (unsigned long)nKnowns,
                        adjoint ? "unknown" : "known", adjoint ? "known" : "unknown");
    if (m->mode == MODE_INIT && bn_prepare(m)) return bn3_fail(m, "%s in Initialization Mode: %s", call, m->init_error);
    for (size_t j = 0; j < nKnowns; j++) {
        if (knowns[j] == BN3_VR_TIME)
            return bn3_fail(m, "%s: known time (value reference %u): no output depends on time", call, knowns[j]);
        if (bn_check_known(m, knowns[j], why, sizeof why)) return bn3_fail(m, "%s: %s", call, why);
    }
    for (size_t i = 0; i < nUnknowns; i++) {
        if (unknowns[i] >= (fmi3ValueReference)N_REAL || !bn_is_output_real((int)unknowns[i]))
            return bn3_fail(m, "%s: unknown %s (value reference %u) is not a Float64 output of this FMU", call,
                            unknowns[i] < (fmi3ValueReference)N_REAL ? bn_real_name((int)unknowns[i]) : "?",
                            unknowns[i]);
        with_kc |= unknowns[i] >= VR_KYY && unknowns[i] <= VR_CZZ;
    }
    for (size_t k = 0; k < nSeed; k++)
        if (!isfinite(seed[k]))
            return bn3_fail(m, "%s: seed[%lu] = %s must be finite", call, (unsigned long)k,
                            bn_num(a, sizeof a, seed[k], 17));
    for (int k = 0; k < N_REAL; k++) d[k] = 0.0;
    if (!adjoint) { /* the direction in the knowns, then each unknown along it */
        for (size_t j = 0; j < nKnowns; j++) d[knowns[j]] += seed[j];
        if (bn_derivative(m, d, with_kc, out)) {
            bn_log(m, fmi3Discard, "%s: %s", call, m->msg);
            return fmi3Discard;
        }
        for (size_t i = 0; i < nUnknowns; i++) sensitivity[i] = BN_OUTPUT_DERIVATIVE(unknowns[i], d, out);
        return fmi3OK;
    }
    for (size_t j = 0; j < nKnowns; j++) { /* adjoint: for each known, sum_i seed_i dU_i/dknown */
        double sum = 0.0;
        d[knowns[j]] = 1.0;
        int refused = bn_derivative(m, d, with_kc, out);
        if (refused) {
            bn_log(m, fmi3Discard, "%s: %s", call, m->msg);
            return fmi3Discard;
        }
        for (size_t i = 0; i < nUnknowns; i++) sum += seed[i] * BN_OUTPUT_DERIVATIVE(unknowns[i], d, out);
        d[knowns[j]] = 0.0;
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
