/* The Reynolds internal (bearing_fmu/physics/solver/reynolds.py): the finite-volume solver in C
 * (reynolds_solver.c, included here so every one of its functions stays static), on the grid
 * n_theta x n_x and with the cavitation model the parameters set, for the bore compiled in
 * (model_data.h: its segments, from geometry.Geometry.segments, and the angles its wall is
 * checked at). Its memory is one block, allocated when the parameters are fixed (the end of
 * Initialization Mode) through the FMI 2.0 callbacks (FMI 3.0: calloc) and again only when a
 * reset changes the grid; freed with the instance (bn_release). Nothing is allocated per call.
 * Force and Jacobian equal the Python internal's (tests/test_native_reynolds.py: bit for bit
 * in every state compared, within 1e-10 relative the tolerance). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BN_PART reynolds /* its functions' names in an FMU of several internals */
#define BN_PART_REYNOLDS 1 /* its part of model_data.h */
#include "bearing_native.h"
#include "model_data.h"
#include "reynolds_solver.h"

static const double RS_EDGE_DATA[] = RS_EDGES;
static const int RS_FIXED_DATA[] = RS_SEG_FIXED;
static const double RS_SUPPLY_DATA[] = RS_SEG_SUPPLY;
static const double RS_WALL_A_DATA[] = RS_WALL_A; /* (-sin, cos) / H0 at the film's sample angles */
static const double RS_WALL_B_DATA[] = RS_WALL_B;

static void *rs_allocate(Instance *m, size_t bytes) { return m->allocate(1, bytes); }

static void rs_release_block(Instance *m, void *p) {
    if (p) m->release(p);
}

static int rs_build(Instance *m, int n_theta, int n_x);

void bn_release(Instance *m) {
    rs_release_block(m, m->work.block);
    m->work.block = NULL;
    m->work.solver = NULL;
    m->work.block_bytes = 0;
}

int bn_setup(Instance *m) {
    int n_theta = BN_INT_OPTION(m, N_THETA), n_x = BN_INT_OPTION(m, N_X);
    /* 0: the default grid (the registry's: reynolds.DEFAULT_N_THETA x DEFAULT_N_X) */
    if (n_theta == 0) n_theta = RS_DEFAULT_N_THETA;
    if (n_x == 0) n_x = RS_DEFAULT_N_X;
    if (n_theta < 8 || n_theta > RS_MAX_CELLS || n_x < 2 || n_x % 2 || n_x > RS_MAX_CELLS) {
        snprintf(m->msg, sizeof m->msg, "Reynolds: the grid n_theta = %d, n_x = %d: n_theta an integer >= 8, n_x an "
                 "even integer >= 2, both at most %d (0: the default %d x %d)", n_theta, n_x, RS_MAX_CELLS,
                 RS_DEFAULT_N_THETA, RS_DEFAULT_N_X);
        return 1;
    }
    size_t bytes = rs_bytes(n_theta, n_x);
    if (m->work.block_bytes != bytes) {
        bn_release(m);
        m->work.block = rs_allocate(m, bytes + 16);
        if (!m->work.block) {
            snprintf(m->msg, sizeof m->msg, "Reynolds: out of memory for the %d x %d grid (%.0f kB)", n_theta, n_x,
                     (bytes + 16) / 1024.0);
            return 1;
        }
        m->work.block_bytes = bytes;
    }
    return rs_build(m, n_theta, n_x);
}

/* The solver for the parameters as set, in the block (16-byte aligned inside it: the callbacks
 * promise only what malloc does): 0, or 1 with the reason in m->msg */
static int rs_build(Instance *m, int n_theta, int n_x) {
    void *mem = (void *)(((size_t)m->work.block + 15) / 16 * 16);
    int mode = strcmp(m->eff[S_OPT_CAVITATION], "gumbel") == 0 ? 0 : 1;
    char why[400];
    m->work.solver = rs_create(mem, n_theta, n_x, mode, 1, m->r[VR_D], m->r[VR_L], m->r[VR_CR], m->r[VR_MU],
                               RS_NSEG, RS_EDGE_DATA, RS_FIXED_DATA, RS_SUPPLY_DATA, RS_LOBES, RS_PRELOAD,
                               RS_LOBE_OFFSET, RS_LOBE_ANGLE, why, sizeof why);
    if (!m->work.solver || (RS_GROOVE_WIDTH > 0.0 && rs_set_lands((rs_solver *)m->work.solver, RS_GROOVE_WIDTH,
                                                                   RS_GROOVE_SUPPLY, why, sizeof why))) {
        m->work.solver = NULL;
        snprintf(m->msg, sizeof m->msg, "Reynolds: %s (%s)", why, RS_BORE_TEXT);
        return 1;
    }
    return 0;
}

/* how far the journal closes the film: the eccentricity ratio of the full bore, the closure
 * (geometry.Geometry.closure: the largest (e . u) / (CR H0) over the film) of another */
static double rs_closure(double y, double z, double CR) {
    if (RS_NSEG == 0) return hypot(y, z) / CR;
    double big = -INFINITY;
    int k;
    for (k = 0; k < RS_NWALL; k++) {
        double v = y * RS_WALL_A_DATA[k] + z * RS_WALL_B_DATA[k];
        if (v > big) big = v;
    }
    return big / CR;
}

int bn_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood) {
    rs_solver *s = (rs_solver *)m->work.solver;
    double CR = m->r[VR_CR];
    char a[32], b[32], c[32], d[32], e[32];
    *ood = 0;
    double closure = rs_closure(x[0], x[1], CR);
    if (!(closure < 1.0)) { /* registry.wall_error's words */
        double eps = hypot(x[0], x[1]) / CR;
        if (RS_NSEG == 0)
            snprintf(m->msg, sizeof m->msg, "eccentricity ratio %s >= 1: the journal (y = %s m, z = %s m) is at or "
                     "beyond the bearing wall (CR = %s m)", bn_num(a, 32, eps, 4), bn_num(b, 32, x[0], 4),
                     bn_num(c, 32, x[1], 4), bn_num(d, 32, CR, 4));
        else
            snprintf(m->msg, sizeof m->msg, "film closure %s >= 1: the journal (y = %s m, z = %s m, eccentricity "
                     "ratio %s) is at or beyond the bore (%s; CR = %s m)", bn_num(a, 32, closure, 4),
                     bn_num(b, 32, x[0], 4), bn_num(c, 32, x[1], 4), bn_num(d, 32, eps, 4), RS_BORE_TEXT,
                     bn_num(e, 32, CR, 4));
        return 1;
    }
    int status = rs_call(s, x[0], x[1], x[2], x[3], x[4], want_jac);
    if (status == RS_NOT_CONVERGED) {
        snprintf(m->msg, sizeof m->msg, "Reynolds: active-set iteration did not converge in %d steps at y = %s m, "
                 "z = %s m, vy = %s m/s, vz = %s m/s, omega = %s rad/s", s->max_iter, bn_num(a, 32, x[0], 17),
                 bn_num(b, 32, x[1], 17), bn_num(c, 32, x[2], 17), bn_num(d, 32, x[3], 17), bn_num(e, 32, x[4], 17));
        return 1;
    }
    if (status == RS_OVERFLOW) { /* registry.overflow_error: the input that drives it, as a rate of the film */
        static const char *const names[5] = {"y", "z", "vy", "vz", "omega"};
        static const char *const units[5] = {"m", "m", "m/s", "m/s", "rad/s"};
        double size[5] = {fabs(x[0]) / CR, fabs(x[1]) / CR, 2.0 * fabs(x[2]) / CR, 2.0 * fabs(x[3]) / CR, fabs(x[4])};
        int i, big = 0;
        for (i = 1; i < 5; i++)
            if (size[i] > size[big]) big = i;
        snprintf(m->msg, sizeof m->msg, "bearing input %s = %s %s is too large: it puts the film %s beyond the "
                 "floating-point range", names[big], bn_num(a, 32, x[big], 17), units[big],
                 want_jac ? "force and its Jacobian" : "force");
        return 1;
    }
    F[0] = s->F[0];
    F[1] = s->F[1];
    if (want_jac) { /* row-major 2 x 4 over (y, z, vy, vz) */
        J[0] = s->dFq[0]; J[1] = s->dFq[1]; J[2] = s->dFv[0]; J[3] = s->dFv[1];
        J[4] = s->dFq[2]; J[5] = s->dFq[3]; J[6] = s->dFv[2]; J[7] = s->dFv[3];
        dw[0] = s->dFw[0];
        dw[1] = s->dFw[1];
    }
    return 0;
}

#if BN_FLOWS_REYNOLDS
int bn_film(Instance *m, const double x[5], double out[5]) {
    rs_film_report((rs_solver *)m->work.solver, x[0], x[1], x[2], x[3], x[4], out);
    return 0;
}
#endif

/* the film's peak pressure and its angle (p [Pa], theta [rad]) of the field bn_eval just solved */
void bn_peak(Instance *m, double out[2]) { rs_peak_pressure((rs_solver *)m->work.solver, out); }

/* n_theta, n_x and cavitation are no Real options: nothing to differentiate */
void bn_option_derivative(Instance *m, const double x[5], int k, double dF[2], double dJ[8]) {
    int i;
    (void)m;
    (void)x;
    (void)k;
    dF[0] = dF[1] = 0.0;
    for (i = 0; i < 8; i++) dJ[i] = 0.0;
}

/* F = mu R L (R / CR)^2 G(L/D, q/CR, v/CR, omega): dF along ln(L/D) at a fixed scale is L dF/dL
 * at a fixed D less F (the scale's own part; J likewise), L dF/dL by central differences of the
 * solver rebuilt in its own memory at L (1 +- 1e-6) (nothing allocated; ~1e-9 relative) */
int bn_shape_derivative(Instance *m, const double x[5], int want_jac, double dF[2], double dJ[8]) {
    const rs_solver *s = (const rs_solver *)m->work.solver;
    int N = s->N, n_x = s->n_x, i, ood, bad = 0;
    double L = m->r[VR_L], h = 1e-6, F0[2], J0[8], Fp[2], Jp[8], Fm[2], Jm[8], dw[2];
    if (bn_eval(m, x, want_jac, F0, J0, dw, &ood)) return 1;
    m->r[VR_L] = L * (1.0 + h);
    bad = rs_build(m, N, n_x) || bn_eval(m, x, want_jac, Fp, Jp, dw, &ood);
    m->r[VR_L] = L * (1.0 - h);
    bad = bad || rs_build(m, N, n_x) || bn_eval(m, x, want_jac, Fm, Jm, dw, &ood);
    m->r[VR_L] = L;
    if (rs_build(m, N, n_x) || bad) return 1;
    for (i = 0; i < 2; i++) dF[i] = (Fp[i] - Fm[i]) / (2.0 * h) - F0[i];
    for (i = 0; want_jac && i < 8; i++) dJ[i] = (Jp[i] - Jm[i]) / (2.0 * h) - J0[i];
    return 0;
}
