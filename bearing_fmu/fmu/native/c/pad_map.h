/* The tilting pads' map (internal_tilting_pad.c with TP_MAP: generators/tilting_pad.py), static
 * functions included after model_data.h (MAP_*, TP_PRELOAD) and the pad's Frame: */
#ifndef PAD_MAP_H
#define PAD_MAP_H
/* Every pad from the pads' 3-D partial-arc map (model_data.h MAP_*: padmap.PadMapSolver): the
 * circular arc of clearance C_pad with the journal shifted by the preload d = C_pad - C_bearing
 * along -z', the force F = S r (G_r u + G_t w), S = mu R L (R / C_pad)^2, G(eps, phi, beta) the
 * tensor cubic spline. A port of internal_map.c's bn_eval for a grooved bore's map (MAP_DIMS 3),
 * itself a port of map_kernels.map3_force, with the pad's clearance and scale for the bearing's. */
#include "film_friction.h" /* ff_reduce */
#include "map_spline.h"

static double pad_clearance(const Instance *m) { return m->r[VR_CR] / (1.0 - TP_PRELOAD); }

static void map_g(double eps, double phi, double beta, double g[2][4]) {
    double s = -log1p(-eps), o[2][4];
    spline3(MAP_TS, MAP_TP, MAP_TB, MAP_C, MAP_NP, 2, s, phi, beta, o);
    for (int k = 0; k < 2; k++) {
        g[k][0] = o[k][0];
        g[k][1] = o[k][1] * exp(s);
        g[k][2] = o[k][3];
        g[k][3] = o[k][2];
    }
}

/* the pad's force, Jacobian and dF/domega in its frame at st (y', z', vy', vz', omega): 0, or 1 */
static int map_pad(Instance *m, const double st[5], Frame *f) {
    const double CR = pad_clearance(m), R = 0.5 * m->r[VR_D], omega = st[4];
    const double scale = m->r[VR_MU] * R * m->r[VR_L] * pow(R / CR, 2.0);
    double x[5] = {st[0], st[1] - (CR - m->r[VR_CR]), st[2], st[3], st[4]};
    double cp, sp, a, c, *F = f->F, *dw = f->Jw, J[8];
    double eps = ff_reduce(x, CR, MAP_EPS_MIN, &cp, &sp, &a, &c);
    if (!(eps < MAP_EPS_MAX)) {
        char b1[32], b2[32];
        snprintf(m->msg, sizeof m->msg, "tilting pads: a pad's journal at eccentricity %s of C_pad is beyond the pads' "
                 "map (eps < %s, %s)", bn_num(b1, 32, eps, 4), bn_num(b2, 32, MAP_EPS_MAX, 6), MAP_SOURCE);
        return 1;
    }
    double eps_eval = fmax(eps, MAP_EPS_MIN), r = hypot(a, c), g[2][4], g2[2][4];
    double Pr, Pt, Pr_a, Pr_c, Pt_a, Pt_c, Pr_e, Pt_e, Pr_p, Pt_p, phi = atan2(sp, cp);
    if (r > 0.0) {
        double beta = atan2(c, a), cb = a / r, sb = c / r;
        map_g(eps_eval, phi, beta, g);
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
        map_g(eps_eval, phi, 0.0, g);
        map_g(eps_eval, phi, M_PI, g2);
        Pr_a = 0.5 * (g[0][0] - g2[0][0]);
        Pt_a = 0.5 * (g[1][0] - g2[1][0]);
        map_g(eps_eval, phi, 0.5 * M_PI, g);
        map_g(eps_eval, phi, -0.5 * M_PI, g2);
        Pr_c = 0.5 * (g[0][0] - g2[0][0]);
        Pt_c = 0.5 * (g[1][0] - g2[1][0]);
    }
    F[0] = scale * (Pr * cp - Pt * sp);
    F[1] = scale * (Pr * sp + Pt * cp);
    double da_dphi = c, dc_dphi = eps_eval * omega - a;
    double dPr_dphi = Pr_a * da_dphi + Pr_c * dc_dphi + Pr_p, dPt_dphi = Pt_a * da_dphi + Pt_c * dc_dphi + Pt_p;
    double dFphi_y = scale * ((dPr_dphi - Pt) * cp - (dPt_dphi + Pr) * sp);
    double dFphi_z = scale * ((dPr_dphi - Pt) * sp + (dPt_dphi + Pr) * cp);
    double dPr_de = Pr_e + Pr_a * omega, dPt_de = Pt_e + Pt_a * omega;
    double dFe_y = scale * (dPr_de * cp - dPt_de * sp), dFe_z = scale * (dPr_de * sp + dPt_de * cp);
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
    f->Jq[0] = J[0], f->Jq[1] = J[1], f->Jq[2] = J[4], f->Jq[3] = J[5];
    f->Jv[0] = J[2], f->Jv[1] = J[3], f->Jv[2] = J[6], f->Jv[3] = J[7];
    dw[0] = scale * (Pr_a * eps_eval * cp - Pt_a * eps_eval * sp); /* omega enters through a = eps omega - 2 v_t / CR */
    dw[1] = scale * (Pr_a * eps_eval * sp + Pt_a * eps_eval * cp);
    return 0;
}
#endif
