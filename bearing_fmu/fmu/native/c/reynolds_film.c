/* The film report in C: friction and flows of the converged field (a port of
 * bearing_fmu/physics/solver/film.py field_report, whose docstring gives the definitions: Couette and
 * pressure torque, friction power, inflow, side flow), over reynolds_solver.c's field (compiled
 * beside it when the FMU has the thermal model, BN_FLOWS_REYNOLDS); equal to Python's to about 1e-14 relative
 * (tests/test_native_reynolds.py: 1e-12 the tolerance; the sums' order differs). The field's peak
 * pressure (film.py peak_pressure, Reynolds.peak_pressure) is rs_peak_pressure, in reynolds_peak.c:
 * every Reynolds FMU has it, with or without the thermal model. */
#include <math.h>

#include "film_friction.h" /* the full bore's friction in closed form, the friction power */
#include "py_mod.h"
#include "reynolds_solver.h"

#if !defined(RS_EXPORT) && !BN_FLOWS_REYNOLDS && !BN_FLOWS_TILTING_PAD
#error "the Reynolds film report is compiled alone (RS_EXPORT) or in an FMU with the thermal model (BN_FLOWS_REYNOLDS, the tilting pads' BN_FLOWS_TILTING_PAD)"
#endif
/* numpy's argmax/argmin: the first of equal values */
static int rf_first_max(const double *x, int n) {
    int i, k = 0;
    for (i = 1; i < n; i++)
        if (x[i] > x[k]) k = i;
    return k;
}

/* The report of the last rs_call's field at the state it was called at (y, z [m], vy, vz [m/s],
 * omega [rad/s]; the field is 0 when the call had no source: s->p_stale): out = Couette torque, pressure torque [N m], friction power [W], inflow, side
 * flow [m^3/s]. Uses the solver's work arrays rhs, tmp, mu_y, mu_z as scratch (free between calls). */
RS_API void rs_film_report(rs_solver *s, double y, double z, double vy, double vz, double omega, double out[5]) {
    int N = s->N, m = s->m, i, j, any_fixed = 0;
    /* the film's length: L, less a circumferential groove's width (lands.film_length: the groove shears none) */
    double mu = s->mu, R = s->R, CR = s->CR, L = s->L - s->groove, dx = s->dx, tc, tp;
    double *a1 = s->rhs, *a2 = s->tmp, *flux = s->mu_y, *hf = s->mu_z;
    /* the face fluxes and film thickness (the shared part) */
    for (i = 0; i < N; i++) {
        int nx = i + 1 < N ? i + 1 : 0;
        hf[i] = CR * s->H0f[i] + y * s->sin_f[i] - z * s->cos_f[i];
        double safe = s->dst[i] > 0.0 ? s->dst[i] : 1.0, sdp = 0.0, jump = 0.0;
        for (j = 0; j < m; j++) {
            double p0 = s->fixed[i] ? s->psup[i] : (s->p_stale ? 0.0 : s->p[i * m + j]);
            double p1 = s->fixed[nx] ? s->psup[nx] : (s->p_stale ? 0.0 : s->p[nx * m + j]);
            sdp += (p1 - p0) / safe * (2.0 * dx);
            jump += (p1 - p0) * (2.0 * s->qw[j]);
        }
        flux[i] = (omega * R * hf[i] / 2.0) * L - hf[i] * hf[i] * hf[i] / (12.0 * mu * R) * sdp;
        /* (R / 2) h_f (p_next - p) over the faces with film on a side (the pressure torque) */
        a2[i] = (s->fixed[i] && s->fixed[nx]) ? 0.0 : hf[i] * jump;
        any_fixed |= s->fixed[i];
    }
    if (!s->bore) {
        tc = ff_couette(mu, omega, R, L, CR, hypot(y, z) / CR);
        tp = ff_pressure(y, z, s->F);
    } else {
        for (i = 0; i < N; i++) { /* Simpson's 1/h over each film cell */
            double hc = CR * s->H0c[i] + y * s->sin_c[i] - z * s->cos_c[i];
            double hl = CR * s->hl0[i] + y * sin(s->lf[i]) - z * cos(s->lf[i]);
            /* h at the right face on the cell's own lobe: hf's, for a film cell */
            a1[i] = s->fixed[i] ? 0.0 : s->wd[i] / 6.0 * (1.0 / hl + 4.0 / hc + 1.0 / hf[i]);
        }
        tc = mu * omega * R * R * R * L * rs_np_sum(a1, N);
        tp = 0.5 * R * rs_np_sum(a2, N);
    }
    /* side flow: out of both ends of every film cell (the solver's end gradient) */
    for (i = 0; i < N; i++) {
        double hc = CR * s->H0c[i] + y * s->sin_c[i] - z * s->cos_c[i];
        double grad = s->p_stale ? 0.0 : m == 1 ? 8.0 * s->p[i * m] / (3.0 * dx)
                                                  : (9.0 * s->p[i * m] - s->p[i * m + 1]) / (3.0 * dx);
        a1[i] = s->fixed[i] ? 0.0 : hc * hc * hc / (12.0 * mu) * grad * R * s->wd[i];
    }
    double q_side = rs_np_sum(a1, N) * 2.0, q_in = 0.0;
    int feeds = 0;
    if (any_fixed) { /* into the film from each prescribed cell, where positive */
        for (i = 0; i < N; i++) {
            int nx = i + 1 < N ? i + 1 : 0;
            double in_next = s->fixed[i] && !s->fixed[nx] ? flux[i] : 0.0;
            double in_prev = !s->fixed[i] && s->fixed[nx] ? -flux[i] : 0.0;
            a1[i] = in_next > 0.0 ? in_next : 0.0;
            a2[i] = in_prev > 0.0 ? in_prev : 0.0;
        }
        q_in = rs_np_sum(a1, N) + rs_np_sum(a2, N);
    }
    if (s->bore && s->lobes > 1 && s->preload > 0.0) { /* film.lobe_feed_faces: each lobe's own feed line */
        unsigned char fed[RS_MAX_LOBES] = {0};
        for (i = 0; i < N; i++) { /* a lobe beside a supply edge is fed there */
            int nx = i + 1 < N ? i + 1 : 0;
            if (s->fixed[i] && !s->fixed[nx]) fed[rs_lobe_of(s->lobes, s->lobe_angle, s->cen[nx])] = 1;
            if (!s->fixed[i] && s->fixed[nx]) fed[rs_lobe_of(s->lobes, s->lobe_angle, s->cen[i])] = 1;
        }
        for (i = 0; i < N; i++) {
            int nx = i + 1 < N ? i + 1 : 0, pv = i > 0 ? i - 1 : N - 1;
            if (!s->fixed[i] && !s->fixed[nx] && hf[i] > hf[nx] && hf[i] >= hf[pv] &&
                !fed[rs_lobe_of(s->lobes, s->lobe_angle, s->cen[i])]) {
                q_in += fabs(flux[i]);
                feeds++;
            }
        }
    }
    if (s->lands) { /* the groove is the lands' only supply: in a steady state it delivers what leaves by the ends */
        q_in = q_side;
    } else if (!any_fixed && !feeds) { /* across the line of thickest film, between the two faces around it */
        int k = rf_first_max(hf, N), a = -1;
        double t_max = (y != 0.0 || z != 0.0) ? atan2(y, -z) : s->rt[k];
        for (i = 0; i < N; i++) {
            double d = py_mod(t_max - s->rt[i] + M_PI, RS_TWO_PI) - M_PI;
            a1[i] = d;
            if (d >= 0.0 && (a < 0 || d < a1[a])) a = i;
        }
        if (a < 0) a = 0; /* numpy's argmin of all inf */
        int b = a + 1 < N ? a + 1 : 0;
        double span = py_mod(s->rt[b] - s->rt[a], RS_TWO_PI);
        if (span == 0.0) span = 1.0;
        double w = a1[a] / span;
        q_in = fabs((1.0 - w) * flux[a] + w * flux[b]);
    }
    out[0] = tc;
    out[1] = tp;
    out[2] = ff_power(tc, tp, omega, s->F, vy, vz);
    out[3] = q_in;
    out[4] = q_side;
}
