/* Taylor's domain_action = fallback in an FMU of several internals that holds the Reynolds one
 * (bearing_native.h: bn_fallback_eval, bn_fallback_film): the Reynolds internal's force and film
 * report, called by the Taylor internal; bn_parts.c prepares it with Taylor's (bn_fallback_set).
 * A file of its own, so that the dispatch (bn_parts.c, which calls the internals) and the Taylor
 * internal (which calls this) do not call each other. */
#include <stdio.h>
#include <string.h>

#include "bearing_native.h"

#undef bn_eval /* the Reynolds internal's own names (bn_parts.c defines the plain ones) */
#undef bn_film
#define PART_FN(p, name) BN_NAME(BN_ID, BN_NAME(p, name))
#if BN_HOLDS_REYNOLDS
BN_HIDDEN int PART_FN(reynolds, bn_eval)(Instance *m, const double x[5], int want_jac, double F[2], double J[8],
                                         double dw[2], int *ood);
#endif
#if BN_FLOWS_REYNOLDS
BN_HIDDEN int PART_FN(reynolds, bn_film)(Instance *m, const double x[5], double out[5]);
#endif

/* Taylor's fallback: the surrogate's bearing and the grid and cavitation as set, prepared with it */
int bn_fallback_set(const Instance *m) {
#if BN_HOLDS_TAYLOR && BN_HOLDS_REYNOLDS
    return strcmp(m->eff[S_INTERNAL], "taylor") == 0 && strcmp(m->eff[S_OPT_DOMAIN_ACTION], "fallback") == 0;
#else
    (void)m;
    return 0;
#endif
}

int bn_fallback_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2]) {
#if BN_HOLDS_REYNOLDS
    int ood = 0;
    if (!bn_fallback_set(m) || !m->work.solver) {
        snprintf(m->msg, sizeof m->msg, "domain_action = 'fallback': the Reynolds internal was not prepared");
        return 1;
    }
    return PART_FN(reynolds, bn_eval)(m, x, want_jac, F, J, dw, &ood);
#else
    (void)x;
    (void)want_jac;
    (void)F;
    (void)J;
    (void)dw;
    snprintf(m->msg, sizeof m->msg, "domain_action = 'fallback' needs the Reynolds internal in this FMU");
    return 1;
#endif
}

#if BN_FLOWS_TAYLOR && BN_HOLDS_REYNOLDS
/* Taylor's film report outside its domain with fallback: the Reynolds field bn_fallback_eval just solved */
int bn_fallback_film(Instance *m, const double x[5], double out[5]) {
#if BN_FLOWS_REYNOLDS
    if (!bn_fallback_set(m) || !m->work.solver) {
        snprintf(m->msg, sizeof m->msg, "domain_action = 'fallback': the Reynolds internal was not prepared");
        return 1;
    }
    return PART_FN(reynolds, bn_film)(m, x, out);
#else
    (void)x;
    (void)out;
    snprintf(m->msg, sizeof m->msg, "domain_action = 'fallback': the film report of the Reynolds internal: %.1900s",
             BN_FLOW_WHY_reynolds);
    return 1;
#endif
}
#endif
