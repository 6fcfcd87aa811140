/* The force map's tensor cubic B-spline evaluated (ports of _map_kernels.py), for the force
 * (internal_map.c: MAP_TS, MAP_TB, MAP_C, a grooved bore's MAP_TP, a fed-groove map's MAP_TU too) and
 * the flow table (map_flows.c: MAP_QTS ..., on the same axes): static inline functions, included after
 * model_data.h (MAP_NS, MAP_NB, MAP_DIMS; MAP_NU with MAP_DIMS 4). */
#ifndef MAP_SPLINE_H
#define MAP_SPLINE_H

#include "py_mod.h"

#ifndef MAP_DIMS
#define MAP_DIMS 2
#endif

#if MAP_LOBES > 1
/* A lobed bore (internals/map/lobemap.py): lobe k's frame, the journal state x turned by -alpha_k
 * (MAP_LOBE_ROT: cos, sin) relative to lobe 0's centre O_0 = -(C_pad - CR) u(theta_p,0) (MAP_LOBE_U),
 * in kernels.lobes_force's order of operations; the lobe arc's clearance C_pad = CR / (1 - m) */
static inline double map_lobe_clearance(double CR) { return CR / (1.0 - MAP_LOBE_PRELOAD); }
static inline void map_lobe_state(double CR, int k, const double x[5], double xk[5]) {
    double d = map_lobe_clearance(CR) - CR;
    double o0 = -d * MAP_LOBE_U[0], o1 = -d * MAP_LOBE_U[1];
    double c = MAP_LOBE_ROT[2 * k], s = MAP_LOBE_ROT[2 * k + 1];
    xk[0] = c * x[0] + s * x[1] - o0;
    xk[1] = -s * x[0] + c * x[1] - o1;
    xk[2] = c * x[2] + s * x[3];
    xk[3] = -s * x[2] + c * x[3];
    xk[4] = x[4];
}
/* the lobe arc's map at a lobe's state (internal_map.c): returns eps', evaluated when < MAP_EPS_MAX */
#define map_arc_force BN_FN(map_arc_force)
double map_arc_force(const double x[5], double CR, double scale, int want_jac, double F[2], double J[8],
                     double dw[2]);
#endif

/* knot span i (3 <= i <= n - 1) with t[i] <= x < t[i + 1], clamped to the base interval */
static inline int span(const double *t, int n, double x) {
    if (x >= t[n]) return n - 1;
    if (x <= t[3]) return 3;
    int lo = 3, hi = n;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (x >= t[mid])
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* the four non-zero cubic B-splines at x and their derivatives (Piegl & Tiller A2.2) */
static inline void basis(const double *t, int i, double x, double N[4], double dN[4]) {
    double left[4], right[4], N2[3] = {0, 0, 0};
    N[0] = 1.0;
    for (int j = 1; j < 4; j++) {
        left[j] = x - t[i + 1 - j];
        right[j] = t[i + j] - x;
        double saved = 0.0;
        for (int r = 0; r < j; r++) {
            double temp = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        N[j] = saved;
        if (j == 2) {
            N2[0] = N[0];
            N2[1] = N[1];
            N2[2] = N[2];
        }
    }
    for (int r = 0; r < 4; r++) {
        double d = 0.0;
        if (r >= 1) d += N2[r - 1] / (t[i + r] - t[i - 3 + r]);
        if (r <= 2) d -= N2[r] / (t[i + 1 + r] - t[i - 2 + r]);
        dN[r] = 3.0 * d;
    }
}

#if MAP_DIMS == 2
/* out[k] = (value, d/ds, d/dbeta) of the two components of the spline (ts, tb, C): the force's
 * (MAP_TS, MAP_TB, MAP_C) or the flow table's, on the same axes */
static inline void spline2(const double *ts, const double *tb, const double *C, double s, double beta, double out[2][3]) {
    int ns = MAP_NS, nb = MAP_NB;
    double period = tb[nb] - tb[3];
    double b = tb[3] + py_mod(beta - tb[3], period);
    int i = span(ts, ns, s), j = span(tb, nb, b);
    double Ns[4], dNs[4], Nb[4], dNb[4];
    basis(ts, i, s, Ns, dNs);
    basis(tb, j, b, Nb, dNb);
    for (int k = 0; k < 2; k++) {
        double v = 0.0, vs = 0.0, vb = 0.0;
        for (int p = 0; p < 4; p++) {
            double row_v = 0.0, row_b = 0.0;
            for (int q = 0; q < 4; q++) {
                double c = C[((i - 3 + p) * nb + (j - 3 + q)) * 2 + k];
                row_v += Nb[q] * c;
                row_b += dNb[q] * c;
            }
            v += Ns[p] * row_v;
            vs += dNs[p] * row_v;
            vb += Ns[p] * row_b;
        }
        out[k][0] = v;
        out[k][1] = vs;
        out[k][2] = vb;
    }
}
#endif

#if MAP_DIMS == 3
/* out[k] = (value, d/ds, d/dphi, d/dbeta) of the nk components of the tensor spline (ts, tp, tb, C)
 * in (s, phi, beta), phi and beta periodic, C (MAP_NS, np, MAP_NB, nk): the force's (MAP_TP, MAP_C,
 * np MAP_NP, nk 2) or the flow table's over one period (MAP_QTP, MAP_QC, map_flows.c) */
static inline void spline3(const double *ts, const double *tp, const double *tb, const double *C, int np, int nk, double s,
                    double phi, double beta, double out[][4]) {
    int ns = MAP_NS, nb = MAP_NB;
    double p = tp[3] + py_mod(phi - tp[3], tp[np] - tp[3]);
    double b = tb[3] + py_mod(beta - tb[3], tb[nb] - tb[3]);
    int i = span(ts, ns, s), j = span(tp, np, p), m = span(tb, nb, b);
    double Ns[4], dNs[4], Np[4], dNp[4], Nb[4], dNb[4];
    basis(ts, i, s, Ns, dNs);
    basis(tp, j, p, Np, dNp);
    basis(tb, m, b, Nb, dNb);
    for (int k = 0; k < nk; k++) {
        double v = 0.0, vs = 0.0, vp = 0.0, vb = 0.0;
        for (int a = 0; a < 4; a++) {
            double pv = 0.0, pp = 0.0, pb = 0.0;
            for (int q = 0; q < 4; q++) {
                double bv = 0.0, bb = 0.0;
                for (int r = 0; r < 4; r++) {
                    double c = C[(((i - 3 + a) * np + (j - 3 + q)) * nb + (m - 3 + r)) * nk + k];
                    bv += Nb[r] * c;
                    bb += dNb[r] * c;
                }
                pv += Np[q] * bv;
                pp += dNp[q] * bv;
                pb += Np[q] * bb;
            }
            v += Ns[a] * pv;
            vs += dNs[a] * pv;
            vp += Ns[a] * pp;
            vb += Ns[a] * pb;
        }
        out[k][0] = v;
        out[k][1] = vs;
        out[k][2] = vp;
        out[k][3] = vb;
    }
}
#endif

#if MAP_DIMS == 4
/* out[k] = (value, d/ds, d/dphi, d/dbeta, d/du) of the nk components of the fed-groove map's tensor spline
 * (ts, tp, tb, tu, C) in (s, phi, beta, u), phi and beta periodic, C (MAP_NS, MAP_NP, MAP_NB, MAP_NU, nk):
 * supplykernels.spline4, in its order of operations */
static inline void spline4(const double *ts, const double *tp, const double *tb, const double *tu, const double *C,
                           int nk, double s, double phi, double beta, double u, double out[][5]) {
    int ns = MAP_NS, np = MAP_NP, nb = MAP_NB, nu = MAP_NU;
    double p = tp[3] + py_mod(phi - tp[3], tp[np] - tp[3]);
    double b = tb[3] + py_mod(beta - tb[3], tb[nb] - tb[3]);
    int i = span(ts, ns, s), j = span(tp, np, p), m = span(tb, nb, b), n = span(tu, nu, u);
    double N[4][4], dN[4][4];
    basis(ts, i, s, N[0], dN[0]);
    basis(tp, j, p, N[1], dN[1]);
    basis(tb, m, b, N[2], dN[2]);
    basis(tu, n, u, N[3], dN[3]);
    for (int k = 0; k < nk; k++) {
        double v = 0.0, vs = 0.0, vp = 0.0, vb = 0.0, vu = 0.0;
        for (int a = 0; a < 4; a++) {
            double pv = 0.0, pp = 0.0, pb = 0.0, pu = 0.0;
            for (int q = 0; q < 4; q++) {
                double bv = 0.0, bb = 0.0, bu = 0.0;
                for (int r = 0; r < 4; r++) {
                    double uv = 0.0, uu = 0.0;
                    const double *c = C + ((((size_t)(i - 3 + a) * np + (size_t)(j - 3 + q)) * nb
                                            + (size_t)(m - 3 + r)) * nu + (size_t)(n - 3)) * nk + k;
                    for (int w = 0; w < 4; w++) {
                        uv += N[3][w] * c[w * nk];
                        uu += dN[3][w] * c[w * nk];
                    }
                    bv += N[2][r] * uv;
                    bb += dN[2][r] * uv;
                    bu += N[2][r] * uu;
                }
                pv += N[1][q] * bv;
                pp += dN[1][q] * bv;
                pb += N[1][q] * bb;
                pu += N[1][q] * bu;
            }
            v += N[0][a] * pv;
            vs += dN[0][a] * pv;
            vp += N[0][a] * pp;
            vb += N[0][a] * pb;
            vu += N[0][a] * pu;
        }
        out[k][0] = v;
        out[k][1] = vs;
        out[k][2] = vp;
        out[k][3] = vb;
        out[k][4] = vu;
    }
}
#endif

#endif
