/* The force map's film report (bn_film, bearing_native.h): included by internal_map.c when the map
 * file has flow tables (BN_FLOWS_MAP, MAP_FLOWS; model_data.h, fmu/native/map_data.py), its spline
 * evaluation and ff_reduce (film_friction.h) shared with the force. Ports, in their order of operations, of
 *  - a full-bore map (MAP_DIMS 2): ForceMap.film_report, film.reduced_report: the friction in closed
 *    form from the force (film_friction.h), the flows from the table's (J_s, J_i) at (eps, beta);
 *  - a grooved or partial-arc map (MAP_DIMS 3): GroovedForceMap.film_report, film.grooved_report:
 *    the Couette torque over the film's segments in closed form (film.film_couette_integral), the
 *    pressure torque from the force, the side flow r Q0 J_s and the inflow summed over the supply
 *    edges, each max(sign omega Q0 h_e / (2 CR) - r Q0 P_e, 0), (J_s, P_1 .. P_E) the flow spline
 *    over one period in phi at (eps, phi, beta), renumbered for the periods folded away
 *    (groovemap.flow_components: GroovedMapTable.flow_spline, flow_images);
 *    docs/forcemap.md, "Grooved bores: the flows".
 * A lobed bore's (MAP_LOBES > 1): LobedForceMap.film_report, each lobe's parts in its own frame summed.
 * Q0 = R L CR (film.flow_scale). out as bn_film's. Compiled beside internal_map.c when the map's
 * film report is (BN_FLOWS_MAP); the flow table's arrays of model_data.h are this file's
 * (BN_MAP_FLOW_UNIT), the force's internal_map.c's. */
#include <math.h>

#define BN_PART map /* its functions' names in an FMU of several internals */
#define BN_PART_MAP 1 /* its part of model_data.h */
#define BN_MAP_FLOW_UNIT 1 /* and in it the flow table's arrays */
#include "bearing_native.h"
#include "model_data.h"
#include "film_friction.h" /* ff_reduce, the friction */
#include "map_spline.h"

#if !MAP_FLOWS || !BN_FLOWS_MAP
#error "the film report needs a map with its flow table (portgen.film_flow), compiled in (BN_FLOWS_MAP)"
#endif

#if MAP_DIMS == 3
/* int dtheta / (1 + eps sin(theta - phi)) over the film's segments (MAP_FILM_SEGS), in closed form:
 * film.film_couette_integral, whose docstring derives the primitive */
static double mf_couette_integral(double eps, double phi) {
    double root = sqrt(1.0 - eps * eps), k = sqrt((1.0 - eps) / (1.0 + eps)), sum = 0.0;
    for (int n = 0; n < MAP_N_FILM; n++) {
        double prim[2];
        for (int end = 0; end < 2; end++) {
            double u = MAP_FILM_SEGS[2 * n + end] - phi - 0.5 * M_PI;
            prim[end] = (u + 2.0 * atan2((k - 1.0) * sin(u), (1.0 + k) + (1.0 - k) * cos(u))) / root;
        }
        sum += prim[1] - prim[0];
    }
    return sum;
}

/* GroovedForceMap.film_report's parts at the state x of a film of clearance CR whose force is F: out[0] the
 * Couette torque, out[1] the pressure torque, out[3] the inflow, out[4] the side flow (out[2] the caller's) */
static void grooved_film(const Instance *m, const double x[5], double CR, const double F[2], double out[5]) {
    double cp, sp, a, c, q[MAP_NQ][4];
    const double y = x[0], z = x[1], omega = x[4];
    const double R = 0.5 * m->r[VR_D], L = m->r[VR_L], mu = m->r[VR_MU];
    double eps = ff_reduce(x, CR, 0.0, &cp, &sp, &a, &c);
    /* phi folded twice into the spline's period (its own fold then leaves it), j the periods folded away */
    double phi = atan2(sp, cp), t3 = MAP_QTP[3], T = MAP_QTP[MAP_NQP] - MAP_QTP[3];
    double p = t3 + py_mod(t3 + py_mod(phi - t3, T) - t3, T);
    int j = (int)floor((phi - p) / T + 0.5) % MAP_QTURNS;
    const int *img = MAP_QIMG + MAP_NQ * (j < 0 ? j + MAP_QTURNS : j);
    spline3(MAP_QTS, MAP_QTP, MAP_QTB, MAP_QC, MAP_NQP, MAP_NQ, -log1p(-fmax(eps, MAP_EPS_MIN)), p, atan2(c, a), q);
    double r = hypot(a, c), q0 = R * L * CR, q_in = 0.0;
    for (int e = 0; e < MAP_N_EDGES; e++) {
        double theta = MAP_EDGES[2 * e], sign = MAP_EDGES[2 * e + 1];
        double h = CR + y * sin(theta) - z * cos(theta);
        double v = sign * omega * q0 * h / (2.0 * CR) - r * q0 * q[img[1 + e]][0];
        q_in += 0.0 > v ? 0.0 : v; /* Python's max(v, 0.0) */
    }
    out[0] = mu * omega * pow(R, 3.0) * L / CR * mf_couette_integral(hypot(y, z) / CR, atan2(z, y));
    out[1] = ff_pressure(y, z, F);
    out[3] = q_in;
    out[4] = r * q0 * q[img[0]][0];
}

#if MAP_LOBES > 1
/* A lobed bore (LobedForceMap.film_report): each lobe's parts in its frame (map_lobe_state) with the lobe
 * arc's force there and clearance C_pad, summed in lobe order; the power from the summed force */
int bn_film(Instance *m, const double x[5], double out[5]) {
    double F[2], J[8], dw[2], o[5];
    int ood;
    if (bn_eval(m, x, 0, F, J, dw, &ood)) return 1;
    const double CR = m->r[VR_CR], cpad = map_lobe_clearance(CR);
    double tc = 0.0, tp = 0.0, q_in = 0.0, q_s = 0.0;
    for (int k = 0; k < MAP_LOBES; k++) {
        double xk[5], Fk[2];
        map_lobe_state(CR, k, x, xk);
        map_arc_force(xk, cpad, m->work.scale, 0, Fk, J, dw); /* within the map: bn_eval checked every lobe */
        grooved_film(m, xk, cpad, Fk, o);
        tc += o[0];
        tp += o[1];
        q_in += o[3];
        q_s += o[4];
    }
    out[0] = tc;
    out[1] = tp;
    out[2] = ff_power(tc, tp, x[4], F, x[2], x[3]);
    out[3] = q_in;
    out[4] = q_s;
    return 0;
}
#else
int bn_film(Instance *m, const double x[5], double out[5]) {
    double F[2], J[8], dw[2];
    int ood;
    if (bn_eval(m, x, 0, F, J, dw, &ood)) return 1;
    grooved_film(m, x, m->r[VR_CR], F, out);
    out[2] = ff_power(out[0], out[1], x[4], F, x[2], x[3]);
    return 0;
}
#endif
#else
int bn_film(Instance *m, const double x[5], double out[5]) {
    double F[2], J[8], dw[2], cp, sp, a, c, q[2][3];
    int ood;
    if (bn_eval(m, x, 0, F, J, dw, &ood)) return 1;
    const double CR = m->r[VR_CR], R = 0.5 * m->r[VR_D], L = m->r[VR_L], omega = x[4];
    double eps = ff_reduce(x, CR, 0.0, &cp, &sp, &a, &c);
    spline2(MAP_QTS, MAP_QTB, MAP_QC, -log1p(-fmax(eps, MAP_EPS_MIN)), atan2(c, a), q);
    double r = hypot(a, c), q0 = R * L * CR;
    out[0] = ff_couette(m->r[VR_MU], omega, R, L, CR, eps);
    out[1] = ff_pressure(x[0], x[1], F);
    out[2] = ff_power(out[0], out[1], omega, F, x[2], x[3]);
    out[3] = fabs(omega * q0 * 0.5 * (1.0 + eps) - r * q0 * q[1][0]);
    out[4] = r * q0 * q[0][0];
    return 0;
}
#endif
