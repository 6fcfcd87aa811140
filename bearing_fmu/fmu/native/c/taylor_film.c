/* The Taylor surrogate's film report (bn_film; BN_FLOWS_TAYLOR: a surrogate file with its film
 * fit, format version 2), a port of Taylor.film_report behind DomainGuard.film_report:
 *
 *   the friction in closed form of the full bore from the surrogate's own force (film_friction.h),
 *   side flow  r Q0 J_s(eps, beta),  inflow  | omega Q0 (1 + eps) / 2 - r Q0 J_i(eps, beta) |,
 *
 * Q0 = R L CR, (eps, beta, r) the state's reduced coordinates (ff_reduce: forcemap.reduced), J_s,
 * J_i the file's fitted functions over the basis eps^i t_j(beta) (surrogates.film.features; the
 * coefficients TAY_FILM_COEF, taylor_data.py). The bearing is the surrogate's (TAY_PARAMS), as the
 * Python internal's. Outside the fitted domain the report does what the force does: refused
 * beyond domain_limit, with domain_action = discard or at the wall (guard()); with warn the
 * surrogate's report (the force's evaluation warned); with fallback the Reynolds internal's report
 * (bn_fallback_film), blended with the surrogate's over the same band as the force.
 * Compiled beside internal_taylor.c when the film report is (BN_FLOWS_TAYLOR): the guard and the
 * force are that file's (taylor_internal.h), the film fit's arrays of model_data.h this one's
 * (BN_TAYLOR_FILM_UNIT). */
#include <math.h>
#include <string.h>

#define BN_PART taylor /* its functions' names in an FMU of several internals */
#define BN_PART_TAYLOR 1 /* its part of model_data.h */
#define BN_TAYLOR_FILM_UNIT 1 /* and in it the film fit's arrays */
#include "bearing_native.h"
#include "model_data.h"
#include "film_friction.h"
#include "taylor_internal.h"

#if !BN_FLOWS_TAYLOR
#error "the Taylor film report needs a surrogate file with its film fit (taylor_data.py), compiled in (BN_FLOWS_TAYLOR)"
#endif

#if TAY_FILM_NF != (TAY_FILM_DEGREE + 1) * (2 * TAY_FILM_HARMONICS + 1)
#error "TAY_FILM_NF: (degree + 1) (2 harmonics + 1) coefficients per function (surrogates.film.n_features)"
#endif

/* J[0] = J_s, J[1] = J_i at (eps, beta): each feature eps^i t_j(beta) formed as numpy forms it
 * (eps ** i, cos(m beta), sin(m beta), their product), then summed with the coefficient rows */
static void film_functions(double eps, double beta, double J[2]) {
    enum { NT = 2 * TAY_FILM_HARMONICS + 1 };
    double t[NT];
    t[0] = 1.0;
    for (int k = 1; k <= TAY_FILM_HARMONICS; k++) {
        t[2 * k - 1] = cos(k * beta);
        t[2 * k] = sin(k * beta);
    }
    J[0] = J[1] = 0.0;
    for (int i = 0; i <= TAY_FILM_DEGREE; i++) {
        double p = pow(eps, (double)i);
        for (int j = 0; j < NT; j++) {
            double f = p * t[j];
            J[0] += TAY_FILM_COEF[i * NT + j] * f;
            J[1] += TAY_FILM_COEF[TAY_FILM_NF + i * NT + j] * f;
        }
    }
}

/* Taylor.film_report at x (the guard passed): out as bn_film's (bearing_native.h) */
static int taylor_film(Instance *m, const double x[5], double out[5]) {
    double F[2], J[8], dw[2], cp, sp, a, c, jf[2];
    if (tay_eval(m, x, 0, F, J, dw)) return 1;
    const double R = 0.5 * TAY_PARAMS[0], L = TAY_PARAMS[1], CR = TAY_PARAMS[2], omega = x[4];
    double eps = ff_reduce(x, CR, 0.0, &cp, &sp, &a, &c);
    film_functions(eps, atan2(c, a), jf);
    double r = hypot(a, c), q0 = R * L * CR;
    out[0] = ff_couette(TAY_PARAMS[3], omega, R, L, CR, eps);
    out[1] = ff_pressure(x[0], x[1], F);
    out[2] = ff_power(out[0], out[1], omega, F, x[2], x[3]);
    out[3] = fabs(omega * q0 * 0.5 * (1.0 + eps) - r * q0 * jf[1]);
    out[4] = r * q0 * jf[0];
    return 0;
}

int bn_film(Instance *m, const double x[5], double out[5]) {
    int ood;
    if (tay_guard(m, x, &ood)) return 1; /* what the force refuses */
#if BN_HOLDS_REYNOLDS
    if (ood && strcmp(m->eff[S_OPT_DOMAIN_ACTION], "fallback") == 0) {
        double rey[5], tay[5], w = tay_blend_weight(tay_domain_distance(m, x[0], x[1], x[2], x[3]));
        if (bn_fallback_film(m, x, rey)) return 1;
        if (w >= 1.0) {
            memcpy(out, rey, sizeof rey);
            return 0;
        }
        if (taylor_film(m, x, tay)) return 1;
        for (int i = 0; i < 5; i++) out[i] = (1.0 - w) * tay[i] + w * rey[i];
        return 0;
    }
#endif
    return taylor_film(m, x, out);
}
