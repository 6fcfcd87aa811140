/* What the files of the FMI 3.0 layer share: fmi3_bearing.c (logging, instances, modes, values),
 * fmi3_state.c (FMU states), fmi3_derivatives.c and fmi3_modes.c (the calling sequence, the live
 * instances, Model Exchange, Co-Simulation and what this FMU does not provide). */
#ifndef FMI3_LAYER_H
#define FMI3_LAYER_H

#include "bearing_values.h"
#include "fmi3_config.h"

#if !BN_FMI3
#error "the FMI 3.0 layer is compiled with BN_FMI_VERSION=3 (sources/buildDescription.xml)"
#endif

/* log an error and return fmi3Error */
fmi3Status bn3_fail(Instance *m, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* 0 if fmi3<call> is allowed in the instance's mode (`allowed`: its BN3_ALLOW_ mask), else 1
 * with an fmi3Error logged naming the call, the mode and what to do instead */
int bn3_refused(Instance *m, const char *call, unsigned allowed, int kind);
#define ORDER3(call, kind) \
    if (bn3_refused(m, "fmi3" #call, BN3_ALLOW_##call, kind)) return fmi3Error

/* the outputs for a get (Initialization Mode: computed; Model Exchange: computed when the inputs
 * changed, a refused state fmi3Discard): fmi3OK, fmi3Discard or fmi3Error, logged */
fmi3Status bn3_outputs(Instance *m, const char *call, const char *name);

/* the live instances (a second fmi3FreeInstance of one is recognised): add; remove (0: not live) */
void bn3_live_add(Instance *m);
int bn3_live_remove(Instance *m);

#endif
