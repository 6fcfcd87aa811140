/* The FMI 2.0 calling sequence of the native bearing FMU.
 *
 * Which call is allowed in which mode is bearing_fmu/fmi_order.py's table (the Python FMU's
 * too), generated into model_config.h as one bit mask per call (BN_ALLOW_<call>; bit k: Mode k).
 * The FMI 2.0 layer (fmi2_bearing.c, fmi2_modes.c) asks bn_order_refused at the top of every
 * function that the table restricts. */
#include <stdio.h>
#include <string.h>

#include "fmi2_layer.h"

static const char *const MODE_NAMES[] = BN_MODE_NAMES;
static const int STAGE[] = {0, 1, 2, 2, 2, 3}; /* each mode's place in an instance's life (fmi_order._STAGE) */

int bn_order_refused(Instance *m, const char *call, unsigned allowed, int kind) {
    if (allowed & (1u << m->mode)) return 0;
    const char *mode = MODE_NAMES[m->mode];
    int me = m->type == fmi2ModelExchange;
    if ((kind == BN_CS_ONLY && me) || (kind == BN_ME_ONLY && !me)) {
        bn_log(m, fmi2Error, "%s in %s: a %s call; this instance is a %s one", call, mode,
               me ? "Co-Simulation" : "Model Exchange", me ? "Model Exchange" : "Co-Simulation");
        return 1;
    }
    unsigned never = me ? 1u << MODE_STEP : (1u << MODE_EVENT) | (1u << MODE_CONTINUOUS);
    char here[200] = "";
    int lo = 3, hi = 0, stage = STAGE[m->mode];
    for (int k = 0; k <= MODE_TERMINATED; k++) {
        if (!(allowed & (1u << k))) continue;
        lo = STAGE[k] < lo ? STAGE[k] : lo;
        hi = STAGE[k] > hi ? STAGE[k] : hi;
        size_t n = strlen(here);
        if (!(never & (1u << k))) snprintf(here + n, sizeof here - n, "%s%s", n ? " or " : "", MODE_NAMES[k]);
    }
    /* what to do instead, from where the instance is: before, after or beside the allowed modes */
    const char *hint;
    if (strcmp(call, "terminate") == 0 && stage < 2)
        hint = "nothing to terminate: the instance was never initialised (free it, or fmi2Reset)";
    else if (stage > hi)
        hint = m->mode == MODE_TERMINATED ? "too late: the instance is terminated (fmi2Reset starts it over)"
               : stage == 2 ? "too late: the instance is initialised (fmi2Reset starts it over)"
                            : "too late: the instance is in Initialization Mode (fmi2Reset starts it over)";
    else if (stage < lo)
        hint = stage == 1 ? "call exitInitializationMode first"
               : (allowed & (1u << MODE_INIT))
                   ? "call enterInitializationMode first"
                   : "initialise it first (enterInitializationMode, then exitInitializationMode)";
    else
        hint = m->mode == MODE_EVENT ? "call enterContinuousTimeMode first"
               : m->mode == MODE_CONTINUOUS ? "call enterEventMode first" : "call exitInitializationMode first";
    bn_log(m, fmi2Error, "%s in %s: not allowed there (FMI 2.0: in %s only); %s", call, mode, here, hint);
    return 1;
}
