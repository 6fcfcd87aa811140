/* The tilting pads' map (internal_tilting_pad.c with TP_MAP: generators/tilting_pad.py), static
 * functions included after model_data.h (MAP_*, TP_PRELOAD) and the pad's Frame: */
#ifndef PAD_MAP_H
#define PAD_MAP_H
/* Every pad from the pads' 3-D partial-arc map (model_data.h MAP_*: padmap.PadMapSolver): the
 * circular arc of clearance C_pad with the journal shifted by the preload d = C_pad - C_bearing
 * along -z', the force F = S r (G_r u + G_t w), S = mu R L (R / C_pad)^2, G(eps, phi, beta) the
 * tensor cubic spline: map_arc.h's arc_force (internal_map.c's for a grooved bore's map, MAP_DIMS 3)
 * with the pad's clearance and scale for the bearing's. */
#include "map_arc.h" /* arc_force: the 3-D map's force and Jacobian, internal_map.c's */

static double pad_clearance(const Instance *m) { return m->r[VR_CR] / (1.0 - TP_PRELOAD); }

/* the pad's force, Jacobian and dF/domega in its frame at st (y', z', vy', vz', omega): 0, or 1 */
static int map_pad(Instance *m, const double st[5], Frame *f) {
    const double CR = pad_clearance(m), R = 0.5 * m->r[VR_D];
    const double scale = m->r[VR_MU] * R * m->r[VR_L] * pow(R / CR, 2.0);
    double x[5] = {st[0], st[1] - (CR - m->r[VR_CR]), st[2], st[3], st[4]}, J[8];
    double eps = arc_force(x, CR, scale, 1, f->F, J, f->Jw);
    if (!(eps < MAP_EPS_MAX)) {
        char b1[32], b2[32];
        snprintf(m->msg, sizeof m->msg, "tilting pads: a pad's journal at eccentricity %s of C_pad is beyond the pads' "
                 "map (eps < %s, %s)", bn_num(b1, 32, eps, 4), bn_num(b2, 32, MAP_EPS_MAX, 6), MAP_SOURCE);
        return 1;
    }
    f->Jq[0] = J[0], f->Jq[1] = J[1], f->Jq[2] = J[4], f->Jq[3] = J[5];
    f->Jv[0] = J[2], f->Jv[1] = J[3], f->Jv[2] = J[6], f->Jv[3] = J[7];
    return 0;
}
#endif
