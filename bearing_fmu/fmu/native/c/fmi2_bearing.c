/* The FMI 2.0 layer of the native bearing FMU (Co-Simulation and Model Exchange in one binary).
 *
 * The journal state (y, z, vy, vz, omega) goes in, the film force and its tangent come out,
 * computed by the internal compiled beside this file (internal_<name>.c). It has no state of
 * its own apart from its inputs and outputs, so fmi2GetFMUstate is a copy of those.
 *
 * Statuses (docs/fmu.md, "FMI status"), as the Python FMU gives them:
 *   a parameter that can never be valid        -> that fmi2SetX: fmi2Error, value not stored, and
 *                                                 exitInitializationMode fails until a valid one is set
 *   parameters valid alone but not together     -> fmi2ExitInitializationMode: fmi2Error
 *   an unknown value reference, setting an output, a parameter after initialisation,
 *   a bad step size or time, doStep before initialisation, a foreign FMU state -> fmi2Error
 *   a state the internal refuses (non-finite input, the wall, far outside a surrogate's domain)
 *                                               -> doStep (CS) / getReal of an output (ME): fmi2Discard,
 *                                                 outputs keep their last values, logged with the reason
 *   a call out of the FMI 2.0 calling sequence, a non-finite time (setTime) or direction
 *   (getDirectionalDerivative)                  -> fmi2Error naming the call; nothing changes
 * The calling sequence is bearing_fmu/fmi_order.py's table, the Python FMU's too (fmi2_order.c).
 * After an error the instance stays usable. A second fmi2FreeInstance of the same instance is
 * recognised and does nothing (fmi2_order.c lists the live instances). With logging off, the
 * first warning, discard and error of each instance are printed to stderr, so a user of a master
 * without a logger still learns the first thing that went wrong. */
#define BN_FMI_LAYER 1
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bearing_native.h"

typedef struct {
    const char *name;
    double start;
    double minimum;         /* -INFINITY: none */
    int exclusive_minimum;
    double maximum;         /* INFINITY: none */
    const char *allowed;    /* in words, for messages */
} RealOption;

typedef struct {
    const char *name;
    const char *start;
    const char *choices;    /* "a|b|c": allowed values (lower-case); NULL: see file */
    int file;               /* the value names the data compiled in: "" or exactly `start` */
    const char *refuse;     /* a value refused with its own reason (NULL: none) */
    const char *refuse_why;
} StringOption;

/* An enumeration parameter (FMI 2.0: Integer-valued): the same choice as a String parameter, for
 * masters that show a drop-down. A value away from its start wins over the String; if both are
 * set away from their starts they must agree (resolve_choices). */
typedef struct {
    const char *name;       /* e.g. "internal_enum" */
    int string;             /* the String parameter it mirrors: index into m->s */
    int start;
    const char *all;        /* every choice of its type "a|b|c": value k + 1 is the k-th (the Python FMU's) */
} EnumOption;

static const EnumOption ENUMS[BN_N_ENUMS] = { BN_ENUM_TABLE };

#if BN_N_REAL_OPTIONS > 0
static const RealOption REAL_OPTIONS[BN_N_REAL_OPTIONS] = { BN_REAL_OPTION_TABLE };
#else
static const RealOption *REAL_OPTIONS = NULL;
#endif
#if BN_N_STRING_OPTIONS > 0
static const StringOption STRING_OPTIONS[BN_N_STRING_OPTIONS] = { BN_STRING_OPTION_TABLE };
#else
static const StringOption *STRING_OPTIONS = NULL;
#endif

static const char *const CORE_NAMES[VR_REAL_OPTIONS] = {
    "y", "z", "vy", "vz", "omega", "Fy", "Fz", "eccentricity", "h_min",
    "Kyy", "Kyz", "Kzy", "Kzz", "Cyy", "Cyz", "Czy", "Czz", "D", "L", "CR", "mu"};
static const char *const CORE_UNITS[VR_REAL_OPTIONS] = {
    "m", "m", "m/s", "m/s", "rad/s", "N", "N", "1", "m",
    "N/m", "N/m", "N/m", "N/m", "N.s/m", "N.s/m", "N.s/m", "N.s/m", "m", "m", "m", "Pa.s"};
static const double START_INPUTS[N_INPUTS] = BN_START_INPUTS;
static const double START_BEARING[4] = BN_START_BEARING;
static const char *const BOOL_NAMES[N_BOOL] = {"out_of_domain", "compute_tangent"};
static const char *const STATUS_NAMES[] = {"ok", "warning", "discard", "error", "fatal", "pending"};

#define STATE_TAG "bearing-native/1"
typedef struct {
    char tag[24];
    char guid[64];
    double t;
    double values[VR_D];    /* inputs and Real outputs */
    int out_of_domain;
} State;

/* ------------------------------------------------------------------------------ helpers */

const char *bn_num(char *buf, size_t n, double x, int digits) {
    if (isnan(x))
        snprintf(buf, n, "nan");
    else if (isinf(x))
        snprintf(buf, n, x > 0 ? "inf" : "-inf");
    else
        snprintf(buf, n, "%.*g", digits, x);
    return buf;
}

static const char *real_name(int vr) {
    return vr < VR_REAL_OPTIONS ? CORE_NAMES[vr] : REAL_OPTIONS[vr - VR_REAL_OPTIONS].name;
}

static const char *string_name(int k) {
    return k == S_INTERNAL ? "internal" : STRING_OPTIONS[k - 1].name;
}

static void echo(Instance *m, fmi2Status status, const char *text) {
    /* logging off: print the first warning, discard and error of this instance to stderr */
    int bit = 1 << (int)status;
    if (m->logging_on || status == fmi2OK || (m->echoed & bit)) return;
    int first = m->echoed == 0;
    m->echoed |= bit;
    fprintf(stderr, "bearing FMU '%s' [%s]: %s\n", m->name, STATUS_NAMES[status], text);
    if (first)
        fprintf(stderr, "  (logging is off, so this FMU instance prints its first warning, discard and error "
                        "here; instantiate it with loggingOn (fmpy: simulate_fmu(..., debug_logging=True)) to "
                        "receive every message)\n");
    fflush(stderr);
}

void bn_log(Instance *m, fmi2Status status, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    /* the logger takes a printf format: no '%' may reach it (messages never write one; names might) */
    for (char *p = text; *p; p++)
        if (*p == '%') *p = '?';
    if (m->logging_on && m->cb.logger)
        m->cb.logger(m->cb.componentEnvironment, m->name, status, STATUS_NAMES[status], text);
    echo(m, status, text);
}

static fmi2Status fail(Instance *m, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static fmi2Status fail(Instance *m, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    bn_log(m, fmi2Error, "%s", text);
    return fmi2Error;
}

/* refuse `call` (an FMI 2.0 function without "fmi2") unless the instance's mode allows it (fmi2_order.c) */
#define ORDER(call, kind) \
    if (bn_order_refused(m, #call, BN_ALLOW_##call, kind)) return fmi2Error

static void lower_strip(const char *in, char *out, size_t n) {
    while (*in && isspace((unsigned char)*in)) in++;
    size_t k = 0;
    for (; *in && k + 1 < n; in++) out[k++] = (char)tolower((unsigned char)*in);
    while (k > 0 && isspace((unsigned char)out[k - 1])) k--;
    out[k] = 0;
}

static int in_choices(const char *value, const char *choices) {
    size_t n = strlen(value);
    for (const char *p = choices; *p;) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (len == n && strncmp(p, value, n) == 0) return 1;
        if (!bar) break;
        p = bar + 1;
    }
    return 0;
}

static void choices_words(const char *choices, char *out, size_t n) {
    size_t k = 0;
    for (const char *p = choices; *p && k + 3 < n; p++) {
        if (*p == '|') {
            out[k++] = ',';
            out[k++] = ' ';
        } else {
            out[k++] = *p;
        }
    }
    out[k] = 0;
}

/* ------------------------------------------------------------------------------ values */

static void set_starts(Instance *m) {
    memset(m->r, 0, sizeof m->r);
    for (int i = 0; i < N_INPUTS; i++) m->r[i] = START_INPUTS[i];
    for (int i = 0; i < 4; i++) m->r[VR_D + i] = START_BEARING[i];
    for (int i = 0; i < BN_N_REAL_OPTIONS; i++) m->r[VR_REAL_OPTIONS + i] = REAL_OPTIONS[i].start;
    m->b[B_OUT_OF_DOMAIN] = 0;
    m->b[B_COMPUTE_TANGENT] = 1;
    snprintf(m->s[S_INTERNAL], STRING_MAX, "%s", BN_INTERNAL);
    for (int i = 0; i < BN_N_STRING_OPTIONS; i++) snprintf(m->s[1 + i], STRING_MAX, "%s", STRING_OPTIONS[i].start);
    for (int i = 0; i < N_STRING; i++) snprintf(m->eff[i], STRING_MAX, "%s", m->s[i]);
    for (int i = 0; i < N_ENUM; i++) m->e[i] = ENUMS[i].start;
    memset(m->refused, 0, sizeof m->refused);
    m->init_error[0] = 0;
    m->t = 0.0;
    m->initialized = 0;
    m->terminated = 0;
    m->dirty = 1;
    m->work.last_nn = -1;
    m->work.excursions = 0;
}

/* A Real parameter's value alone: 0, or 1 with the reason in why. */
static int check_real_parameter(int vr, double v, char *why, size_t n) {
    char a[32];
    if (vr >= VR_D && vr <= VR_MU) {
        if (!(v > 0.0 && v < INFINITY)) {
            snprintf(why, n, "%s = %s %s must be finite and > 0", CORE_NAMES[vr], bn_num(a, sizeof a, v, 17),
                     CORE_UNITS[vr]);
            return 1;
        }
        return 0;
    }
    const RealOption *o = &REAL_OPTIONS[vr - VR_REAL_OPTIONS];
    int bad = !isfinite(v) || (o->exclusive_minimum ? v <= o->minimum : v < o->minimum) || v > o->maximum;
    if (bad) snprintf(why, n, "%s = %s must be %s", o->name, bn_num(a, sizeof a, v, 17), o->allowed);
    return bad;
}

/* A String parameter's value alone: 0 (normalised into out), or 1 with the reason in why. */
static int check_string_parameter(int k, const char *value, char *out, char *why, size_t n) {
    char v[STRING_MAX];
    if (strlen(value) >= STRING_MAX) {
        snprintf(why, n, "%s: a value of %lu characters is longer than the %d this FMU keeps", string_name(k),
                 (unsigned long)strlen(value), STRING_MAX - 1);
        return 1;
    }
    if (k == S_INTERNAL) {
        lower_strip(value, v, sizeof v);
        if (strcmp(v, BN_INTERNAL) != 0) {
            snprintf(why, n, "internal = '%s': this native FMU computes the %s internal only; for another build "
                     "one with `bearing-fmu build --native --internal NAME` (reynolds: the Python FMU, "
                     "`bearing-fmu build`)", value, BN_INTERNAL);
            return 1;
        }
        snprintf(out, STRING_MAX, "%s", v);
        return 0;
    }
    const StringOption *o = &STRING_OPTIONS[k - 1];
    if (o->file) {
        if (value[0] && strcmp(value, o->start) != 0) {
            snprintf(why, n, "%s = '%s': this native FMU has its %s file compiled in ('%s'); build another FMU "
                     "for another file (bearing-fmu build --native)", o->name, value, o->name, o->start);
            return 1;
        }
        snprintf(out, STRING_MAX, "%s", o->start);
        return 0;
    }
    lower_strip(value, v, sizeof v);
    if (o->refuse && strcmp(v, o->refuse) == 0) {
        snprintf(why, n, "%s = '%s': %s", o->name, value, o->refuse_why ? o->refuse_why : "");
        return 1;
    }
    if (!in_choices(v, o->choices)) {
        char words[256];
        choices_words(o->choices, words, sizeof words);
        snprintf(why, n, "unknown %s '%s'; choose one of %s", o->name, value, words);
        return 1;
    }
    snprintf(out, STRING_MAX, "%s", v);
    return 0;
}

static const char *string_start(int k) { return k == S_INTERNAL ? BN_INTERNAL : STRING_OPTIONS[k - 1].start; }

/* The choice with value v of an enumeration (v = k + 1 for the k-th of o->all) into out: 1, or 0 if none. */
static int enum_choice(const EnumOption *o, int v, char *out, size_t n) {
    const char *p = o->all;
    for (int k = 1; p && *p; k++) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (k == v) {
            snprintf(out, n, "%.*s", (int)len, p);
            return 1;
        }
        p = bar ? bar + 1 : NULL;
    }
    return 0;
}

/* An enumeration parameter's value alone: 0, or 1 with the reason in why (the String's reason for
 * a choice this FMU does not take, else the values it takes). */
static int check_enum_parameter(int j, int v, char *why, size_t n) {
    const EnumOption *o = &ENUMS[j];
    char item[STRING_MAX], out[STRING_MAX], sub[400]; /* a reason fits the caller's 512 with the words around it */
    if (enum_choice(o, v, item, sizeof item)) {
        if (check_string_parameter(o->string, item, out, sub, sizeof sub) == 0) return 0;
        snprintf(why, n, "%s = %d means %s", o->name, v, sub);
        return 1;
    }
    size_t off = (size_t)snprintf(why, n, "%s = %d must be one of", o->name, v);
    const char *sep = " ";
    for (int k = 1; enum_choice(o, k, item, sizeof item) && off < n; k++)
        if (check_string_parameter(o->string, item, out, sub, sizeof sub) == 0) {
            off += (size_t)snprintf(why + off, n - off, "%s%d (%s)", sep, k, item);
            sep = ", ";
        }
    return 1;
}

/* The String choices as they count, into m->eff: each String's value, or its enumeration's item
 * where only the enumeration was set away from its start. 0, or 1 with why when both were set
 * away from their starts and disagree. */
static int resolve_choices(Instance *m, char *why, size_t n) {
    char item[STRING_MAX];
    for (int k = 0; k < N_STRING; k++) snprintf(m->eff[k], STRING_MAX, "%s", m->s[k]);
    for (int j = 0; j < N_ENUM; j++) {
        const EnumOption *o = &ENUMS[j];
        if (m->e[j] == o->start || !enum_choice(o, m->e[j], item, sizeof item)) continue;
        const char *text = m->s[o->string];
        if (strcmp(text, string_start(o->string)) != 0 && strcmp(text, item) != 0) {
            snprintf(why, n, "%s = '%s' and %s = %d (%s) disagree: set one of them (%s is the same choice as an "
                     "enumeration)", string_name(o->string), text, o->name, m->e[j], item, o->name);
            return 1;
        }
        snprintf(m->eff[o->string], STRING_MAX, "%s", item);
    }
    return 0;
}

/* The bearing's physical ranges (bearing_fmu/params.py, BearingParams): 0, or 1 with why. */
static int check_bearing(const Instance *m, char *why, size_t n) {
    double D = m->r[VR_D], L = m->r[VR_L], CR = m->r[VR_CR], mu = m->r[VR_MU];
    char a[32], b[32], c[32], d[32];
    if (!(D >= 1e-3 && D <= 5.0)) {
        snprintf(why, n, "D = %s m is outside the physical range 1 mm .. 5 m", bn_num(a, sizeof a, D, 4));
        return 1;
    }
    if (!(L >= 0.05 * D && L <= 5.0 * D)) {
        snprintf(why, n, "L = %s m is outside the physical range %s .. %s m (L/D 0.05 .. 5 at D = %s m)",
                 bn_num(a, sizeof a, L, 4), bn_num(b, sizeof b, 0.05 * D, 4), bn_num(c, sizeof c, 5.0 * D, 4),
                 bn_num(d, sizeof d, D, 4));
        return 1;
    }
    if (!(CR >= 1e-5 * 0.5 * D && CR <= 0.05 * 0.5 * D)) {
        snprintf(why, n, "CR = %s m is outside the physical range %s .. %s m (CR/R 1e-05 .. 0.05 at D = %s m)",
                 bn_num(a, sizeof a, CR, 4), bn_num(b, sizeof b, 1e-5 * 0.5 * D, 4),
                 bn_num(c, sizeof c, 0.05 * 0.5 * D, 4), bn_num(d, sizeof d, D, 4));
        return 1;
    }
    if (!(mu >= 1e-5 && mu <= 10.0)) {
        snprintf(why, n, "mu = %s Pa s is outside the physical range 1e-05 .. 10 Pa s", bn_num(a, sizeof a, mu, 4));
        return 1;
    }
    return 0;
}

/* Parameters checked together and the internal prepared: 0, or 1 with m->init_error set. */
static int setup(Instance *m) {
    char why[2048];
    size_t off = 0;
    why[0] = 0;
    for (int i = 0; i < N_PARAM_SLOTS; i++)
        if (m->refused[i])
            off += (size_t)snprintf(why + off, off < sizeof why ? sizeof why - off : 0, "%s%s (refused when it was set)",
                                    off ? "; " : "", m->refused_msg[i]);
    if (!why[0] && resolve_choices(m, why, sizeof why) == 0 && check_bearing(m, why, sizeof why) == 0) {
        if (bn_setup(m) == 0) {
            m->init_error[0] = 0;
            return 0;
        }
        snprintf(why, sizeof why, "%s", m->msg);
    }
    snprintf(m->init_error, sizeof m->init_error, "bearing FMU initialisation failed: %s", why);
    return 1;
}

/* The inputs as a state: 0, or 1 with the reason in m->msg (a non-finite input). */
static int read_inputs(Instance *m, double x[5]) {
    char a[32];
    for (int i = 0; i < 5; i++) {
        x[i] = m->r[i];
        if (!isfinite(x[i])) {
            snprintf(m->msg, sizeof m->msg, "bearing input %s = %s is not finite", CORE_NAMES[i],
                     bn_num(a, sizeof a, x[i], 17));
            return 1;
        }
    }
    return 0;
}

/* Evaluate the internal at the inputs and set the outputs: 0, or 1 with the reason in m->msg
 * (outputs untouched). out_of_domain is a discrete output: in Continuous-Time Mode (ME) it keeps
 * its value and the state's own goes to m->ood_now, which it takes at the next event. */
static int evaluate(Instance *m) {
    double x[5], F[2], J[8], dw[2];
    int ood = 0;
    char a[32], b[32], c[32], d[32], e[32];
    if (read_inputs(m, x)) return 1;
    int jac = m->b[B_COMPUTE_TANGENT];
    if (bn_eval(m, x, jac, F, J, dw, &ood)) return 1;
    int finite = isfinite(F[0]) && isfinite(F[1]);
    for (int i = 0; jac && i < 8; i++) finite = finite && isfinite(J[i]);
    if (!finite) {
        snprintf(m->msg, sizeof m->msg, "the %s internal returned a non-finite force or tangent at y = %s m, "
                 "z = %s m, vy = %s m/s, vz = %s m/s, omega = %s rad/s", BN_INTERNAL, bn_num(a, 32, x[0], 6),
                 bn_num(b, 32, x[1], 6), bn_num(c, 32, x[2], 6), bn_num(d, 32, x[3], 6), bn_num(e, 32, x[4], 6));
        return 1;
    }
    double eps = hypot(x[0], x[1]) / m->r[VR_CR];
    m->r[VR_FY] = F[0];
    m->r[VR_FZ] = F[1];
    m->r[VR_ECC] = eps;
    m->r[VR_HMIN] = m->r[VR_CR] * (1.0 - eps);
    m->ood_now = ood;
    if (m->mode != MODE_CONTINUOUS) m->b[B_OUT_OF_DOMAIN] = ood;
    if (jac) { /* Lund's sign: K = -dF/dq, C = -dF/dv */
        m->r[VR_KYY] = -J[0]; m->r[VR_KYZ] = -J[1]; m->r[VR_CYY] = -J[2]; m->r[VR_CYZ] = -J[3];
        m->r[VR_KZY] = -J[4]; m->r[VR_KZZ] = -J[5]; m->r[VR_CZY] = -J[6]; m->r[VR_CZZ] = -J[7];
    }
    /* a shaft at rest with no squeeze carries no load: most likely omega is not connected */
    int still = x[4] == 0.0 && x[2] == 0.0 && x[3] == 0.0;
    if (still && !m->still) {
        bn_log(m, fmi2Warning, "the force was asked at omega = 0 rad/s with no squeeze velocity (vy = vz = 0): the "
               "film carries no load, the force is zero; is the input omega connected? (warned once, until the "
               "journal moves or turns)");
        m->warn_pending = 1;
    }
    m->still = still;
    m->dirty = 0;
    return 0;
}

/* fmi2Warning if a warning was logged since the last call that reported one, else fmi2OK */
static fmi2Status warned(Instance *m) {
    fmi2Status s = m->warn_pending ? fmi2Warning : fmi2OK;
    m->warn_pending = 0;
    return s;
}

static int is_output_real(fmi2ValueReference vr) { return vr >= VR_FY && vr < VR_D; }

/* Outputs requested: Initialization Mode computes them from the inputs and parameters set so
 * far; Model Exchange after initialisation computes them when the inputs changed. A refused
 * state is logged once; reading again at the same inputs gives fmi2Discard without a new line. */
static fmi2Status outputs_for_get(Instance *m, const char *call, const char *name) {
    if (m->mode == MODE_INIT) {
        if (setup(m))
            return fail(m, "%s %s in Initialization Mode: the outputs cannot be computed: %s", call, name,
                        m->init_error);
        if (evaluate(m))
            return fail(m, "%s %s in Initialization Mode: the outputs cannot be computed at the inputs set: %s "
                        "(set valid inputs and read again)", call, name, m->msg);
        return warned(m);
    }
    if ((m->mode == MODE_EVENT || m->mode == MODE_CONTINUOUS) && m->dirty) {
        m->refused_state = evaluate(m);
        if (m->refused_state) {
            char t[32];
            m->dirty = 0; /* until the inputs change */
            bn_log(m, fmi2Discard, "%s at t = %s s (outputs keep their last values)", m->msg,
                   bn_num(t, sizeof t, m->t, 10));
        }
    }
    if (m->refused_state && (m->mode == MODE_EVENT || m->mode == MODE_CONTINUOUS)) return fmi2Discard;
    return warned(m);
}

/* ------------------------------------------------------------------------------ FMI: common */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    if (!c) return fmi2Error;
    ((Instance *)c)->logging_on = loggingOn != 0;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    (void)fmuResourceLocation;
    (void)visible;
    const char *name = instanceName ? instanceName : "";
    if (!fmuGUID || strcmp(fmuGUID, BN_GUID) != 0) {
        if (functions && functions->logger)
            functions->logger(functions->componentEnvironment, name, fmi2Error, "error",
                              "fmi2Instantiate: the GUID given is not this FMU's (" BN_GUID ")");
        else
            fprintf(stderr, "bearing FMU '%s' [error]: fmi2Instantiate: the GUID given is not this FMU's\n", name);
        return NULL;
    }
    Instance *m = (functions && functions->allocateMemory) ? functions->allocateMemory(1, sizeof(Instance))
                                                           : calloc(1, sizeof(Instance));
    if (!m) return NULL;
    memset(m, 0, sizeof *m);
    if (functions) m->cb = *functions;
    m->type = fmuType;
    m->logging_on = loggingOn != 0;
    snprintf(m->name, sizeof m->name, "%s", name);
    set_starts(m);
    m->mode = MODE_INSTANTIATED;
    bn_live_add(m);
    return m;
}

void fmi2FreeInstance(fmi2Component c) {
    Instance *m = c;
    if (!m) return;
    if (!bn_live_remove(m)) { /* freed already (or never ours): its memory is not touched */
        fprintf(stderr, "bearing FMU: fmi2FreeInstance(%p): not a live instance of this FMU (freed already?); "
                        "nothing done\n", c);
        fflush(stderr);
        return;
    }
    if (m->cb.freeMemory) {
        fmi2CallbackFreeMemory release = m->cb.freeMemory;
        release(m);
    } else {
        free(m);
    }
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Instance *m = c;
    char a[32], b[32];
    (void)toleranceDefined;
    (void)tolerance;
    if (!m) return fmi2Error;
    ORDER(setupExperiment, BN_ANY_TYPE);
    if (!isfinite(startTime))
        return fail(m, "setupExperiment: startTime = %s s must be finite", bn_num(a, 32, startTime, 17));
    if (stopTimeDefined && !(startTime <= stopTime && stopTime < INFINITY))
        return fail(m, "setupExperiment: stopTime = %s s must be finite and >= startTime = %s s",
                    bn_num(a, 32, stopTime, 17), bn_num(b, 32, startTime, 17));
    m->t = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(enterInitializationMode, BN_ANY_TYPE);
    m->mode = MODE_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(exitInitializationMode, BN_ANY_TYPE);
    m->initialized = 1;
    if (setup(m)) return fail(m, "%s", m->init_error);
    m->mode = m->type == fmi2ModelExchange ? MODE_EVENT : MODE_STEP;
    /* both the String and its enumeration show the choice that counts */
    memcpy(m->s, m->eff, sizeof m->s); /* same shape; gcc's -Wrestrict took snprintf here for an overlap */
    for (int j = 0; j < N_ENUM; j++) {
        char item[STRING_MAX];
        for (int v = 1; enum_choice(&ENUMS[j], v, item, sizeof item); v++)
            if (strcmp(item, m->s[ENUMS[j].string]) == 0) m->e[j] = v;
    }
    /* outputs at the start time from the initial inputs, when they can be evaluated: a master
     * may set the inputs only before the first step, so a refused state is no initialisation error */
    if (evaluate(m)) {
        bn_log(m, fmi2Warning, "outputs at the start time left at their start values: %s", m->msg);
        m->warn_pending = 1;
        m->dirty = 1;
    }
    return warned(m);
}

fmi2Status fmi2Terminate(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(terminate, BN_ANY_TYPE);
    m->mode = MODE_TERMINATED;
    if (m->work.excursions > 0) { /* the count of what was warned once per excursion */
        char a[32], b[32];
        bn_log(m, fmi2Warning, "terminate: the state left the surrogate's fitted domain %d time(s) in this run (each "
               "excursion warned when it began; the first at t = %s s, the last at t = %s s)", m->work.excursions,
               bn_num(a, sizeof a, m->work.excursion_t[0], 10), bn_num(b, sizeof b, m->work.excursion_t[1], 10));
    }
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    set_starts(m);
    m->mode = MODE_INSTANTIATED;
    return fmi2OK;
}

/* ------------------------------------------------------------------------------ getters and setters */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getReal, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    int computed = 0;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] >= (fmi2ValueReference)N_REAL)
            return fail(m, "getReal: value reference %u is not a Real variable of this FMU", vr[i]);
        if (is_output_real(vr[i]) && !computed) {
            computed = 1;
            fmi2Status s = outputs_for_get(m, "getReal", real_name((int)vr[i]));
            if (s == fmi2Error) return s;
            if (s > status) status = s;
        }
        value[i] = m->r[vr[i]];
    }
    return status;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getInteger, BN_ANY_TYPE);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_INT0 || vr[i] >= VR_INT0 + N_ENUM)
            return fail(m, "getInteger: value reference %u is not an Integer variable of this FMU", vr[i]);
        value[i] = m->e[vr[i] - VR_INT0];
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getBoolean, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_BOOL0 || vr[i] >= VR_BOOL0 + N_BOOL)
            return fail(m, "getBoolean: value reference %u is not a Boolean variable of this FMU", vr[i]);
        if (vr[i] == VR_BOOL0 + B_OUT_OF_DOMAIN) {
            fmi2Status s = outputs_for_get(m, "getBoolean", "out_of_domain");
            if (s == fmi2Error) return s;
            if (s > status) status = s;
        }
        value[i] = m->b[vr[i] - VR_BOOL0] ? fmi2True : fmi2False;
    }
    return status;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getString, BN_ANY_TYPE);
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING)
            return fail(m, "getString: value reference %u is not a String variable of this FMU", vr[i]);
        value[i] = m->s[vr[i] - VR_STRING0];
    }
    return fmi2OK;
}

/* a parameter set after initialisation: refused (1, logged), else 0 */
static int parameter_fixed(Instance *m, const char *call, const char *name, const char *keeps) {
    if (!m->initialized) return 0;
    fail(m, "%s: parameter %s is fixed after initialisation (variability fixed); it keeps %s", call, name, keeps);
    return 1;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setReal, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    char a[32], why[512];
    for (size_t i = 0; i < nvr; i++) {
        fmi2ValueReference k = vr[i];
        if (k < N_INPUTS) { /* inputs: any value; a non-finite one is refused when evaluated */
            m->r[k] = value[i];
            m->dirty = 1;
            continue;
        }
        if (k >= (fmi2ValueReference)N_REAL) {
            status = fail(m, "setReal: value reference %u is not a Real variable of this FMU", k);
            continue;
        }
        if (is_output_real(k)) {
            status = fail(m, "setReal: %s is an output and cannot be set", real_name((int)k));
            continue;
        }
        if (parameter_fixed(m, "setReal", real_name((int)k), bn_num(a, sizeof a, m->r[k], 17))) {
            status = fmi2Error;
            continue;
        }
        if (check_real_parameter((int)k, value[i], why, sizeof why)) {
            m->refused[k] = 1;
            snprintf(m->refused_msg[k], sizeof m->refused_msg[k], "%s", why);
            status = fail(m, "setReal: %s; %s keeps %s", why, real_name((int)k), bn_num(a, sizeof a, m->r[k], 17));
            continue;
        }
        m->refused[k] = 0;
        m->r[k] = value[i];
    }
    return status;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setInteger, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    char why[512], keeps[32];
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_INT0 || vr[i] >= VR_INT0 + N_ENUM) {
            status = fail(m, "setInteger: value reference %u is not an Integer variable of this FMU", vr[i]);
            continue;
        }
        int j = (int)(vr[i] - VR_INT0);
        int slot = N_REAL + N_BOOL + N_STRING + j;
        snprintf(keeps, sizeof keeps, "%d", m->e[j]);
        if (parameter_fixed(m, "setInteger", ENUMS[j].name, keeps)) {
            status = fmi2Error;
            continue;
        }
        if (check_enum_parameter(j, value[i], why, sizeof why)) {
            m->refused[slot] = 1;
            snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
            status = fail(m, "setInteger: %s; %s keeps %s", why, ENUMS[j].name, keeps);
            continue;
        }
        m->refused[slot] = 0;
        m->e[j] = value[i];
    }
    return status;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setBoolean, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_BOOL0 || vr[i] >= VR_BOOL0 + N_BOOL) {
            status = fail(m, "setBoolean: value reference %u is not a Boolean variable of this FMU", vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_BOOL0);
        if (k == B_OUT_OF_DOMAIN) {
            status = fail(m, "setBoolean: out_of_domain is an output and cannot be set");
            continue;
        }
        if (parameter_fixed(m, "setBoolean", BOOL_NAMES[k], m->b[k] ? "True" : "False")) {
            status = fmi2Error;
            continue;
        }
        m->b[k] = value[i] != fmi2False;
    }
    return status;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setString, BN_ANY_TYPE);
    fmi2Status status = fmi2OK;
    char why[512], out[STRING_MAX], keeps[STRING_MAX + 2];
    for (size_t i = 0; i < nvr; i++) {
        if (vr[i] < VR_STRING0 || vr[i] >= VR_STRING0 + N_STRING) {
            status = fail(m, "setString: value reference %u is not a String variable of this FMU", vr[i]);
            continue;
        }
        int k = (int)(vr[i] - VR_STRING0);
        int slot = N_REAL + N_BOOL + k;
        snprintf(keeps, sizeof keeps, "'%s'", m->s[k]);
        if (parameter_fixed(m, "setString", string_name(k), keeps)) {
            status = fmi2Error;
            continue;
        }
        if (check_string_parameter(k, value[i] ? value[i] : "", out, why, sizeof why)) {
            m->refused[slot] = 1;
            snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
            status = fail(m, "setString: %s; %s keeps %s", why, string_name(k), keeps);
            continue;
        }
        m->refused[slot] = 0;
        snprintf(m->s[k], STRING_MAX, "%s", out);
    }
    return status;
}

/* ------------------------------------------------------------------------------ FMU state */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    Instance *m = c;
    if (!m || !FMUstate) return fmi2Error;
    State *s = *FMUstate;
    if (!s) {
        s = m->cb.allocateMemory ? m->cb.allocateMemory(1, sizeof(State)) : calloc(1, sizeof(State));
        if (!s) return fail(m, "getFMUstate: out of memory");
        *FMUstate = s;
    }
    memset(s, 0, sizeof *s);
    snprintf(s->tag, sizeof s->tag, "%s", STATE_TAG);
    snprintf(s->guid, sizeof s->guid, "%s", BN_GUID);
    s->t = m->t;
    memcpy(s->values, m->r, sizeof s->values);
    s->out_of_domain = m->b[B_OUT_OF_DOMAIN];
    return fmi2OK;
}

static int valid_state(const State *s) {
    return s && strncmp(s->tag, STATE_TAG, sizeof s->tag) == 0 && strncmp(s->guid, BN_GUID, sizeof s->guid) == 0;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    Instance *m = c;
    const State *s = FMUstate;
    if (!m) return fmi2Error;
    if (!valid_state(s))
        return fail(m, "setFMUstate: not a %s state of this FMU; the instance keeps its state", STATE_TAG);
    m->t = s->t;
    memcpy(m->r, s->values, sizeof s->values);
    m->b[B_OUT_OF_DOMAIN] = s->out_of_domain;
    m->terminated = 0;
    m->dirty = 1;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    Instance *m = c;
    if (!m || !FMUstate) return fmi2Error;
    if (*FMUstate) {
        /* no tag left: a stale copy of the pointer used soon after is likely refused, not restored
         * (not a guarantee: the memory is freed; the master's own pointer is set to NULL below) */
        memset(((State *)*FMUstate)->tag, 0, sizeof ((State *)*FMUstate)->tag);
        if (m->cb.freeMemory)
            m->cb.freeMemory(*FMUstate);
        else
            free(*FMUstate);
    }
    *FMUstate = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
    Instance *m = c;
    if (!m || !size) return fmi2Error;
    if (!valid_state(FMUstate)) return fail(m, "serializedFMUstateSize: not a %s state of this FMU", STATE_TAG);
    *size = sizeof(State);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size) {
    Instance *m = c;
    if (!m) return fmi2Error;
    if (!valid_state(FMUstate)) return fail(m, "serializeFMUstate: not a %s state of this FMU", STATE_TAG);
    if (size < sizeof(State))
        return fail(m, "serializeFMUstate: a buffer of %lu bytes is smaller than the state (%lu bytes)",
                    (unsigned long)size, (unsigned long)sizeof(State));
    memcpy(serializedState, FMUstate, sizeof(State));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate) {
    Instance *m = c;
    if (!m || !FMUstate) return fmi2Error;
    if (size != sizeof(State) || !valid_state((const State *)(const void *)serializedState))
        return fail(m, "deSerializeFMUstate: %lu bytes are not a serialised %s state of this FMU",
                    (unsigned long)size, STATE_TAG);
    fmi2FMUstate s = *FMUstate;
    if (!s) {
        s = m->cb.allocateMemory ? m->cb.allocateMemory(1, sizeof(State)) : calloc(1, sizeof(State));
        if (!s) return fail(m, "deSerializeFMUstate: out of memory");
    }
    memcpy(s, serializedState, sizeof(State));
    *FMUstate = s;
    return fmi2OK;
}

/* ------------------------------------------------------------------------------ derivatives */

/* The internal's F and J at x, quietly (a derivative's evaluation is no state of the run): 0, or 1 (m->msg). */
static int eval_quiet(Instance *m, const double x[5], double F[2], double J[8], double dw[2]) {
    int ood;
    m->work.quiet = 1;
    int refused = bn_eval(m, x, 1, F, J, dw, &ood);
    m->work.quiet = 0;
    return refused;
}

/* dJ: the derivative of the analytic Jacobian J along the input direction dx, by central
 * differences (one-sided next to a state the internal refuses): the force has no second
 * derivative in closed form. The step is 1e-6 of each input's scale (CR; omega CR; omega).
 * 0, or 1 (m->msg) when neither side evaluates. */
static int jacobian_derivative(Instance *m, const double x[5], const double J[8], const double dx[5], double dJ[8]) {
    double w = fmax(fabs(x[4]), 1.0), CR = m->r[VR_CR];
    double scale[5] = {CR, CR, fmax(w * CR, hypot(x[2], x[3])), fmax(w * CR, hypot(x[2], x[3])), w};
    double big = 0.0, xp[5], xm[5], Fp[2], Fm[2], Jp[8], Jm[8], wp[2], wm[2];
    for (int i = 0; i < 5; i++) big = fmax(big, fabs(dx[i]) / scale[i]);
    for (int i = 0; i < 8; i++) dJ[i] = 0.0;
    if (big == 0.0) return 0;
    double h = 1e-6 / big;
    for (int i = 0; i < 5; i++) {
        xp[i] = x[i] + h * dx[i];
        xm[i] = x[i] - h * dx[i];
    }
    int bad_p = eval_quiet(m, xp, Fp, Jp, wp), bad_m = eval_quiet(m, xm, Fm, Jm, wm);
    if (bad_p && bad_m) return 1;
    for (int i = 0; i < 8; i++)
        dJ[i] = bad_p ? (J[i] - Jm[i]) / h : bad_m ? (Jp[i] - J[i]) / h : (Jp[i] - Jm[i]) / (2.0 * h);
    return 0;
}

/* FMI 2.0 directional derivatives of every Real output with respect to the inputs (any mode after
 * instantiation where getDirectionalDerivative is allowed) and, in Initialization Mode, to the
 * Real parameters:
 *   Fy, Fz         the internal's analytic Jacobian (dF/domega: the map's; the Taylor and linear
 *                  models are defined at one speed: 0)
 *   Kyy .. Czz     central differences of that Jacobian (jacobian_derivative)
 *   eccentricity, h_min   analytic
 *   D, L, CR, mu   the map: F = S P(q/CR, v/CR, omega) with S = mu L D^3 / (8 CR^2), so a change
 *                  of the bearing is a scale and, for CR, a move of the state along (q, v);
 *                  the Taylor and linear models hold their own bearing: 0 (ecc, h_min follow CR)
 *   the internal's Real options   bn_option_derivative (the linear model's coefficients) */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    Instance *m = c;
    char a[32];
    if (!m) return fmi2Error;
    ORDER(getDirectionalDerivative, BN_ANY_TYPE);
    if (m->mode == MODE_INIT && setup(m))
        return fail(m, "getDirectionalDerivative in Initialization Mode: %s", m->init_error);
    double dx[5] = {0, 0, 0, 0, 0}, db[4] = {0, 0, 0, 0}, dopt[BN_N_REAL_OPTIONS + 1];
    for (int k = 0; k <= BN_N_REAL_OPTIONS; k++) dopt[k] = 0.0;
    int any_option = 0;
    for (size_t j = 0; j < nKnown; j++) {
        fmi2ValueReference k = vKnown_ref[j];
        const char *name = k < (fmi2ValueReference)N_REAL ? real_name((int)k) : "?";
        if (k >= (fmi2ValueReference)N_REAL || is_output_real(k))
            return fail(m, "getDirectionalDerivative: known %s (value reference %u) is not an input or a Real "
                        "parameter", name, k);
        if (k >= VR_D && m->mode != MODE_INIT)
            return fail(m, "getDirectionalDerivative: known %s is a parameter: FMI 2.0 gives derivatives with "
                        "respect to parameters in Initialization Mode only", name);
        if (!isfinite(dvKnown[j]))
            return fail(m, "getDirectionalDerivative: dvKnown[%lu] = %s (the direction in %s) must be finite",
                        (unsigned long)j, bn_num(a, sizeof a, dvKnown[j], 17), name);
        if (k < N_INPUTS)
            dx[k] += dvKnown[j];
        else if (k <= VR_MU)
            db[k - VR_D] += dvKnown[j];
        else {
            dopt[k - VR_REAL_OPTIONS] += dvKnown[j];
            any_option = 1;
        }
    }
    double x[5], F[2], J[8], dw[2], dJ[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    if (read_inputs(m, x) || eval_quiet(m, x, F, J, dw)) {
        bn_log(m, fmi2Discard, "getDirectionalDerivative: %s", m->msg);
        return fmi2Discard;
    }
    double D = m->r[VR_D], L = m->r[VR_L], CR = m->r[VR_CR], mu = m->r[VR_MU];
    /* the bearing: a scale of F (k = 2) and J (k = 3), and for CR a move along (q, v) (see above) */
    double gain = 0.0, along = 0.0; /* S's relative change from D, L, mu; CR's move along (q, v) */
#if BN_BEARING_IN_FORCE
    gain = 3.0 * db[0] / D + db[1] / L + db[3] / mu;
    along = -db[2] / CR;
#else
    (void)D; (void)L; (void)mu;
#endif
    double d_eff[5], dF[2];
    for (int i = 0; i < 4; i++) d_eff[i] = dx[i] + along * x[i];
    d_eff[4] = BN_SPEED_IN_FORCE ? dx[4] : 0.0; /* a model of one speed: its force does not move with omega */
    for (int r = 0; r < 2; r++) {
        const double *row = J + 4 * r;
        dF[r] = row[0] * d_eff[0] + row[1] * d_eff[1] + row[2] * d_eff[2] + row[3] * d_eff[3] + dw[r] * d_eff[4]
                + F[r] * (gain + 2.0 * along); /* S ~ CR^-2 */
    }
    int need_dJ = 0;
    for (size_t i = 0; i < nUnknown; i++) need_dJ |= vUnknown_ref[i] >= VR_KYY && vUnknown_ref[i] <= VR_CZZ;
    if (need_dJ) {
        if (jacobian_derivative(m, x, J, d_eff, dJ)) {
            bn_log(m, fmi2Discard, "getDirectionalDerivative: the Jacobian's derivative needs states next to this one: "
                   "%s", m->msg);
            return fmi2Discard;
        }
        for (int i = 0; i < 8; i++) dJ[i] += J[i] * (gain + 3.0 * along); /* J ~ S / CR */
    }
    if (any_option)
        for (int k = 0; k < BN_N_REAL_OPTIONS; k++)
            if (dopt[k] != 0.0) {
                double oF[2], oJ[8];
                bn_option_derivative(m, x, k, oF, oJ);
                for (int r = 0; r < 2; r++) dF[r] += oF[r] * dopt[k];
                for (int i = 0; i < 8; i++) dJ[i] += oJ[i] * dopt[k];
            }
    double e = hypot(x[0], x[1]);
    double de = e > 0.0 ? (x[0] * dx[0] + x[1] * dx[1]) / e : 0.0; /* d|q| */
    static const int jac_index[8] = {0, 1, 4, 5, 2, 3, 6, 7};   /* Kyy Kyz Kzy Kzz Cyy Cyz Czy Czz in J */
    for (size_t i = 0; i < nUnknown; i++) {
        fmi2ValueReference u = vUnknown_ref[i];
        if (u == VR_FY || u == VR_FZ)
            dvUnknown[i] = dF[u - VR_FY];
        else if (u == VR_ECC)
            dvUnknown[i] = de / CR - e / CR * db[2] / CR;
        else if (u == VR_HMIN)
            dvUnknown[i] = db[2] - de;
        else if (u >= VR_KYY && u <= VR_CZZ)
            dvUnknown[i] = -dJ[jac_index[u - VR_KYY]]; /* Lund's sign */
        else
            return fail(m, "getDirectionalDerivative: unknown %s (value reference %u) is not a Real output",
                        u < (fmi2ValueReference)N_REAL ? real_name((int)u) : "?", u);
    }
    return fmi2OK;
}

/* ------------------------------------------------------------------------------ FMI: Co-Simulation */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setRealInputDerivatives, BN_CS_ONLY);
    return fail(m, "setRealInputDerivatives: not supported (canInterpolateInputs is false)");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getRealOutputDerivatives, BN_CS_ONLY);
    return fail(m, "getRealOutputDerivatives: not supported (maxOutputDerivativeOrder is 0)");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Instance *m = c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!m) return fmi2Error;
    double t0 = currentCommunicationPoint, h = communicationStepSize, t = t0 + h;
    char a[32], b[32];
    if (m->mode == MODE_INIT && m->init_error[0] && m->type != fmi2ModelExchange) /* the reason, not only the mode */
        return fail(m, "doStep: step to t = %s s refused: %s", bn_num(a, 32, t, 10), m->init_error);
    ORDER(doStep, BN_CS_ONLY);
    if (!(h > 0.0 && h < INFINITY))
        return fail(m, "doStep: communicationStepSize = %s s must be finite and > 0 (currentCommunicationPoint = %s s)",
                    bn_num(a, 32, h, 17), bn_num(b, 32, t0, 17));
    if (!isfinite(t0))
        return fail(m, "doStep: currentCommunicationPoint = %s s must be finite", bn_num(a, 32, t0, 17));
    if (!isfinite(t))
        return fail(m, "doStep: currentCommunicationPoint + communicationStepSize = %s + %s s is not finite",
                    bn_num(a, 32, t0, 17), bn_num(b, 32, h, 17));
    if (evaluate(m)) {
        /* not fmi2Terminated: the same step from a restored state, or a shorter one, can succeed */
        bn_log(m, fmi2Discard, "%s at t = %s s", m->msg, bn_num(a, 32, t, 10));
        return fmi2Discard;
    }
    m->t = t;
    return warned(m);
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    if (!c) return fmi2Error;
    return fail(c, "cancelStep: doStep never runs asynchronously here");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getStatus, BN_CS_ONLY);
    return fail(m, "getStatus: status kind %d is not provided (doStep never returns fmi2Pending)", (int)s);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getRealStatus, BN_CS_ONLY);
    if (s != fmi2LastSuccessfulTime) return fail(m, "getRealStatus: status kind %d is not provided", (int)s);
    *value = m->t;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getIntegerStatus, BN_CS_ONLY);
    return fail(m, "getIntegerStatus: status kind %d is not provided", (int)s);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getBooleanStatus, BN_CS_ONLY);
    if (s != fmi2Terminated) return fail(m, "getBooleanStatus: status kind %d is not provided", (int)s);
    *value = m->terminated ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)value;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(getStringStatus, BN_CS_ONLY);
    return fail(m, "getStringStatus: status kind %d is not provided", (int)s);
}

/* ------------------------------------------------------------------------------ FMI: Model Exchange */
/* No continuous states and no event indicators: the outputs are a direct feedthrough of the
 * inputs, computed when read (outputs_for_get). */

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(enterEventMode, BN_ME_ONLY);
    m->mode = MODE_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(newDiscreteStates, BN_ME_ONLY);
    if (!info) return fail(m, "newDiscreteStates: fmi2EventInfo* is NULL");
    /* the discrete output out_of_domain takes the state's value here, at an event only */
    if (m->dirty) outputs_for_get(m, "newDiscreteStates", "out_of_domain");
    if (!m->refused_state) m->b[B_OUT_OF_DOMAIN] = m->ood_now;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = fmi2False;
    info->nextEventTimeDefined = fmi2False;
    info->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(enterContinuousTimeMode, BN_ME_ONLY);
    m->mode = MODE_CONTINUOUS;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(completedIntegratorStep, BN_ME_ONLY);
    /* a step event when the state crossed the fitted domain's edge: out_of_domain (discrete)
     * changes at the event that follows, never within Continuous-Time Mode */
    fmi2Status s = m->dirty ? outputs_for_get(m, "completedIntegratorStep", "out_of_domain") : fmi2OK;
    if (enterEventMode) *enterEventMode = !m->refused_state && m->ood_now != m->b[B_OUT_OF_DOMAIN];
    if (terminateSimulation) *terminateSimulation = fmi2False;
    return s == fmi2Discard ? fmi2OK : s; /* the refused state was logged; the master finds it at getReal */
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    Instance *m = c;
    if (!m) return fmi2Error;
    ORDER(setTime, BN_ME_ONLY);
    if (!isfinite(time)) {
        char a[32], b[32];
        return fail(m, "setTime: time = %s s must be finite; the instance keeps t = %s s", bn_num(a, 32, time, 17),
                    bn_num(b, 32, m->t, 17));
    }
    m->t = time;
    return fmi2OK;
}

static fmi2Status no_states(Instance *m, const char *call, unsigned allowed, size_t n, const char *what) {
    if (!m) return fmi2Error;
    if (bn_order_refused(m, call, allowed, BN_ME_ONLY)) return fmi2Error;
    if (n != 0) return fail(m, "%s: this FMU has no %s, got %lu", call, what, (unsigned long)n);
    return fmi2OK;
}
#define NO_STATES(call, n, what) no_states(c, #call, BN_ALLOW_##call, n, what)

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    (void)x;
    return NO_STATES(setContinuousStates, nx, "continuous states");
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    (void)derivatives;
    return NO_STATES(getDerivatives, nx, "continuous states");
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    (void)eventIndicators;
    return NO_STATES(getEventIndicators, ni, "event indicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    (void)x;
    return NO_STATES(getContinuousStates, nx, "continuous states");
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    (void)x_nominal;
    return NO_STATES(getNominalsOfContinuousStates, nx, "continuous states");
}
