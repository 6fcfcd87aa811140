/* What the two files of the FMI 3.0 layer share: fmi3_bearing.c (logging, instances, modes,
 * values, FMU states, derivatives) and fmi3_modes.c (dependencies, Model Exchange, Co-Simulation
 * and what this FMU does not provide), over the model layer (bearing_calls.h), the same code as
 * under the FMI 2.0 layer. */
#ifndef FMI3_LAYER_H
#define FMI3_LAYER_H

#include "bearing_calls.h"
#include "fmi3_config.h"

#if !BN_FMI3
#error "the FMI 3.0 layer is compiled with BN_FMI_VERSION=3 (sources/buildDescription.xml)"
#endif

/* the instance, and fmi3<call> refused unless allowed in the instance's mode (its BN3_ALLOW_ mask
 * from fmi3.py ALLOWED3) for an instance of `kind` (BN_ANY_TYPE, BN_CS_ONLY, BN_ME_ONLY) */
#define INSTANCE Instance *m = instance; if (!m) return fmi3Error
#define ORDER3(call, kind) if (bn_order_refused(m, "fmi3" #call, BN3_ALLOW_##call, kind)) return fmi3Error

#endif
