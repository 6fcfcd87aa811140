/* What the files of the FMI 2.0 layer share: fmi2_bearing.c (logging, instances, modes, values),
 * fmi2_modes.c (FMU states, derivatives, Co-Simulation, Model Exchange) and fmi2_order.c (the
 * calling sequence), over the model layer (bearing_values.h). */
#ifndef FMI2_LAYER_H
#define FMI2_LAYER_H

#include "bearing_values.h"

#if BN_FMI3
#error "the FMI 2.0 layer is compiled without BN_FMI_VERSION=3"
#endif

#define bn2_fail BN_NAME(BN_ID, bn2_fail)
/* log an error and return fmi2Error */
BN_HIDDEN fmi2Status bn2_fail(Instance *m, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* refuse `call` (an FMI 2.0 function without "fmi2") unless the instance's mode allows it (fmi2_order.c) */
#define ORDER(call, kind) \
    if (bn_order_refused(m, #call, BN_ALLOW_##call, kind)) return fmi2Error

#endif
