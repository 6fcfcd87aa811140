/* The 2-D and 3-D force maps' evaluation from model_data.h's spline (MAP_*): G from the table (gfun),
 * the force F = S r (G_r u + G_t w) at a journal state in the arc's frame (arc_force: a port of
 * map/kernels.map_force and map3_force) and the Jacobian of every map's F from the partial derivatives of
 * its components (arc_jacobian: kernels.force_jacobian, the fed 4-D map's too). Static functions shared
 * by internal_map.c (every map bore) and pad_map.h (the tilting pads' map in internal_tilting_pad.c):
 * each unit compiles its own copy, no unit calls another. */
#ifndef MAP_ARC_H
#define MAP_ARC_H
#include "film_friction.h" /* ff_reduce */
#include "map_spline.h"

/* J and dw (dF/domega) of F = S (Pr u + Pt w) from P = (Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p, Pt_p),
 * the partial derivatives of its components in (a, c, eps, phi): kernels.force_jacobian, every map's */
static void arc_jacobian(double scale, double CR, double cp, double sp, double eps_eval, double omega, double a,
                         double c, const double P[10], double J[8], double dw[2]) {
    const double Pr = P[0], Pt = P[1], Pr_a = P[2], Pr_c = P[3], Pt_a = P[4], Pt_c = P[5], Pr_e = P[6], Pt_e = P[7],
                 Pr_p = P[8], Pt_p = P[9];
    double da_dphi = c, dc_dphi = eps_eval * omega - a;
    double dPr_dphi = Pr_a * da_dphi + Pr_c * dc_dphi + Pr_p; /* + the table's own attitude dependence */
    double dPt_dphi = Pt_a * da_dphi + Pt_c * dc_dphi + Pt_p;
    double dFphi_y = scale * ((dPr_dphi - Pt) * cp - (dPt_dphi + Pr) * sp);
    double dFphi_z = scale * ((dPr_dphi - Pt) * sp + (dPt_dphi + Pr) * cp);
    double dPr_de = Pr_e + Pr_a * omega, dPt_de = Pt_e + Pt_a * omega;
    double dFe_y = scale * (dPr_de * cp - dPt_de * sp);
    double dFe_z = scale * (dPr_de * sp + dPt_de * cp);
    double e_eval = eps_eval * CR;
    J[0] = dFe_y * cp / CR - dFphi_y * sp / e_eval;
    J[4] = dFe_z * cp / CR - dFphi_z * sp / e_eval;
    J[1] = dFe_y * sp / CR + dFphi_y * cp / e_eval;
    J[5] = dFe_z * sp / CR + dFphi_z * cp / e_eval;
    for (int col = 0; col < 2; col++) {
        double dvr = col == 0 ? cp : sp, dvt = col == 0 ? -sp : cp;
        double da = -2.0 * dvt / CR, dc = 2.0 * dvr / CR;
        double dPr = Pr_a * da + Pr_c * dc, dPt = Pt_a * da + Pt_c * dc;
        J[2 + col] = scale * (dPr * cp - dPt * sp);
        J[6 + col] = scale * (dPr * sp + dPt * cp);
    }
    /* the speed enters through a = eps omega - 2 v_t / CR only */
    double dPr_w = Pr_a * eps_eval, dPt_w = Pt_a * eps_eval;
    dw[0] = scale * (dPr_w * cp - dPt_w * sp);
    dw[1] = scale * (dPr_w * sp + dPt_w * cp);
}

#if MAP_DIMS != 4
/* g[k] = (G, dG/deps, dG/dbeta, dG/dphi) of the radial (k = 0) and tangential parts: a full-bore
 * map's G = H / (1 - eps)^k does not depend on phi; a grooved bore's has no wall factor */
static void gfun(double eps, double phi, double beta, double g[2][4]) {
    double s = -log1p(-eps);
#if MAP_DIMS == 3
    double o[2][4];
    spline3(MAP_TS, MAP_TP, MAP_TB, MAP_C, MAP_NP, 2, s, phi, beta, o);
    for (int k = 0; k < 2; k++) {
        g[k][0] = o[k][0];
        g[k][1] = o[k][1] * exp(s);
        g[k][2] = o[k][3];
        g[k][3] = o[k][2];
    }
#else
    (void)phi;
    double o[2][3];
    spline2(MAP_TS, MAP_TB, MAP_C, s, beta, o);
    double grow = exp(MAP_WALL_EXPONENT * s), dsde = exp(s);
    for (int k = 0; k < 2; k++) {
        double h = o[k][0], hs = o[k][1], hb = o[k][2];
        g[k][0] = h * grow;
        g[k][1] = (hs + MAP_WALL_EXPONENT * h) * grow * dsde;
        g[k][2] = hb * grow;
        g[k][3] = 0.0;
    }
#endif
}

/* The map's force at x with clearance CR and scale S (the lobe arc's for a lobed bore): returns eps, and
 * evaluates only when eps < MAP_EPS_MAX */
static double arc_force(const double x[5], double CR, double scale, int want_jac, double F[2], double J[8],
                        double dw[2]) {
    const double omega = x[4];
    double cp, sp, a, c;
    double eps = ff_reduce(x, CR, MAP_EPS_MIN, &cp, &sp, &a, &c);
    if (!(eps < MAP_EPS_MAX)) return eps;
    double eps_eval = fmax(eps, MAP_EPS_MIN);
    double r = hypot(a, c);
    double g[2][4], g2[2][4];
    double Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p, Pt_p;
    double phi = atan2(sp, cp); /* the attitude: a grooved bore's G depends on it */
    if (r > 0.0) {
        double beta = atan2(c, a);
        gfun(eps_eval, phi, beta, g);
        double cb = a / r, sb = c / r;
        Pr = r * g[0][0];
        Pt = r * g[1][0];
        Pr_a = cb * g[0][0] - sb * g[0][2];
        Pr_c = sb * g[0][0] + cb * g[0][2];
        Pt_a = cb * g[1][0] - sb * g[1][2];
        Pt_c = sb * g[1][0] + cb * g[1][2];
        Pr_e = r * g[0][1];
        Pt_e = r * g[1][1];
        Pr_p = r * g[0][3];
        Pt_p = r * g[1][3];
    } else { /* no film source: no force; the derivative is the odd part of the directional response */
        Pr = Pt = Pr_e = Pt_e = Pr_p = Pt_p = 0.0;
        gfun(eps_eval, phi, 0.0, g);
        gfun(eps_eval, phi, M_PI, g2);
        Pr_a = 0.5 * (g[0][0] - g2[0][0]);
        Pt_a = 0.5 * (g[1][0] - g2[1][0]);
        gfun(eps_eval, phi, 0.5 * M_PI, g);
        gfun(eps_eval, phi, -0.5 * M_PI, g2);
        Pr_c = 0.5 * (g[0][0] - g2[0][0]);
        Pt_c = 0.5 * (g[1][0] - g2[1][0]);
    }
    F[0] = scale * (Pr * cp - Pt * sp);
    F[1] = scale * (Pr * sp + Pt * cp);
    if (!want_jac) return eps;
    const double P[10] = {Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p, Pt_p};
    arc_jacobian(scale, CR, cp, sp, eps_eval, omega, a, c, P, J, dw);
    return eps;
}
#endif /* MAP_DIMS != 4 */
#endif
