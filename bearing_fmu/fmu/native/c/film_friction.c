/* The film's friction in closed form for the full 360 deg bore, and its friction power (ports of
 * bearing_fmu/physics/film.py full_bore_friction and _report, whose docstrings give the
 * definitions, in their order of operations: pow(R, 3) is Python's R ** 3). Included by
 * reynolds_film.c (the Reynolds film report of the full bore) and by map_flows.c (the map's,
 * film.reduced_report and grooved_report): one definition for both, every function static in either. */
#ifndef FILM_FRICTION_C
#define FILM_FRICTION_C
#include <math.h>

#ifndef FF_NO_FULL_BORE /* a grooved map's report (map_flows.c) integrates over its film's segments */
/* Couette torque [N m] of the full bore at the eccentricity ratio eps: 2 pi mu omega R^3 L /
 * (CR sqrt(1 - eps^2)) (the integral of 1/h over the circle, exactly) */
static double ff_couette(double mu, double omega, double R, double L, double CR, double eps) {
    return 2.0 * M_PI * mu * omega * pow(R, 3.0) * L / (CR * sqrt(1.0 - eps * eps));
}
#endif

/* pressure (Poiseuille) torque [N m] of the full bore: (y Fz - z Fy) / 2, F the film force [N] */
static double ff_pressure(double y, double z, const double F[2]) {
    return 0.5 * (y * F[1] - z * F[0]);
}

/* friction power [W] of any film: T omega - F . v, T = tc + tp the drag torque */
static double ff_power(double tc, double tp, double omega, const double F[2], double vy, double vz) {
    return (tc + tp) * omega - (F[0] * vy + F[1] * vz);
}
#endif
