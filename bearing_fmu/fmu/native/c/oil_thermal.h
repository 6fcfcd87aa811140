/* The oil's viscosity laws and the film's effective temperature in C (ports of
 * bearing_fmu/physics/oil.py: Walther through two points, Vogel; and physics/thermal.py
 * film_temperature: the heat balance at a fixed journal state, quasi-static or lagged by the
 * residence time, solved by Brent's method as scipy's brentq). The model layer's, for the native
 * FMU's thermal ports (oil_thermal.c, included by bearing_model.c); compiled alone with RS_EXPORT for the ctypes comparison with Python
 * (bearing_fmu/fmu/native/solver_lib.py, tests/test_native_thermal.py). */
#ifndef OIL_THERMAL_H
#define OIL_THERMAL_H

#include <stddef.h>

#if defined(RS_EXPORT)
#if defined(_WIN32)
#define OT_API __declspec(dllexport)
#else
#define OT_API __attribute__((visibility("default")))
#endif
#else /* in an FMU: included by bearing_model.c, every function static (their names stay the FMU's own) */
#define OT_API static
#endif

enum { OT_NONE = 0, OT_WALTHER = 1, OT_VOGEL = 2 }; /* ports.OIL_LAWS' order */

typedef struct {
    int law;
    double c[3];            /* walther: A, B of log10(log10(nu [cSt] + 0.7)) = A - B log10(T); vogel: a [Pa s], b, c [K] */
    double T_min, T_max;    /* the range the law may be used in [K] */
    double density;         /* [kg/m^3] */
    double heat_capacity;   /* [J/(kg K)] */
    double rise_factor;     /* k of T_eff = T_supply + k dT */
} ot_oil;

#endif
