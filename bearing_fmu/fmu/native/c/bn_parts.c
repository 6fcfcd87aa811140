/* An FMU of several internals (model_config.h: BN_PARTS > 1, BN_PART_LIST): each internal's file
 * defines its functions under its own name (<id>_<internal>_bn_setup ...: bearing_native.h
 * BN_FN), and this file the ones the model layer calls, dispatching on the parameter internal as
 * it counts (m->eff, the String or its enumeration). Taylor's domain_action = fallback evaluates
 * the Reynolds internal of the same FMU (bn_fallback.c), prepared here with Taylor's when set. */
#include <stdio.h>
#include <string.h>

#include "bearing_native.h"

/* the plain names from here on: this file defines them */
#undef bn_setup
#undef bn_eval
#undef bn_option_derivative
#undef bn_release
#undef bn_shape_derivative
#undef bn_film
#undef bn_peak
#define PART_FN(p, name) BN_NAME(BN_ID, BN_NAME(p, name))

#define DECLARE(p, bearing, speed)                                                                              \
    BN_HIDDEN int PART_FN(p, bn_setup)(Instance * m);                                                          \
    BN_HIDDEN int PART_FN(p, bn_eval)(Instance * m, const double x[5], int want_jac, double F[2], double J[8], \
                                      double dw[2], int *ood);                                                 \
    BN_HIDDEN void PART_FN(p, bn_option_derivative)(Instance * m, const double x[5], int k, double dF[2],      \
                                                    double dJ[8]);                                             \
    BN_HIDDEN void PART_FN(p, bn_release)(Instance * m);
BN_PART_LIST(DECLARE)
#if BN_HOLDS_REYNOLDS
BN_HIDDEN void PART_FN(reynolds, bn_peak)(Instance *m, double out[2]);
BN_HIDDEN int PART_FN(reynolds, bn_shape_derivative)(Instance *m, const double x[5], int want_jac, double dF[2],
                                                     double dJ[8]);
#endif

/* the film report of each internal with the film's flows (model_config.h BN_FLOWS_<NAME>), NULL for
 * the others: their why (BN_FLOW_WHY_<name>) refuses thermal = true at initialisation */
#if BN_FLOWS_REYNOLDS
BN_HIDDEN int PART_FN(reynolds, bn_film)(Instance *m, const double x[5], double out[5]);
#define FILM_reynolds PART_FN(reynolds, bn_film)
#else
#define FILM_reynolds NULL
#endif
#if BN_FLOWS_MAP
BN_HIDDEN int PART_FN(map, bn_film)(Instance *m, const double x[5], double out[5]);
#define FILM_map PART_FN(map, bn_film)
#else
#define FILM_map NULL
#endif
#if BN_FLOWS_TAYLOR
BN_HIDDEN int PART_FN(taylor, bn_film)(Instance *m, const double x[5], double out[5]);
#define FILM_taylor PART_FN(taylor, bn_film)
#else
#define FILM_taylor NULL
#endif
#define FILM_linear NULL

typedef struct {
    const char *name;
    int (*setup)(Instance *m);
    int (*eval)(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood);
    void (*option_derivative)(Instance *m, const double x[5], int k, double dF[2], double dJ[8]);
    void (*release)(Instance *m);
    int bearing, speed; /* does its force depend on the bearing (1 by the scale law, 2 and on L/D), the speed */
    int (*film)(Instance *m, const double x[5], double out[5]);
    const char *film_why;
} Part;

#define ENTRY(p, bearing, speed)                                                                                  \
    {#p, PART_FN(p, bn_setup), PART_FN(p, bn_eval), PART_FN(p, bn_option_derivative), PART_FN(p, bn_release), \
     bearing, speed, FILM_##p, BN_FLOW_WHY_##p},
static const Part PARTS[BN_PARTS] = {BN_PART_LIST(ENTRY)};

/* the internal as set (checked against BN_INTERNALS when set: one of the parts) */
static const Part *active(const Instance *m) {
    for (int i = 0; i < BN_PARTS; i++)
        if (strcmp(m->eff[S_INTERNAL], PARTS[i].name) == 0) return &PARTS[i];
    return &PARTS[0];
}

void bn_force_depends(const Instance *m, int *bearing, int *speed) {
    const Part *p = active(m);
    *bearing = p->bearing;
    *speed = p->speed;
}

int BN_NAME(BN_ID, bn_setup)(Instance *m) {
    if (active(m)->setup(m)) return 1;
#if BN_HOLDS_REYNOLDS
    if (bn_fallback_set(m) && PART_FN(reynolds, bn_setup)(m)) {
        char why[sizeof m->msg];
        memcpy(why, m->msg, sizeof why);
        snprintf(m->msg, sizeof m->msg, "domain_action = 'fallback': %.1900s", why);
        return 1;
    }
#endif
    return 0;
}

int BN_NAME(BN_ID, bn_eval)(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2],
                            int *ood) {
    return active(m)->eval(m, x, want_jac, F, J, dw, ood);
}

void BN_NAME(BN_ID, bn_option_derivative)(Instance *m, const double x[5], int k, double dF[2], double dJ[8]) {
    active(m)->option_derivative(m, x, k, dF, dJ);
}

#if BN_HOLDS_REYNOLDS
/* the peak pressure of the Reynolds internal's field; the others have none (0, as the Python FMU's) */
void BN_NAME(BN_ID, bn_peak)(Instance *m, double out[2]) {
    if (strcmp(active(m)->name, "reynolds") == 0) {
        PART_FN(reynolds, bn_peak)(m, out);
        return;
    }
    out[0] = out[1] = 0.0;
}
#endif

const char *bn_film_why(const Instance *m) {
    return active(m)->film ? "" : active(m)->film_why;
}

#if BN_FILM_FLOW
int BN_NAME(BN_ID, bn_film)(Instance *m, const double x[5], double out[5]) {
    const Part *p = active(m);
    if (p->film) return p->film(m, x, out);
    snprintf(m->msg, sizeof m->msg, "the film report of internal = '%s': %.1900s", p->name, p->film_why);
    return 1;
}
#endif

void BN_NAME(BN_ID, bn_release)(Instance *m) {
    for (int i = 0; i < BN_PARTS; i++) PARTS[i].release(m);
}

#if BN_BEARING_IN_FORCE == 2
int BN_NAME(BN_ID, bn_shape_derivative)(Instance *m, const double x[5], int want_jac, double dF[2], double dJ[8]) {
    return PART_FN(reynolds, bn_shape_derivative)(m, x, want_jac, dF, dJ);
}
#endif
