/* Logging and the calling sequence of the native bearing FMU, for either FMI layer
 * (bearing_calls.h).
 *
 * bn_log formats a line and gives it to the layer's m->emit (FMI 2.0: the logger callback with
 * logging on; FMI 3.0: logMessage, errors even with logging off). When no logger received it, the
 * first warning, discard and error of each instance are printed to stderr, so a user of a master
 * without a logger still learns the first thing that went wrong.
 *
 * bn_order_refused: which call is allowed in which mode is a table per FMI version
 * (bearing_fmu/fmu/order.py ALLOWED, the Python FMU's too; fmi3.py ALLOWED3), generated into
 * model_config.h (BN_ALLOW_<call>) and fmi3_config.h (BN3_ALLOW_<call>) as one bit mask per call,
 * bit k: Mode k; the refusal's words are order.refusal's. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "bearing_calls.h"

static const char *const STATUS_NAMES[] = {"ok", "warning", "discard", "error", "fatal"};

/* ------------------------------------------------------------------------------ logging */

static void echo(Instance *m, bn_status status, const char *text) {
    int bit = 1 << (int)status;
    if (status == BN_OK || (m->echoed & bit)) return;
    int first = m->echoed == 0;
    m->echoed |= bit;
    fprintf(stderr, "bearing FMU '%s' [%s]: %s\n", m->name, STATUS_NAMES[status], text);
    if (first)
        fprintf(stderr, "  (logging is off, so this FMU instance prints its first warning, discard and error "
                        "here; instantiate it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to "
                        "receive every message)\n");
    fflush(stderr);
}

static void log_text(Instance *m, bn_status status, const char *fmt, va_list ap) {
    char text[2048];
    if (m->mute) return; /* the states a derivative's differences evaluate */
    vsnprintf(text, sizeof text, fmt, ap);
    if (!m->emit(m, status, text) && !m->logging_on) echo(m, status, text);
}

void bn_log(Instance *m, bn_status status, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    log_text(m, status, fmt, ap);
    va_end(ap);
}

bn_status bn_fail(Instance *m, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    log_text(m, BN_ERROR, fmt, ap);
    va_end(ap);
    return BN_ERROR;
}

/* a double the way Python's %.{digits}g writes it (the messages' numbers) */
const char *bn_num(char *buf, size_t n, double x, int digits) {
    if (isnan(x))
        snprintf(buf, n, "nan");
    else if (isinf(x))
        snprintf(buf, n, x > 0 ? "inf" : "-inf");
    else
        snprintf(buf, n, "%.*g", digits, x);
    return buf;
}

/* ------------------------------------------------------------------------------ calling sequence */

static const char *const MODE_NAMES[] = BN_MODE_NAMES;
static const int STAGE[] = {0, 1, 2, 2, 2, 3}; /* each mode's place in an instance's life (order._STAGE) */
#if BN_FMI3
#define RESET_TEXT "fmi3Reset"
#else
#define RESET_TEXT "fmi2Reset"
#endif

int bn_order_refused(Instance *m, const char *call, unsigned allowed, int kind) {
    const char *mode = MODE_NAMES[m->mode];
    int me = m->model_exchange;
    if ((kind == BN_CS_ONLY && me) || (kind == BN_ME_ONLY && !me)) { /* whatever the mode */
#if BN_FMI3
        int event = strstr(call, "EventMode") || strstr(call, "DiscreteStates");
        const char *note = !me && event ? " (this FMU has no Event Mode in Co-Simulation: hasEventMode is false)" : "";
#else
        const char *note = "";
#endif
        bn_log(m, BN_ERROR, "%s in %s: a %s " BN_CALL_WORD "; this instance is a %s one%s", call, mode,
               me ? "Co-Simulation" : "Model Exchange", me ? "Model Exchange" : "Co-Simulation", note);
        return 1;
    }
    if (allowed & (1u << m->mode)) return 0;
    unsigned never = me ? 1u << MODE_STEP : (1u << MODE_EVENT) | (1u << MODE_CONTINUOUS);
    char here[200] = "";
    int lo = 3, hi = 0, stage = STAGE[m->mode];
    for (int k = 0; k <= MODE_TERMINATED; k++) {
        if (!(allowed & (1u << k)) || (never & (1u << k))) continue;
        lo = STAGE[k] < lo ? STAGE[k] : lo;
        hi = STAGE[k] > hi ? STAGE[k] : hi;
        size_t n = strlen(here);
        snprintf(here + n, sizeof here - n, "%s%s", n ? " or " : "", MODE_NAMES[k]);
    }
    /* what to do instead, from where the instance is: before, after or beside the allowed modes */
    const char *hint;
    if (strcmp(call, BN_CALL(terminate, Terminate)) == 0 && stage < 2)
        hint = "nothing to terminate: the instance was never initialised (free it, or " RESET_TEXT ")";
    else if (stage > hi)
        hint = m->mode == MODE_TERMINATED ? "too late: the instance is terminated (" RESET_TEXT " starts it over)"
               : stage == 2 ? "too late: the instance is initialised (" RESET_TEXT " starts it over)"
                            : "too late: the instance is in Initialization Mode (" RESET_TEXT " starts it over)";
    else if (stage < lo)
        hint = stage == 1 ? "call " BN_CALL(exitInitializationMode, ExitInitializationMode) " first"
               : (allowed & (1u << MODE_INIT))
                   ? "call " BN_CALL(enterInitializationMode, EnterInitializationMode) " first"
                   : "initialise it first (" BN_CALL(enterInitializationMode, EnterInitializationMode) ", then "
                     BN_CALL(exitInitializationMode, ExitInitializationMode) ")";
    else
        hint = m->mode == MODE_EVENT ? "call " BN_CALL(enterContinuousTimeMode, EnterContinuousTimeMode) " first"
               : m->mode == MODE_CONTINUOUS ? "call " BN_CALL(enterEventMode, EnterEventMode) " first"
                                            : "call " BN_CALL(exitInitializationMode, ExitInitializationMode) " first";
    bn_log(m, BN_ERROR, "%s in %s: not allowed there (" BN_FMI_TEXT ": in %s only); %s", call, mode, here, hint);
    return 1;
}
