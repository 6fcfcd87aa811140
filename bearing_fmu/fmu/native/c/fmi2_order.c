/* The FMI 2.0 calling sequence of the native bearing FMU, and its list of live instances.
 *
 * Which call is allowed in which mode is bearing_fmu/fmi_order.py's table (the Python FMU's
 * too), generated into model_config.h as one bit mask per call (BN_ALLOW_<call>; bit k: Mode k).
 * fmi2_bearing.c asks bn_order_refused at the top of every function that the table restricts. */
#include <stdio.h>
#include <string.h>

#include "bearing_native.h"

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

/* fmi2FreeInstance gets only a pointer: a second free of the same instance would free freed
 * memory and abort the host. So the live instances are listed (linked through next_live, changed
 * under a spin lock: masters may make and free instances on several threads), and a pointer not
 * in the list is left alone. What this cannot tell: a pointer whose memory a later
 * fmi2Instantiate got again is live again; and any other call on a freed instance reads freed
 * memory, as with any FMU. */
#if defined(_MSC_VER)
#include <intrin.h>
static volatile long live_lock;
static void lock_live(void) { while (_InterlockedExchange(&live_lock, 1)) {} }
static void unlock_live(void) { _InterlockedExchange(&live_lock, 0); }
#else
static volatile char live_lock;
static void lock_live(void) { while (__atomic_test_and_set(&live_lock, __ATOMIC_ACQUIRE)) {} }
static void unlock_live(void) { __atomic_clear(&live_lock, __ATOMIC_RELEASE); }
#endif
static Instance *live;

void bn_live_add(Instance *m) {
    lock_live();
    m->next_live = live;
    live = m;
    unlock_live();
}

int bn_live_remove(Instance *m) {
    int found = 0;
    lock_live();
    for (Instance **p = &live; *p; p = &(*p)->next_live)
        if (*p == m) {
            *p = m->next_live;
            found = 1;
            break;
        }
    unlock_live();
    return found;
}
