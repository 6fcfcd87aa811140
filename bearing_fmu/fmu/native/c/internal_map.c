/* The force-map internal (bearing_fmu/forcemap.py, _map_kernels.py): the Reynolds force
 * reduced to G(eps, beta), tabulated and interpolated by a tensor cubic B-spline in
 * s = -ln(1 - eps) and beta (periodic), F = S r (G_r u + G_t w), S = mu R L (R / CR)^2.
 * The knots and coefficients are model_data.h (MAP_TS, MAP_TB, MAP_C); this file is a line-by-line
 * port of map_force, so the force and Jacobian equal the Python internal's to rounding.
 * States at or beyond the table's last eccentricity (MAP_EPS_MAX) are refused.
 * A grooved or partial-arc bore's map (MAP_DIMS 3, internals/groovemap.py) adds the journal's
 * attitude phi as a third, periodic axis (MAP_TP, MAP_NP): G(eps, phi, beta), a port of
 * map_kernels.map3_force; a full-bore map has MAP_DIMS 2 (or none: files generated before).
 * The film report (bn_film, BN_FLOWS_MAP: a map with its flow table, MAP_FLOWS) is map_flows.c,
 * a port of ForceMap.film_report and GroovedForceMap.film_report; the spline's evaluation, the
 * same for both, map_spline.h. A lobed bore with ambient grooves over its lobe boundaries (MAP_LOBES > 1,
 * internals/map/lobemap.py) sums the lobe arc's map over its lobes, each in its own frame (bn_eval).
 * A bore whose grooves are fed at a supply pressure p_s (MAP_DIMS 4, internals/map/supplymap.py) has
 * F = W (G_r u + G_t w), W = S r + R L p_s, G(eps, phi, beta, u) with u = R L p_s / W the fourth axis
 * (MAP_TU, MAP_NU): supply_arc_force, a port of supplykernels.map4_force; p_s is the FMU's parameter
 * supply_pressure (MAP_SUPPLY_VR), which initialisation holds at the bearing's (check_bore). */
#include <math.h>
#include <stdio.h>

#define BN_PART map /* its functions' names in an FMU of several internals */
#define BN_PART_MAP 1 /* its part of model_data.h */
#include "bearing_native.h"
#include "model_data.h"
#include "py_mod.h"
#include "map_arc.h" /* gfun, arc_force, arc_jacobian (and film_friction.h, map_spline.h) */

int bn_setup(Instance *m) {
    double D = m->r[VR_D], L = m->r[VR_L], CR = m->r[VR_CR], mu = m->r[VR_MU];
    double ld = L / D;
    if (fabs(ld - MAP_L_OVER_D) > MAP_LD_RTOL * MAP_L_OVER_D) {
        char a[32], b[32], c[32], d[32];
        snprintf(m->msg, sizeof m->msg, "force map %s is for L/D = %s, the bearing has L/D = %s (L = %s m, D = %s m): "
                 "build a map for it with `bearing-fmu map --bearing FILE -o MAP`", MAP_SOURCE,
                 bn_num(a, 32, MAP_L_OVER_D, 6), bn_num(b, 32, ld, 6), bn_num(c, 32, L, 6), bn_num(d, 32, D, 6));
        return 1;
    }
    double R = 0.5 * D;
#if MAP_LOBES > 1
    CR = map_lobe_clearance(CR); /* the lobe arc's clearance C_pad: its map's scale */
#endif
    m->work.scale = mu * R * L * pow(R / CR, 2.0); /* forcemap.scale, in its order of operations */
    return 0;
}

#if MAP_DIMS != 4
/* The map's force at x with clearance CR and scale S (the lobe arc's for a lobed bore: map_flows.c's film
 * report per lobe calls it too): returns eps, and evaluates only when eps < MAP_EPS_MAX */
#if MAP_LOBES > 1
double map_arc_force(const double x[5], double CR, double scale, int want_jac, double F[2], double J[8],
                     double dw[2]) {
#else
static double map_arc_force(const double x[5], double CR, double scale, int want_jac, double F[2], double J[8],
                            double dw[2]) {
#endif
    return arc_force(x, CR, scale, want_jac, F, J, dw);
}
#endif


#if MAP_DIMS == 4
/* g[k] = (G_k, dG_k/deps, dG_k/dphi, dG_k/dbeta, dG_k/du) of a fed-groove map: supplykernels._g4 */
static void g4(double eps, double phi, double beta, double u, double g[2][5]) {
    double s = -log1p(-eps);
    spline4(MAP_TS, MAP_TP, MAP_TB, MAP_TU, MAP_C, 2, s, phi, beta, u, g);
    double dsde = exp(s);
    for (int k = 0; k < 2; k++) g[k][1] *= dsde;
}

/* at rest (1 - u < MAP_T_MIN): out[k] = (dP_k/da, dP_k/dc), the first harmonic of the directional derivatives
 * G - G_u at u = 1 by the MAP_N_HARMONIC-point rule (supplykernels._odd_part) */
static void odd_part(double eps, double phi, double out[2][2]) {
    double g[2][5];
    for (int k = 0; k < 2; k++) out[k][0] = out[k][1] = 0.0;
    for (int j = 0; j < MAP_N_HARMONIC; j++) {
        double b = 2.0 * M_PI * j / MAP_N_HARMONIC;
        g4(eps, phi, b, 1.0, g);
        for (int k = 0; k < 2; k++) {
            double d = g[k][0] - g[k][4];
            out[k][0] += 2.0 / MAP_N_HARMONIC * cos(b) * d;
            out[k][1] += 2.0 / MAP_N_HARMONIC * sin(b) * d;
        }
    }
}

/* The fed-groove map's force at x (supplykernels.map4_force, in its order of operations): F = W (G_r u + G_t w),
 * W = S r + supply (supply = R L p_s [N]), u = supply / W; P = (W / S) G with dP/dr = G - u G_u and
 * (1 / r) dP/dbeta = G_beta / (1 - u) in (a, c), the odd part at rest. Returns eps, evaluated when < MAP_EPS_MAX. */
static double supply_arc_force(const double x[5], double CR, double scale, double supply, int want_jac, double F[2],
                               double J[8], double dw[2]) {
    const double omega = x[4];
    double cp, sp, a, c;
    double eps = ff_reduce(x, CR, MAP_EPS_MIN, &cp, &sp, &a, &c);
    if (!(eps < MAP_EPS_MAX)) return eps;
    double eps_eval = fmax(eps, MAP_EPS_MIN), r = hypot(a, c), phi = atan2(sp, cp);
    double W = scale * r + supply, u = supply / W, t = scale * r / W; /* t = 1 - u without the cancellation */
    double beta = 0.0, cb = 1.0, sb = 0.0; /* the still journal: the u = 1 row is one value for every beta */
    if (r > 0.0) {
        beta = atan2(c, a);
        cb = a / r;
        sb = c / r;
    }
    double g[2][5], P[10];
    g4(eps_eval, phi, beta, u, g);
    double ws = W / scale;
    P[0] = ws * g[0][0];
    P[1] = ws * g[1][0];
    F[0] = scale * (P[0] * cp - P[1] * sp);
    F[1] = scale * (P[0] * sp + P[1] * cp);
    if (!want_jac) return eps;
    P[6] = ws * g[0][1];
    P[7] = ws * g[1][1];
    P[8] = ws * g[0][2];
    P[9] = ws * g[1][2];
    if (t < MAP_T_MIN) {
        double o[2][2];
        odd_part(eps_eval, phi, o);
        P[2] = o[0][0];
        P[4] = o[1][0];
        P[3] = o[0][1];
        P[5] = o[1][1];
    } else {
        double dr_r = g[0][0] - u * g[0][4], db_r = g[0][3] / t;
        double dr_t = g[1][0] - u * g[1][4], db_t = g[1][3] / t;
        P[2] = cb * dr_r - sb * db_r;
        P[3] = sb * dr_r + cb * db_r;
        P[4] = cb * dr_t - sb * db_t;
        P[5] = sb * dr_t + cb * db_t;
    }
    arc_jacobian(scale, CR, cp, sp, eps_eval, omega, a, c, P, J, dw);
    return eps;
}
#endif

/* A lobed bore's force (internals/map/lobemap.py, kernels.lobes_force, in its order of operations): lobe k is
 * the lobe arc turned by alpha_k, the journal in its frame (map_lobe_state, map_spline.h), its force and
 * Jacobian blocks turned back by Rot(alpha_k) and summed. */
int bn_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood) {
    const double y = x[0], z = x[1];
    const double CR = m->r[VR_CR], scale = m->work.scale;
    *ood = 0;
#if MAP_LOBES > 1
    const double cpad = map_lobe_clearance(CR);
    F[0] = F[1] = dw[0] = dw[1] = 0.0;
    for (int i = 0; i < 8; i++) J[i] = 0.0;
    for (int k = 0; k < MAP_LOBES; k++) {
        double xk[5], Fk[2], Jk[8], dwk[2];
        map_lobe_state(CR, k, x, xk);
        double eps = map_arc_force(xk, cpad, scale, want_jac, Fk, Jk, dwk);
        if (!(eps < MAP_EPS_MAX)) {
            char a[32], b[32], c[32], d[32], f[32];
            snprintf(m->msg, sizeof m->msg, "the journal (y = %s m, z = %s m) is %s C_pad from the centre of lobe %d "
                     "(%s; C_pad = %s m; the lobe map covers < %s C_pad from every lobe's centre)", bn_num(c, 32, y, 4),
                     bn_num(d, 32, z, 4), bn_num(a, 32, eps, 4), k,
                     eps >= 1.0 ? "at or beyond the lobe's circle" : "beyond the force map's last point",
                     bn_num(f, 32, cpad, 4), bn_num(b, 32, MAP_EPS_MAX, 6));
            return 1;
        }
        double c = MAP_LOBE_ROT[2 * k], s = MAP_LOBE_ROT[2 * k + 1];
        F[0] += c * Fk[0] - s * Fk[1];
        F[1] += s * Fk[0] + c * Fk[1];
        if (!want_jac) continue; /* dF/domega (dw) and J with the Jacobian only, as map_force */
        dw[0] += c * dwk[0] - s * dwk[1];
        dw[1] += s * dwk[0] + c * dwk[1];
        for (int b = 0; b < 4; b += 2) { /* R Jb R^T of the position (b = 0) and velocity (b = 2) blocks */
            double m00 = c * Jk[b] - s * Jk[4 + b];
            double m01 = c * Jk[b + 1] - s * Jk[4 + b + 1];
            double m10 = s * Jk[b] + c * Jk[4 + b];
            double m11 = s * Jk[b + 1] + c * Jk[4 + b + 1];
            J[b] += m00 * c - m01 * s;
            J[b + 1] += m00 * s + m01 * c;
            J[4 + b] += m10 * c - m11 * s;
            J[4 + b + 1] += m10 * s + m11 * c;
        }
    }
    return 0;
#else
#if MAP_DIMS == 4
    double eps = supply_arc_force(x, CR, scale, 0.5 * m->r[VR_D] * m->r[VR_L] * m->r[MAP_SUPPLY_VR], want_jac, F, J,
                                  dw); /* supplymap.supply_force: R L p_s */
#else
    double eps = map_arc_force(x, CR, scale, want_jac, F, J, dw);
#endif
    if (!(eps < MAP_EPS_MAX)) {
        char a[32], b[32], c[32], d[32], f[32];
        int wall = eps >= 1.0;
        snprintf(m->msg, sizeof m->msg, "eccentricity ratio %s >= %s: the journal (y = %s m, z = %s m) is %s (CR = %s m; "
                 "the map covers eps < %s)", bn_num(a, 32, eps, 4), wall ? "1" : bn_num(b, 32, MAP_EPS_MAX, 6),
                 bn_num(c, 32, y, 4), bn_num(d, 32, z, 4),
                 wall ? "at or beyond the bearing wall" : "beyond the force map's last point",
                 bn_num(f, 32, CR, 4), bn_num(b, 32, MAP_EPS_MAX, 6));
        return 1;
    }
    return 0;
#endif
}


void bn_option_derivative(Instance *m, const double x[5], int k, double dF[2], double dJ[8]) {
    (void)m; (void)x; (void)k; /* the map has no Real option */
    dF[0] = dF[1] = 0.0;
    for (int i = 0; i < 8; i++) dJ[i] = 0.0;
}

void bn_release(Instance *m) { (void)m; } /* nothing allocated */
