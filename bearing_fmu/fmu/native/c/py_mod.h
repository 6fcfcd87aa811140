/* Python's float modulo (numpy's np.mod too): the result has the sign of the divisor. A header
 * (static inline: no warning where a unit includes it unused) so that each file including it keeps every function of its own static: the force
 * map (internal_map.c) and the Reynolds solver's grid (reynolds_solver.c). */
#ifndef PY_MOD_H
#define PY_MOD_H

#include <math.h>

static inline double py_mod(double x, double p) {
    double r = fmod(x, p);
    if (r != 0.0) {
        if ((p < 0) != (r < 0)) r += p;
    } else {
        r = copysign(0.0, p);
    }
    return r;
}

#endif
