/* The film's friction in closed form for the full 360 deg bore, and its friction power (ports of
 * bearing_fmu/physics/solver/film.py full_bore_friction and _report, whose docstrings give the
 * definitions, in their order of operations: pow(R, 3) is Python's R ** 3), and the state in the
 * map's reduced coordinates (forcemap.reduced). Included by reynolds_film.c (the Reynolds film
 * report of the full bore), by internal_map.c (the map's force; map_flows.c its film report,
 * film.reduced_report and grooved_report) and by
 * taylor_film.c (the Taylor surrogate's, the same reduction): one definition for all, a header
 * of static inline functions (a file that does not use one is not warned). */
#ifndef FILM_FRICTION_H
#define FILM_FRICTION_H
#include <math.h>
#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Couette torque [N m] of the full bore at the eccentricity ratio eps: 2 pi mu omega R^3 L /
 * (CR sqrt(1 - eps^2)) (the integral of 1/h over the circle, exactly) */
static inline double ff_couette(double mu, double omega, double R, double L, double CR, double eps) {
    return 2.0 * M_PI * mu * omega * pow(R, 3.0) * L / (CR * sqrt(1.0 - eps * eps));
}

/* pressure (Poiseuille) torque [N m] of the full bore: (y Fz - z Fy) / 2, F the film force [N] */
static inline double ff_pressure(double y, double z, const double F[2]) {
    return 0.5 * (y * F[1] - z * F[0]);
}

/* friction power [W] of any film: T omega - F . v, T = tc + tp the drag torque */
static inline double ff_power(double tc, double tp, double omega, const double F[2], double vy, double vz) {
    return (tc + tp) * omega - (F[0] * vy + F[1] * vz);
}

/* the state in the line-of-centres frame (forcemap.reduced): returns eps = e / CR; (cp, sp) the
 * unit vector toward the journal, a = max(eps, eps_floor) omega - 2 v_t / CR, c = 2 v_r / CR (the
 * map's force: eps_floor MAP_EPS_MIN, as map_force; a film report: 0, as film.reduced_report) */
static inline double ff_reduce(const double x[5], double CR, double eps_floor, double *cp, double *sp, double *a,
                               double *c) {
    double e = hypot(x[0], x[1]);
    if (e > 0.0) {
        *cp = x[0] / e;
        *sp = x[1] / e;
    } else {
        *cp = 1.0;
        *sp = 0.0;
    }
    double eps = e / CR, vr = x[2] * *cp + x[3] * *sp, vt = -x[2] * *sp + x[3] * *cp;
    *a = fmax(eps, eps_floor) * x[4] - 2.0 * vt / CR;
    *c = 2.0 * vr / CR;
    return eps;
}
#endif
