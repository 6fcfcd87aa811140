/* The peak pressure of the Reynolds solver's field (reynolds_solver.h; a port of
 * bearing_fmu/physics/solver/reynolds.py Reynolds.peak_pressure and film.py peak_pressure): a unit of
 * its own beside reynolds_solver.c, compiled into every native Reynolds FMU (its outputs
 * peak_pressure, peak_pressure_angle) and into the ctypes library (fmu/native/solver_lib.py). Equal to
 * the Python solver's bit for bit on every bore and grid (tests/test_native_peak.py). */
#include <math.h>

#include "py_mod.h"
#include "reynolds_solver.h"

/* film.py _vertex: (t, p) of the parabola's vertex through three points (t1 the middle one, p1 >= p0,
 * p2), kept between the neighbours, or the middle point itself when the three are not concave */
static void rs_vertex(double t0, double t1, double t2, double p0, double p1, double p2, double out[2]) {
    double a0 = t0 - t1, a2 = t2 - t1;
    double den = a0 * a2 * (a0 - a2);
    double c2 = ((p0 - p1) * a2 - (p2 - p1) * a0) / den;
    if (!(c2 < 0.0)) {
        out[0] = p1;
        out[1] = t1;
        return;
    }
    double c1 = ((p2 - p1) * a0 * a0 - (p0 - p1) * a2 * a2) / den;
    double v = -c1 / (2.0 * c2);
    v = a0 > v ? a0 : v;
    v = a2 < v ? a2 : v;
    out[0] = p1 + c1 * v + c2 * v * v;
    out[1] = t1 + v;
}

/* the field's value at cell (i, j) of the half length (0 when the last call left none: p_stale) */
#define RS_PV(s, i, j) ((s)->p_stale ? 0.0 : (s)->p[(i) * (s)->m + (j)])

/* The peak pressure of the field rs_call just solved: out = (p_peak [Pa], theta_peak [rad]), a port of
 * physics/solver/reynolds.py Reynolds.peak_pressure and film.py peak_pressure (their docstrings: the
 * largest cell refined by the parabola through its neighbours around the circumference, at its axial
 * row the even parabola A - B x^2 through the two rows nearest the mid-plane; a land fed by a
 * circumferential groove (p_in): the largest cell's column, the groove's p_in where it is the largest).
 * Uses the solver's work array rhs as scratch. */
RS_API void rs_peak_pressure(rs_solver *s, double out[2]) {
    int N = s->N, m = s->m, i, j, bi = 0, bj = 0, k;
    double *rows = s->rhs, best, pk[2];
    if (s->p_in != 0.0 || s->lands) { /* the column of the largest cell (numpy's first), refined along theta */
        best = RS_PV(s, 0, 0);
        for (j = 0; j < m; j++)
            for (i = 0; i < N; i++)
                if (RS_PV(s, i, j) > best) best = RS_PV(s, i, j), bj = j;
        for (i = 0; i < N; i++) rows[i] = RS_PV(s, i, bj);
    } else { /* the whole length: column c of the field is the half's min(c, 2m - 1 - c) */
        best = RS_PV(s, 0, 0);
        for (i = 0; i < N; i++)
            for (k = 0; k < 2 * m; k++) {
                double v = RS_PV(s, i, k < m ? k : 2 * m - 1 - k);
                if (v > best) best = v, bi = i, bj = k;
            }
        if (!(best > 0.0)) {
            out[0] = 0.0;
            out[1] = s->cen[bi];
            return;
        }
        if (m >= 2) { /* A of the even parabola through the two rows nearest the mid-plane */
            double x1 = fabs(-0.5 * s->L + ((double)m + 0.5) * s->dx);
            double x2 = fabs(-0.5 * s->L + ((double)(m + 1) + 0.5) * s->dx);
            for (i = 0; i < N; i++) {
                double pm = RS_PV(s, i, m - 1), pn = RS_PV(s, i, m - 2);
                double a = (pm * x2 * x2 - pn * x1 * x1) / (x2 * x2 - x1 * x1);
                rows[i] = a >= pm ? a : pm;
            }
        } else {
            for (i = 0; i < N; i++) rows[i] = RS_PV(s, i, 0);
        }
    }
    bi = 0;
    for (i = 1; i < N; i++)
        if (rows[i] > rows[bi]) bi = i;
    if ((s->p_in != 0.0 || s->lands) && !(rows[bi] > 0.0)) {
        pk[0] = 0.0;
        pk[1] = s->cen[bi];
    } else {
        int ip = bi > 0 ? bi - 1 : N - 1, in = bi + 1 < N ? bi + 1 : 0;
        double t0 = s->cen[ip] - (bi == 0 ? RS_TWO_PI : 0.0), t2 = s->cen[in] + (bi == N - 1 ? RS_TWO_PI : 0.0);
        rs_vertex(t0, s->cen[bi], t2, rows[ip], rows[bi], rows[in], pk);
        pk[1] = py_mod(pk[1], RS_TWO_PI);
    }
    if ((s->p_in != 0.0 || s->lands) && !(pk[0] >= s->p_in)) pk[0] = s->p_in; /* the groove's own pressure */
    out[0] = pk[0];
    out[1] = pk[1];
}
