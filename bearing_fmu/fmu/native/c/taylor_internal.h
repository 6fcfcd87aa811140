/* What the Taylor internal's film report (taylor_film.c) takes from its force (internal_taylor.c):
 * the fitted-domain guard, the surrogate's force, the domain distance and, with fallback, the
 * blend's weight. Named per internal (BN_FN: BN_PART is taylor in both files). */
#ifndef TAYLOR_INTERNAL_H
#define TAYLOR_INTERNAL_H

#include "bearing_native.h"

#define tay_guard BN_FN(tay_guard)
#define tay_eval BN_FN(tay_eval)
#define tay_domain_distance BN_FN(tay_domain_distance)
#define tay_blend_weight BN_FN(tay_blend_weight)

/* the guard at x: 0 (evaluate; *ood: outside the fitted domain), or 1 with m->msg (refused) */
BN_HIDDEN int tay_guard(Instance *m, const double x[5], int *ood);
/* the surrogate's force at x (the guard passed), as bn_eval: 0, or 1 with m->msg */
BN_HIDDEN int tay_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2]);
/* DomainGuard.distance: exact when > 0, an upper bound <= 0 inside */
BN_HIDDEN double tay_domain_distance(Instance *m, double y, double z, double vy, double vz);
#if BN_HOLDS_REYNOLDS
/* the weight of Reynolds at domain distance d (domain_action = fallback) */
BN_HIDDEN double tay_blend_weight(double d);
#endif

#endif
