/* What the files of the FMI 3.0 layer share: fmi3_bearing.c (logging, instances, modes, values),
 * fmi3_state.c (FMU states), fmi3_derivatives.c and fmi3_modes.c (the calling sequence, Model
 * Exchange, Co-Simulation and what this FMU does not provide), over the model layer
 * (bearing_values.h), the same code as under the FMI 2.0 layer. */
#ifndef FMI3_LAYER_H
#define FMI3_LAYER_H

#include "bearing_values.h"
#include "fmi3_config.h"

#if !BN_FMI3
#error "the FMI 3.0 layer is compiled with BN_FMI_VERSION=3 (sources/buildDescription.xml)"
#endif

#define bn3_fail BN_NAME(BN_ID, bn3_fail)
#define bn3_refused BN_NAME(BN_ID, bn3_refused)
#define bn3_outputs BN_NAME(BN_ID, bn3_outputs)

/* log an error and return fmi3Error */
BN_HIDDEN fmi3Status bn3_fail(Instance *m, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* 0 if fmi3<call> is allowed in the instance's mode (`allowed`: its BN3_ALLOW_ mask), else 1
 * with an fmi3Error logged naming the call, the mode and what to do instead */
BN_HIDDEN int bn3_refused(Instance *m, const char *call, unsigned allowed, int kind);
#define ORDER3(call, kind) \
    if (bn3_refused(m, "fmi3" #call, BN3_ALLOW_##call, kind)) return fmi3Error

/* the outputs for a get: the model layer's bn_outputs, and an fmi3Error in Instantiated (initial =
 * calculated: no value yet) */
BN_HIDDEN fmi3Status bn3_outputs(Instance *m, const char *call, const char *name);

#endif
