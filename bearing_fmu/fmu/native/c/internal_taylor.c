/* The Taylor internal behind its fitted-domain guard (bearing_fmu/taylor.py, guard.py,
 * _taylor_kernels.py, shortbearing.py), ported line by line so the force and Jacobian equal
 * the Python internal's to rounding:
 *
 *   F_i = force_scale (1 - eps^2)^-p sum_k c_ik u^e_k  +  sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u)
 *
 * u the scaled state about the expansion point, p the wall power, S the short-bearing
 * (Ocvirk) force. The polynomials are coefficient rows over their monomials in model_data.h
 * (codegen.taylor_polynomials): each monomial is computed once, by one multiplication from
 * its parent, and the force and its u-gradient are dot products of rows with them.
 *
 * Guard: d = max(excess over the fitted domain's bounds, (nn - radius) / size), nn the
 * distance in u to the nearest stored training state (a sweep over the points sorted by u_0, skipped while the state
 * stays within the radius of the point nearest to the previous one, as guard.NearestTraining
 * does). Outside (d > 1e-12): refused beyond domain_limit or with domain_action = discard,
 * else warned once per excursion (excursion()) and counted (the count at fmi2Terminate).
 * "fallback": the Reynolds internal of the same FMU (one of several internals, bn_parts.c), blended
 * with the surrogate over the band beyond the domain's edge as guard.DomainGuard does (fallback());
 * an FMU without it refuses "fallback" when set. The film report (BN_FLOWS_TAYLOR): taylor_film.c,
 * over the guard and the force this file gives it (taylor_internal.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#define BN_PART taylor /* its functions' names in an FMU of several internals */
#define BN_PART_TAYLOR 1 /* its part of model_data.h */
#include "bearing_native.h"
#include "model_data.h"
#include "taylor_internal.h"

/* meta = (y0, z0, omega0, pos_scale, vel_scale, force_scale, omega_rtol, order, wall_power, c0, shape_order) */
#define Y0 TAY_META[0]
#define Z0 TAY_META[1]
#define OMEGA0 TAY_META[2]
#define POS TAY_META[3]
#define VEL TAY_META[4]
#define FS TAY_META[5]
#define RTOL TAY_META[6]
#define WALLP TAY_META[8]
#define C0 TAY_META[9]

/* out[r] += sum_{j < n} W[r][j] M[j] for r < R (R even, n a multiple of 8), two rows per pass */
#if BN_AVX
__attribute__((target("avx2"))) static void dots_avx(const double *W, int R, int n, const double *M, double *out) {
    for (int r = 0; r + 1 < R; r += 2) {
        const double *w0 = W + (size_t)r * TAY_NM, *w1 = w0 + TAY_NM;
        bn_v4 a0 = {0.0, 0.0, 0.0, 0.0}, b0 = a0, a1 = a0, b1 = a0;
        for (int j = 0; j < n; j += 8) {
            bn_v4 m0 = *(const bn_v4 *)(M + j), m1 = *(const bn_v4 *)(M + j + 4);
            a0 += *(const bn_v4 *)(w0 + j) * m0;
            b0 += *(const bn_v4 *)(w0 + j + 4) * m1;
            a1 += *(const bn_v4 *)(w1 + j) * m0;
            b1 += *(const bn_v4 *)(w1 + j + 4) * m1;
        }
        bn_v4 s0 = a0 + b0, s1 = a1 + b1;
        out[r] += (s0[0] + s0[1]) + (s0[2] + s0[3]);
        out[r + 1] += (s1[0] + s1[1]) + (s1[2] + s1[3]);
    }
}
#endif

static void dots_plain(const double *W, int R, int n, const double *M, double *out) {
    for (int r = 0; r + 1 < R; r += 2) {
        const double *w0 = W + (size_t)r * TAY_NM, *w1 = w0 + TAY_NM;
#if BN_VEC
        /* the same four partial sums per row as the AVX2 kernel: lanes 0-1 of a, 2-3 of c, ... */
        bn_v2 a0 = {0.0, 0.0}, c0 = a0, b0 = a0, d0 = a0, a1 = a0, c1 = a0, b1 = a0, d1 = a0;
        for (int j = 0; j < n; j += 8) {
            bn_v2 m0 = *(const bn_v2 *)(M + j), m2 = *(const bn_v2 *)(M + j + 2);
            bn_v2 m4 = *(const bn_v2 *)(M + j + 4), m6 = *(const bn_v2 *)(M + j + 6);
            a0 += *(const bn_v2 *)(w0 + j) * m0;
            c0 += *(const bn_v2 *)(w0 + j + 2) * m2;
            b0 += *(const bn_v2 *)(w0 + j + 4) * m4;
            d0 += *(const bn_v2 *)(w0 + j + 6) * m6;
            a1 += *(const bn_v2 *)(w1 + j) * m0;
            c1 += *(const bn_v2 *)(w1 + j + 2) * m2;
            b1 += *(const bn_v2 *)(w1 + j + 4) * m4;
            d1 += *(const bn_v2 *)(w1 + j + 6) * m6;
        }
        bn_v2 s0 = a0 + b0, t0 = c0 + d0, s1 = a1 + b1, t1 = c1 + d1;
        out[r] += (s0[0] + s0[1]) + (t0[0] + t0[1]);
        out[r + 1] += (s1[0] + s1[1]) + (t1[0] + t1[1]);
#else
        double s0 = 0.0, s1 = 0.0;
        for (int j = 0; j < n; j++) {
            s0 += w0[j] * M[j];
            s1 += w1[j] * M[j];
        }
        out[r] += s0;
        out[r + 1] += s1;
#endif
    }
}

static void dots(const Instance *m, const double *W, int R, int n, const double *M, double *out) {
#if BN_AVX
    if (m->work.avx) {
        dots_avx(W, R, n, M, out);
        return;
    }
#else
    (void)m;
#endif
    dots_plain(W, R, n, M, out);
}

#if TAY_SHAPE
/* x ** n for an integer literal n, as numba computes it (square and multiply) */
static double ipow(double x, int n) {
    double r = 1.0, p = x;
    while (n) {
        if (n & 1) r *= p;
        n >>= 1;
        if (n) p *= p;
    }
    return r;
}

/* shortbearing.short_bearing_kernel: (Fy, Fz, dFy/d(y, z, vy, vz), dFz/d(...)) in SI */
static void short_bearing(double y, double z, double vy, double vz, double omega, double cr, double c0, int jac,
                          double out[10]) {
    double e = sqrt(y * y + z * z), eps = e / cr, ury, urz;
    if (e > 0.0) {
        ury = y / e;
        urz = z / e;
    } else {
        ury = 0.0;
        urz = -1.0;
    }
    double uty = -urz, utz = ury;
    double vr = vy * ury + vz * urz, vt = vy * uty + vz * utz;
    double A = eps * omega - 2.0 * vt / cr, B = 2.0 * vr / cr;
    double phi1 = atan2(B, A);
    double s2 = 1.0 - eps * eps, s = sqrt(s2), beta = eps / (1.0 + s);
    double jss = 0.0, jsc = 0.0, jcc = 0.0, dss = 0.0, dsc = 0.0, dcc = 0.0;
    for (int k = 0; k < 2; k++) {
        double phi = k == 0 ? phi1 + M_PI : phi1, sgn = k == 0 ? 1.0 : -1.0;
        double sp = sin(phi), cp = cos(phi);
        double g = phi - 2.0 * atan(beta * sp / (1.0 + beta * cp));
        double den = 1.0 + eps * cp, sg = s * sp / den, cg = (cp + eps) / den;
        double a = 0.5 * g - 0.5 * sg * cg;
        double b = 0.5 * sg * sg + eps * cg;
        double c = (0.5 + eps * eps) * g + 0.5 * sg * cg - 2.0 * eps * sg;
        jss += sgn * a / ipow(s, 3);
        jsc += sgn * b / ipow(s, 4);
        jcc += sgn * c / ipow(s, 5);
        if (jac) {
            double a_e = -(ipow(sg, 3)) / s2;
            double b_e = -sg * sg * cg / s2 + cg + eps * sg * sg / s2;
            double c_e = (2.0 * eps * g - (0.5 + eps * eps) * sg / s2 + 0.5 * sg * (sg * sg - cg * cg) / s2
                          - 2.0 * sg + 2.0 * eps * sg * cg / s2);
            dss += sgn * (3.0 * eps * a / ipow(s, 5) + a_e / ipow(s, 3));
            dsc += sgn * (4.0 * eps * b / ipow(s, 6) + b_e / ipow(s, 4));
            dcc += sgn * (5.0 * eps * c / ipow(s, 7) + c_e / ipow(s, 5));
        }
    }
    double fr = c0 * (A * jsc - B * jcc), ft = c0 * (A * jss - B * jsc);
    out[0] = fr * ury + ft * uty;
    out[1] = fr * urz + ft * utz;
    if (!jac) {
        for (int i = 2; i < 10; i++) out[i] = 0.0;
        return;
    }
    double fr_e = c0 * (A * dsc - B * dcc), ft_e = c0 * (A * dss - B * dsc);
    double fr_a = c0 * jsc, fr_b = -c0 * jcc, ft_a = c0 * jss, ft_b = -c0 * jsc;
    double einv = 1.0 / fmax(e, 1e-8 * cr);
    double eps_y = ury / cr, eps_z = urz / cr;
    double a_y = omega * ury / cr + 2.0 * vr * uty * einv / cr;
    double a_z = omega * urz / cr + 2.0 * vr * utz * einv / cr;
    double a_vy = -2.0 * uty / cr, a_vz = -2.0 * utz / cr;
    double b_y = 2.0 * vt * uty * einv / cr, b_z = 2.0 * vt * utz * einv / cr;
    double b_vy = 2.0 * ury / cr, b_vz = 2.0 * urz / cr;
    double gr_y = fr_e * eps_y + fr_a * a_y + fr_b * b_y;
    double gr_z = fr_e * eps_z + fr_a * a_z + fr_b * b_z;
    double gr_vy = fr_a * a_vy + fr_b * b_vy;
    double gr_vz = fr_a * a_vz + fr_b * b_vz;
    double gt_y = ft_e * eps_y + ft_a * a_y + ft_b * b_y;
    double gt_z = ft_e * eps_z + ft_a * a_z + ft_b * b_z;
    double gt_vy = ft_a * a_vy + ft_b * b_vy;
    double gt_vz = ft_a * a_vz + ft_b * b_vz;
    double wy = (fr * uty - ft * ury) * einv, wz = (fr * utz - ft * urz) * einv;
    out[2] = ury * gr_y + uty * gt_y + wy * uty;
    out[3] = ury * gr_z + uty * gt_z + wy * utz;
    out[4] = ury * gr_vy + uty * gt_vy;
    out[5] = ury * gr_vz + uty * gt_vz;
    out[6] = urz * gr_y + utz * gt_y + wz * uty;
    out[7] = urz * gr_z + utz * gt_z + wz * utz;
    out[8] = urz * gr_vy + utz * gt_vy;
    out[9] = urz * gr_vz + utz * gt_vz;
}

/* _shape_terms: add the shape columns sum_l M_l(u) S to out (scaled units), with jac also dF/du;
 * M_0..M_3 multiply (Fy by S_y, Fy by S_z, Fz by S_y, Fz by S_z) */
static void shape_terms(const Instance *m, double y, double z, double vy, double vz, double omega, const double *M,
                        int jac, double out[10]) {
    double r[10], sv[4] = {0, 0, 0, 0}, sg[16];
    short_bearing(y, z, vy, vz, omega, POS, C0, jac, r);
    dots(m, &TAY_SVAL[0][0], 4, TAY_N_SVAL, M, sv);
    double sy = r[0], sz = r[1];
    for (int i = 0; i < 2; i++) out[i] += (sv[2 * i] * sy + sv[2 * i + 1] * sz) / FS;
    if (!jac) return;
    for (int k = 0; k < 16; k++) sg[k] = 0.0;
    dots(m, &TAY_SGRAD[0][0], 16, TAY_N_SGRAD, M, sg);
    for (int v = 0; v < 4; v++) {
        double sc = v < 2 ? POS : VEL, dsy = r[2 + v] * sc, dsz = r[6 + v] * sc;
        for (int i = 0; i < 2; i++)
            out[2 + 4 * i + v] += (sg[4 * (2 * i) + v] * sy + sv[2 * i] * dsy + sg[4 * (2 * i + 1) + v] * sz
                                   + sv[2 * i + 1] * dsz) / FS;
    }
}
#endif

/* ------------------------------------------------------------------------------ the guard */

/* _domain_distance_nb: excess over the fitted domain's bounds */
static double bounds_distance(double y, double z, double vy, double vz) {
    const double *dom = TAY_DOM;
    double cr = dom[2], vs = dom[3];
    double u[4] = {(y - dom[0]) / cr, (z - dom[1]) / cr, vy / vs, vz / vs};
    double ecc_max = dom[4], cy = dom[5], cz = dom[6], r = dom[7], vmax = dom[8];
    double dist = ecc_max > 0 ? hypot(y, z) / cr / ecc_max - 1.0 : INFINITY;
    if (r > 0) dist = fmax(dist, hypot(u[0] - cy, u[1] - cz) / r - 1.0);
    if (vmax > 0)
        dist = fmax(dist, hypot(u[2], u[3]) / vmax - 1.0);
    else if (u[2] != 0.0 || u[3] != 0.0)
        dist = INFINITY;
    for (int v = 0; v < 4; v++) {
        double lo = dom[9 + v], hi = dom[13 + v], half = 0.5 * (hi - lo);
        if (half > 0) dist = fmax(dist, fabs(u[v] - 0.5 * (hi + lo)) / half - 1.0);
    }
    return dist;
}

static void scaled(double y, double z, double vy, double vz, double u[4]) {
    u[0] = (y - Y0) / POS;
    u[1] = (z - Z0) / POS;
    u[2] = vy / VEL;
    u[3] = vz / VEL;
}

#if TAY_NN > 0
static double point_distance(const double u[4], int i) {
    const double *p = TAY_NN_POINTS + 4 * i;
    double a = u[0] - p[0], b = u[1] - p[1], c = u[2] - p[2], d = u[3] - p[3];
    return sqrt(a * a + b * b + c * c + d * d);
}

/* the nearest stored state: distance, index. The points are sorted by their first coordinate
 * (codegen), so the search sweeps outward from the query's place in that order and stops on
 * each side once the first coordinate alone is farther than the best distance so far. */
static double nearest(const double u[4], int *index) {
    int lo = 0, hi = TAY_NN;
    while (lo < hi) { /* first point with p0 >= u0 */
        int mid = (lo + hi) / 2;
        if (TAY_NN_POINTS[4 * mid] < u[0])
            lo = mid + 1;
        else
            hi = mid;
    }
    double best = INFINITY;
    int k = 0, up = lo, down = lo - 1;
    while (up < TAY_NN || down >= 0) {
        for (int side = 0; side < 2; side++) {
            int i = side == 0 ? up : down;
            if (i < 0 || i >= TAY_NN) continue;
            const double *p = TAY_NN_POINTS + 4 * i;
            double a = u[0] - p[0];
            if (a * a >= best) { /* every point beyond on this side is farther */
                if (side == 0) up = TAY_NN;
                else down = -1;
                continue;
            }
            double b = u[1] - p[1], c = u[2] - p[2], d = u[3] - p[3];
            double s = a * a + b * b + c * c + d * d;
            if (s < best) {
                best = s;
                k = i;
            }
            if (side == 0) up++;
            else down--;
        }
    }
    *index = k;
    return sqrt(best);
}
#endif

/* DomainGuard.distance: exact when > 0, an upper bound <= 0 inside */
double tay_domain_distance(Instance *m, double y, double z, double vy, double vz) {
    double d = bounds_distance(y, z, vy, vz);
#if TAY_NN > 0
    if (d != d) return d;
    double u[4], nn;
    scaled(y, z, vy, vz, u);
    if (m->work.last_nn >= 0) {
        double bound = point_distance(u, m->work.last_nn);
        if (bound <= TAY_NN_RADIUS) return fmax(d, (bound - TAY_NN_RADIUS) / TAY_NN_SIZE);
    }
    nn = nearest(u, &m->work.last_nn);
    return fmax(d, (nn - TAY_NN_RADIUS) / TAY_NN_SIZE);
#else
    (void)m;
    return d;
#endif
}

/* which part of the domain the state violates, in words */
static void reasons(double y, double z, double vy, double vz, char *out, size_t n) {
    char a[32], b[32], c[32], d[32], e[32];
    size_t off = 0;
    out[0] = 0;
    double bd = bounds_distance(y, z, vy, vz);
    if (bd > 1e-12) off += (size_t)snprintf(out, n, "%s per cent beyond its bounds", bn_num(a, 32, 100 * bd, 3));
#if TAY_NN > 0
    double u[4];
    int k;
    scaled(y, z, vy, vz, u);
    double nn = nearest(u, &k);
    if (nn > TAY_NN_RADIUS && off < n)
        snprintf(out + off, n - off, "%snearest training state %s away in the scaled state u, %s x their radius %s, "
                 "%s per cent of the domain's size %s beyond it", off ? " and " : "", bn_num(a, 32, nn, 3),
                 bn_num(b, 32, nn / TAY_NN_RADIUS, 3), bn_num(c, 32, TAY_NN_RADIUS, 3),
                 bn_num(d, 32, 100 * (nn - TAY_NN_RADIUS) / TAY_NN_SIZE, 3), bn_num(e, 32, TAY_NN_SIZE, 3));
#endif
    if (!out[0]) snprintf(out, n, "at its edge");
}

/* ------------------------------------------------------------------------------ the internal */

int bn_setup(Instance *m) {
    static const char *const names[4] = {"D", "L", "CR", "mu"};
#if BN_AVX
    __builtin_cpu_init();
    m->work.avx = __builtin_cpu_supports("avx2") != 0;
#endif
    for (int i = 0; i < 4; i++) {
        double a = TAY_PARAMS[i], b = m->r[VR_D + i];
        if (fabs(a - b) > 1e-9 * fmax(fabs(a), fabs(b))) {
            char x[32], w[32];
            snprintf(m->msg, sizeof m->msg, "surrogate file '%s': fitted for bearing %s = %s, but used with %s = %s "
                     "(a surrogate is only valid for the bearing it was fitted to)", TAY_SOURCE, names[i],
                     bn_num(x, 32, a, 17), names[i], bn_num(w, 32, b, 17));
            return 1;
        }
    }
    return 0;
}

static int refuse_taylor(Instance *m, int wrong_omega, const double x[5]) {
    char a[32], b[32], c[32], d[32];
    if (wrong_omega) {
        snprintf(m->msg, sizeof m->msg, "Taylor surrogate was fitted at omega = %s rad/s; got omega = %s rad/s",
                 bn_num(a, 32, OMEGA0, 6), bn_num(b, 32, x[4], 6));
    } else {
        double eps = hypot(x[0], x[1]) / TAY_PARAMS[2];
        snprintf(m->msg, sizeof m->msg, "eccentricity ratio %s >= 1: the journal (y = %s m, z = %s m) is at or beyond "
                 "the bearing wall (CR = %s m)%s", bn_num(a, 32, eps, 4), bn_num(b, 32, x[0], 4),
                 bn_num(c, 32, x[1], 4), bn_num(d, 32, TAY_PARAMS[2], 4), TAY_WALL_WHY);
    }
    return 1;
}

/* the guard: 0 (evaluate), or 1 with m->msg (refused) */
int tay_guard(Instance *m, const double x[5], int *ood) {
    double y = x[0], z = x[1], vy = x[2], vz = x[3];
    double d = tay_domain_distance(m, y, z, vy, vz);
    *ood = !(d <= 1e-12);
    if (!*ood) return 0;
    char a[32], b[32], c[32], e[32], f[32], why[600];
    double ecc = hypot(y, z) / TAY_PARAMS[2];
    char where[256];
    snprintf(where, sizeof where, "y = %s m, z = %s m, vy = %s m/s, vz = %s m/s (eccentricity ratio %.3f)",
             bn_num(a, 32, y, 4), bn_num(b, 32, z, 4), bn_num(c, 32, vy, 4), bn_num(e, 32, vz, 4), ecc);
    if (ecc >= 1.0) {
        snprintf(m->msg, sizeof m->msg, "eccentricity ratio %s >= 1: the journal is at or beyond the wall (%s); the "
                 "Taylor surrogate does not evaluate there", bn_num(a, 32, ecc, 4), where);
        return 1;
    }
    double limit = m->r[VR_OPT_DOMAIN_LIMIT];
    int discard = strcmp(m->eff[S_OPT_DOMAIN_ACTION], "discard") == 0;  /* domain_action or its enumeration */
    if (d > limit || discard) {
        reasons(y, z, vy, vz, why, sizeof why);
        char lim[200];
        if (d > limit)
            snprintf(lim, sizeof lim, "more than domain_limit = %s beyond", bn_num(f, 32, limit, 6));
        else
            snprintf(lim, sizeof lim, "outside (domain_action = 'discard')");
        snprintf(m->msg, sizeof m->msg, "state %s per cent beyond the surrogate's fitted domain (%s), %s: %s",
                 bn_num(f, 32, 100 * d, 3), why, lim, where);
        return 1;
    }
    return 0;
}

/* An evaluated state outside the fitted domain: warned when an excursion begins, i.e. when the
 * last committed state (out_of_domain, restored with an FMU state) was inside, once per
 * communication point (a host's Newton iterates of one step all start from its state), and
 * counted. A refused state (wrong speed, the wall) never counts: the zero-speed start a master
 * initialises with used to spend the one warning of an instance. */
static void excursion(Instance *m, const double x[5], const char *what) {
    Work *w = &m->work;
    if (w->quiet || m->b[B_OUT_OF_DOMAIN] || (w->excursions > 0 && w->excursion_t[1] == m->t)) return;
    if (w->excursions++ == 0) w->excursion_t[0] = m->t;
    w->excursion_t[1] = m->t;
    char a[32], b[32], c[32], e[32], t[32], why[600], where[256];
    snprintf(where, sizeof where, "y = %s m, z = %s m, vy = %s m/s, vz = %s m/s (eccentricity ratio %.3f)",
             bn_num(a, 32, x[0], 4), bn_num(b, 32, x[1], 4), bn_num(c, 32, x[2], 4), bn_num(e, 32, x[3], 4),
             hypot(x[0], x[1]) / TAY_PARAMS[2]);
    reasons(x[0], x[1], x[2], x[3], why, sizeof why);
    bn_log(m, BN_WARNING, "t = %s s: state outside the surrogate's fitted domain (%s) at %s; %s (excursion %d: "
           "warned once per excursion, counted at terminate)", bn_num(t, 32, m->t, 10), why, where, what,
           w->excursions);
}

/* the surrogate at x (the guard passed) */
int tay_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2]) {
    const double y = x[0], z = x[1], vy = x[2], vz = x[3], omega = x[4];
    /* _check_nb: the inputs are finite (the FMI layer checked them); the speed */
    if (fabs(omega - OMEGA0) > RTOL * fmax(fabs(OMEGA0), 1.0)) return refuse_taylor(m, 1, x);
    if (!(y * y + z * z < TAY_CR2)) return refuse_taylor(m, 0, x);
    double u[4], M[TAY_NM] BN_ALIGN32;
    scaled(y, z, vy, vz, u);
    monomials(u, M);
    if (!want_jac) { /* _force_nb (+ _force_shape_nb) */
        double f[2] = {0.0, 0.0};
        dots(m, &TAY_VAL[0][0], 2, TAY_N_VAL, M, f);
        double s = FS;
        if (WALLP != 0.0) {
            double cr = POS, q = 1.0 - (y * y + z * z) / (cr * cr);
            if (!(q > 0.0)) return refuse_taylor(m, 0, x);
            s *= pow(q, -WALLP);
        }
        F[0] = f[0] * s;
        F[1] = f[1] * s;
#if TAY_SHAPE
        {
            double cr = POS;
            if (!(1.0 - (y * y + z * z) / (cr * cr) > 0.0)) return refuse_taylor(m, 0, x);
            double out[10] = {0.0, 0.0};
            shape_terms(m, y, z, vy, vz, omega, M, 0, out);
            F[0] = F[0] + out[0] * FS;
            F[1] = F[1] + out[1] * FS;
        }
#endif
        return 0;
    }
    /* _force_jac_nb (+ shape terms), then _to_si */
    double out[10];
    for (int i = 0; i < 10; i++) out[i] = 0.0;
    dots(m, &TAY_VAL[0][0], 2, TAY_N_VAL, M, out);
    dots(m, &TAY_GRAD[0][0], 8, TAY_N_GRAD, M, out + 2);
    if (WALLP != 0.0) {
        double cr = POS, yc = y / cr, zc = z / cr, q = 1.0 - (yc * yc + zc * zc);
        if (!(q > 0.0)) return refuse_taylor(m, 0, x);
        double h = pow(q, -WALLP), gy = 2.0 * WALLP * yc * h / q, gz = 2.0 * WALLP * zc * h / q;
        for (int i = 0; i < 2; i++) {
            double P = out[i];
            int b = 2 + 4 * i;
            out[b] = h * out[b] + P * gy;
            out[b + 1] = h * out[b + 1] + P * gz;
            out[b + 2] *= h;
            out[b + 3] *= h;
            out[i] = h * P;
        }
    }
#if TAY_SHAPE
    {
        double cr = POS;
        if (!(1.0 - (y * y + z * z) / (cr * cr) > 0.0)) return refuse_taylor(m, 0, x);
        shape_terms(m, y, z, vy, vz, omega, M, 1, out);
    }
#endif
    double gq = FS / POS, gv = FS / VEL;
    F[0] = out[0] * FS;
    F[1] = out[1] * FS;
    for (int i = 0; i < 2; i++) {
        J[4 * i + 0] = out[2 + 4 * i] * gq;
        J[4 * i + 1] = out[3 + 4 * i] * gq;
        J[4 * i + 2] = out[4 + 4 * i] * gv;
        J[4 * i + 3] = out[5 + 4 * i] * gv;
    }
    dw[0] = dw[1] = 0.0; /* defined at its fitted speed only (any other is refused) */
    return 0;
}

#if BN_HOLDS_REYNOLDS
#define FALLBACK_BAND 0.1 /* guard.FALLBACK_BAND: Taylor and Reynolds blended from the edge to 10 % beyond it */

/* the weight of Reynolds at domain distance d: 0 at the edge, a smoothstep to 1 at FALLBACK_BAND */
double tay_blend_weight(double d) {
    double s = fmin(fmax(d / FALLBACK_BAND, 0.0), 1.0);
    return s * s * (3.0 - 2.0 * s);
}

/* domain_action = fallback outside the domain (d > 0): the Reynolds force, blended with the
 * surrogate's inside the band; the weight's gradient (central differences of the domain distance,
 * steps 1e-7 of the scales, as guard.DomainGuard._blend_gradient) joins the tangent, since across
 * the band the force changes by F_reynolds - F_taylor */
static int fallback(Instance *m, const double x[5], double d, int want_jac, double F[2], double J[8], double dw[2]) {
    double Fr[2], Jr[8], dwr[2], Ft[2], Jt[8], dwt[2], g[4];
    if (bn_fallback_eval(m, x, want_jac, Fr, Jr, dwr)) return 1;
    double w = tay_blend_weight(d);
    if (w >= 1.0) {
        memcpy(F, Fr, sizeof Fr);
        if (want_jac) {
            memcpy(J, Jr, sizeof Jr);
            memcpy(dw, dwr, sizeof dwr);
        }
        return 0;
    }
    if (tay_eval(m, x, want_jac, Ft, Jt, dwt)) return 1;
    for (int i = 0; i < 2; i++) F[i] = (1.0 - w) * Ft[i] + w * Fr[i];
    if (!want_jac) return 0;
    const double h[4] = {1e-7 * POS, 1e-7 * POS, 1e-7 * VEL, 1e-7 * VEL};
    for (int v = 0; v < 4; v++) {
        double hi[4] = {x[0], x[1], x[2], x[3]}, lo[4] = {x[0], x[1], x[2], x[3]};
        hi[v] += h[v];
        lo[v] -= h[v];
        g[v] = (tay_blend_weight(tay_domain_distance(m, hi[0], hi[1], hi[2], hi[3])) -
                tay_blend_weight(tay_domain_distance(m, lo[0], lo[1], lo[2], lo[3]))) / (2 * h[v]);
    }
    for (int r = 0; r < 2; r++) {
        for (int c = 0; c < 4; c++)
            J[4 * r + c] = (1.0 - w) * Jt[4 * r + c] + w * Jr[4 * r + c] + (Fr[r] - Ft[r]) * g[c];
        dw[r] = (1.0 - w) * dwt[r] + w * dwr[r];
    }
    return 0;
}
#endif

int bn_eval(Instance *m, const double x[5], int want_jac, double F[2], double J[8], double dw[2], int *ood) {
    if (tay_guard(m, x, ood)) return 1;
#if BN_HOLDS_REYNOLDS
    if (*ood && strcmp(m->eff[S_OPT_DOMAIN_ACTION], "fallback") == 0) {
        if (fallback(m, x, tay_domain_distance(m, x[0], x[1], x[2], x[3]), want_jac, F, J, dw)) return 1;
        excursion(m, x, "the Reynolds internal evaluates such states");
        return 0;
    }
#endif
    if (tay_eval(m, x, want_jac, F, J, dw)) return 1;
    if (*ood) excursion(m, x, "its value is an extrapolation");
    return 0;
}

void bn_option_derivative(Instance *m, const double x[5], int k, double dF[2], double dJ[8]) {
    (void)m; (void)x; (void)k; /* domain_limit decides refusals only: the force does not depend on it */
    dF[0] = dF[1] = 0.0;
    for (int i = 0; i < 8; i++) dJ[i] = 0.0;
}

void bn_release(Instance *m) { (void)m; } /* nothing allocated */
