/* The values of a native bearing FMU whatever its FMI version (the model layer: bearing_values.h):
 * the variables' names and start values, the parameters' checks alone and together, the internal
 * prepared. Every check answers 0, or 1 with the reason in words; the FMI layer turns that into
 * its status. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bearing_values.h"

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

/* An enumeration parameter (FMI 2.0: an Integer; FMI 3.0: an Enumeration): the same choice as a String parameter, for
 * masters that show a drop-down. A value away from its start wins over the String; if both are
 * set away from their starts they must agree (resolve_choices). */
typedef struct {
    const char *name;       /* e.g. "internal_enum" */
    int string;             /* the String parameter it mirrors: index into m->s */
    int start;
    const char *all;        /* every choice of its type "a|b|c": value k + 1 is the k-th (the Python FMU's) */
} EnumOption;

static const EnumOption ENUMS[BN_N_ENUMS] = { BN_ENUM_TABLE };

/* An Integer option (FMI 2.0: Integer; FMI 3.0: Int64): a range, maybe even, and a special value
 * allowed besides it (-1: none; reynolds' grid: 0, the default) */
typedef struct {
    const char *name;
    int start, minimum, maximum, even, special;
    const char *allowed;    /* in words, for messages */
} IntOption;
#if BN_N_INT_OPTIONS > 0
static const IntOption INT_OPTIONS[BN_N_INT_OPTIONS] = { BN_INT_OPTION_TABLE };
#else
static const IntOption *INT_OPTIONS = NULL;
#endif

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
const char *const BN_BOOL_NAMES[N_BOOL] = {"out_of_domain", "compute_tangent", "thermal"};
static const char *const THERMAL_NAMES[VR_GEOMETRY0 - VR_T_SUPPLY] = {"T_supply", "P_loss", "Q_side", "T_eff", "mu_eff"};
static const char *const THERMAL_UNITS[VR_GEOMETRY0 - VR_T_SUPPLY] = {"K", "W", "m3/s", "K", "Pa.s"};
static const char *const GEOMETRY_NAMES[N_GEOMETRY_REALS] = {
    "groove_1", "groove_2", "groove_3", "groove_4", "groove_5", "groove_6", "groove_7", "groove_8", "groove_width",
    "supply_pressure", "arc_start", "arc_end", "preload", "lobe_offset", "lobe_angle", "circumferential_groove"};
static const char *const GEOMETRY_UNITS[N_GEOMETRY_REALS] = {
    "rad", "rad", "rad", "rad", "rad", "rad", "rad", "rad", "rad", "Pa", "rad", "rad", "1", "1", "rad", "m"};
/* the bore this FMU's data were made for (codegen: the build's bearing): the geometry parameters' starts */
static const double GEOMETRY_START[N_GEOMETRY_REALS] = BN_GEOMETRY_REAL_START;
/* the oil (ports.OIL_ROWS, ports.BOUNDS): names, units, starts (the build's bearing's), bounds */
static const char *const OIL_NAMES[N_OIL_REALS] = {
    "oil_nu_1", "oil_T_1", "oil_nu_2", "oil_T_2", "oil_vogel_a", "oil_vogel_b", "oil_vogel_c", "oil_T_min",
    "oil_T_max", "oil_density", "oil_heat_capacity", "oil_rise_factor", "oil_outflow_share", "oil_ambient_loss",
    "oil_T_ambient"};
static const char *const OIL_UNITS[N_OIL_REALS] = {"m2/s", "K", "m2/s", "K", "Pa.s", "K", "K", "K", "K", "kg/m3",
                                                   "J/(kg.K)", "1", "1", "W/K", "K"};
static const double OIL_START[N_OIL_REALS] = BN_OIL_START;
static const double OIL_LOW[N_OIL_REALS] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 500.0, 500.0, 0.0, 0.0, 0.0, 0.0};
static const double OIL_HIGH[N_OIL_REALS] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY,
                                             INFINITY, INFINITY, 2000.0, 5000.0, 1.0, 0.5, INFINITY, INFINITY};
#define OIL_SHARE (N_OIL_REALS - 3) /* oil_outflow_share: 0.5 or 0 only (ports.OUTFLOW_SHARES) */
static const int INT_START[N_INT] = BN_GEOMETRY_INT_START;
static const char *const INT_NAMES[N_INT] = {"groove_count", "lobes"};
static const int INT_LOW[N_INT] = {0, 1}, INT_HIGH[N_INT] = {8, 8};

/* ------------------------------------------------------------------------------ names */

#if BN_N_PADS
static const char *const PAD_NAMES[BN_N_PAD_REALS] = BN_PAD_NAMES;
static const char *const PAD_UNITS[BN_N_PAD_REALS] = BN_PAD_UNITS;
#endif

const char *bn_real_name(int vr) {
#if BN_N_PADS
    if (vr >= VR_PAD0) return PAD_NAMES[vr - VR_PAD0];
#endif
    if (vr == VR_PEAK) return "peak_pressure";
    if (vr == VR_PEAK_ANGLE) return "peak_pressure_angle";
    if (vr == VR_DER_T_EFF) return "der(T_eff)";
    if (vr >= VR_OIL0) return OIL_NAMES[vr - VR_OIL0];
    if (vr >= VR_GEOMETRY0) return GEOMETRY_NAMES[vr - VR_GEOMETRY0];
    if (vr >= VR_T_SUPPLY) return THERMAL_NAMES[vr - VR_T_SUPPLY];
    return vr < VR_REAL_OPTIONS ? CORE_NAMES[vr] : REAL_OPTIONS[vr - VR_REAL_OPTIONS].name;
}

const char *bn_string_name(int k) {
    return k == S_INTERNAL ? "internal" : STRING_OPTIONS[k - 1].name;
}

const char *bn_real_unit(int vr) {
    if (vr < VR_REAL_OPTIONS) return CORE_UNITS[vr];
#if BN_N_PADS
    if (vr >= VR_PAD0) return PAD_UNITS[vr - VR_PAD0];
#endif
    if (vr == VR_PEAK) return "Pa";
    if (vr == VR_PEAK_ANGLE) return "rad";
    if (vr == VR_DER_T_EFF) return "K/s";
    if (vr >= VR_OIL0) return OIL_UNITS[vr - VR_OIL0];
    if (vr >= VR_GEOMETRY0) return GEOMETRY_UNITS[vr - VR_GEOMETRY0];
    if (vr >= VR_T_SUPPLY) return THERMAL_UNITS[vr - VR_T_SUPPLY];
    return "";
}

const char *bn_enum_name(int j) { return j < N_ENUM ? ENUMS[j].name : INT_OPTIONS[j - N_ENUM].name; }

const char *bn_int_name(int k) { return INT_NAMES[k]; }

int bn_set_int(Instance *m, int k, long long v, char *why, size_t n) {
    int slot = N_REAL + N_BOOL + N_STRING + N_INTS + k;
    m->refused[slot] = v < INT_LOW[k] || v > INT_HIGH[k];
    if (m->refused[slot]) {
        snprintf(why, n, "%s = %.0f must be in %d .. %d", INT_NAMES[k], (double)v, INT_LOW[k], INT_HIGH[k]);
        snprintf(m->refused_msg[slot], sizeof m->refused_msg[slot], "%s", why);
        return 1;
    }
    m->n[k] = (int)v;
    return 0;
}

int bn_is_output_real(int vr) {
    return (vr >= VR_FY && vr < VR_D) || BN_IS_THERMAL_OUTPUT(vr) || BN_IS_PEAK(vr) || BN_IS_PAD_REAL(vr);
}

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

void bn_set_starts(Instance *m) {
    memset(m->r, 0, sizeof m->r);
    for (int i = 0; i < N_INPUTS; i++) m->r[i] = START_INPUTS[i];
    for (int i = 0; i < 4; i++) m->r[VR_D + i] = START_BEARING[i];
    for (int i = 0; i < BN_N_REAL_OPTIONS; i++) m->r[VR_REAL_OPTIONS + i] = REAL_OPTIONS[i].start;
    m->r[VR_T_SUPPLY] = BN_START_T_SUPPLY;
    for (int i = 0; i < N_GEOMETRY_REALS; i++) m->r[VR_GEOMETRY0 + i] = GEOMETRY_START[i];
    for (int i = 0; i < N_OIL_REALS; i++) m->r[VR_OIL0 + i] = OIL_START[i];
    m->thermal_lagged = 0;
    m->thermal_dt = 0.0;
    m->step_h = 0.0;
    memset(m->pads, 0, sizeof m->pads);
    for (int i = 0; i < N_INT; i++) m->n[i] = INT_START[i];
    m->b[B_PARTIAL_ARC] = BN_GEOMETRY_ARC_START;
    m->b[B_OUT_OF_DOMAIN] = 0;
    m->b[B_COMPUTE_TANGENT] = 1;
    m->b[B_THERMAL] = BN_THERMAL_START;
    snprintf(m->s[S_INTERNAL], STRING_MAX, "%s", BN_INTERNAL);
    for (int i = 0; i < BN_N_STRING_OPTIONS; i++) snprintf(m->s[1 + i], STRING_MAX, "%s", STRING_OPTIONS[i].start);
    for (int i = 0; i < N_STRING; i++) snprintf(m->eff[i], STRING_MAX, "%s", m->s[i]);
    for (int i = 0; i < N_ENUM; i++) m->e[i] = ENUMS[i].start;
    for (int i = 0; i < BN_N_INT_OPTIONS; i++) m->e[N_ENUM + i] = INT_OPTIONS[i].start;
    memset(m->refused, 0, sizeof m->refused);
    m->init_error[0] = 0;
    m->t = 0.0;
    m->terminated = 0;
    m->dirty = 1;
    m->refused_state = 0;
    m->step_refused = 0;
    m->ood_now = 0;
    m->still = 0;
    m->work.last_nn = -1;
    m->work.excursions = 0;
}

/* A Real parameter's value alone: 0, or 1 with the reason in why. */
int bn_check_real(int vr, double v, char *why, size_t n) {
    char a[32];
    if (vr >= VR_D && vr <= VR_MU) {
        if (!(v > 0.0 && v < INFINITY)) {
            snprintf(why, n, "%s = %s %s must be finite and > 0", CORE_NAMES[vr], bn_num(a, sizeof a, v, 17),
                     CORE_UNITS[vr]);
            return 1;
        }
        return 0;
    }
    if (vr >= VR_OIL0) { /* the oil: each alone here (ports.check_value), together at initialisation */
        int k = vr - VR_OIL0;
        if (!(isfinite(v) && v >= OIL_LOW[k] && v <= OIL_HIGH[k])) {
            char lo[32], hi[32];
            snprintf(why, n, "%s = %s must be finite and in %s .. %s", OIL_NAMES[k], bn_num(a, sizeof a, v, 17),
                     bn_num(lo, sizeof lo, OIL_LOW[k], 6), bn_num(hi, sizeof hi, OIL_HIGH[k], 6));
            return 1;
        }
        if (k == OIL_SHARE && v != 0.5 && v != 0.0) {
            snprintf(why, n, "oil_outflow_share = %s must be 0.5 (the side flow leaves at half the rise: outflow_rise "
                     "'half') or 0 (all the oil at the full rise: 'full')", bn_num(a, sizeof a, v, 17));
            return 1;
        }
        return 0;
    }
    if (vr >= VR_GEOMETRY0) { /* the bore: any finite value here, the data's bore at initialisation */
        if (!isfinite(v)) {
            snprintf(why, n, "%s = %s must be finite", GEOMETRY_NAMES[vr - VR_GEOMETRY0], bn_num(a, sizeof a, v, 17));
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
int bn_check_string(int k, const char *value, char *out, char *why, size_t n) {
    char v[STRING_MAX];
    if (strlen(value) >= STRING_MAX) {
        snprintf(why, n, "%s: a value of %lu characters is longer than the %d this FMU keeps", bn_string_name(k),
                 (unsigned long)strlen(value), STRING_MAX - 1);
        return 1;
    }
    if (k == S_INTERNAL) {
        lower_strip(value, v, sizeof v);
#if BN_PARTS > 1
        if (!in_choices(v, BN_INTERNALS)) {
            char words[256];
            choices_words(BN_INTERNALS, words, sizeof words);
            snprintf(why, n, "internal = '%s': this native FMU computes %s; for another build one with "
                     "`bearing-fmu build --native --internal NAME,...` (an internal registered from outside the "
                     "package: the Python FMU, `bearing-fmu build`)", value, words);
            return 1;
        }
#else
        if (strcmp(v, BN_INTERNAL) != 0) {
            snprintf(why, n, "internal = '%s': this native FMU computes the %s internal only; for another build "
                     "one with `bearing-fmu build --native --internal NAME` (an internal registered from outside "
                     "the package: the Python FMU, `bearing-fmu build`)", value, BN_INTERNAL);
            return 1;
        }
#endif
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
        snprintf(why, n, "%s = '%s': %s", o->name, value, o->refuse_why ? o->refuse_why : "refused");
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
int bn_check_enum(int j, int v, char *why, size_t n) {
    if (j >= N_ENUM) { /* an Integer option */
        const IntOption *io = &INT_OPTIONS[j - N_ENUM];
        int bad = v != io->special && (v < io->minimum || v > io->maximum || (io->even && v % 2 != 0));
        if (bad) snprintf(why, n, "%s = %d must be %s", io->name, v, io->allowed);
        return bad;
    }
    const EnumOption *o = &ENUMS[j];
    char item[STRING_MAX], out[STRING_MAX], sub[400]; /* a reason fits the caller's 512 with the words around it */
    if (enum_choice(o, v, item, sizeof item)) {
        if (bn_check_string(o->string, item, out, sub, sizeof sub) == 0) return 0;
        snprintf(why, n, "%s = %d means %s", o->name, v, sub);
        return 1;
    }
    size_t off = (size_t)snprintf(why, n, "%s = %d must be one of", o->name, v);
    const char *sep = " ";
    for (int k = 1; enum_choice(o, k, item, sizeof item) && off < n; k++)
        if (bn_check_string(o->string, item, out, sub, sizeof sub) == 0) {
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
                     "enumeration)", bn_string_name(o->string), text, o->name, m->e[j], item, o->name);
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

/* The bore the geometry parameters describe against the one this FMU's data were made for: 0, or 1
 * with why naming every parameter set away from it (the Python FMU's map and taylor do the same). */
static int check_bore(const Instance *m, char *why, size_t n) {
    char a[32], b[32];
    size_t off = 0;
    for (int k = 0; k < N_INT; k++)
        if (m->n[k] != INT_START[k] && off < n)
            off += (size_t)snprintf(why + off, n - off, "%s%s = %d (the data's: %d)", off ? ", " : "", INT_NAMES[k],
                                    m->n[k], INT_START[k]);
    if (m->b[B_PARTIAL_ARC] != BN_GEOMETRY_ARC_START && off < n)
        off += (size_t)snprintf(why + off, n - off, "%spartial_arc = %s (the data's: %s)", off ? ", " : "",
                                m->b[B_PARTIAL_ARC] ? "true" : "false", BN_GEOMETRY_ARC_START ? "true" : "false");
    for (int i = 0; i < N_GEOMETRY_REALS; i++)
        if (m->r[VR_GEOMETRY0 + i] != GEOMETRY_START[i] && off < n)
            off += (size_t)snprintf(why + off, n - off, "%s%s = %s (the data's: %s)", off ? ", " : "",
                                    GEOMETRY_NAMES[i], bn_num(a, sizeof a, m->r[VR_GEOMETRY0 + i], 17),
                                    bn_num(b, sizeof b, GEOMETRY_START[i], 17));
    if (!off) return 0;
    char list[1024];
    snprintf(list, sizeof list, "%s", why);
    snprintf(why, n, "this native FMU's %s data were made for one bore (%s): the geometry parameters set away from "
             "it are %.900s; build another FMU for another bore (bearing-fmu build --native --bearing FILE)",
             BN_INTERNAL, BN_BORE_WORDS, list);
    return 1;
}

/* Parameters checked together and the internal prepared: 0, or 1 with m->init_error set. */
int bn_prepare(Instance *m) {
    char why[2048];
    size_t off = 0;
    why[0] = 0;
    for (int i = 0; i < N_PARAM_SLOTS; i++)
        if (m->refused[i])
            off += (size_t)snprintf(why + off, off < sizeof why ? sizeof why - off : 0,
                                    "%s%s (refused when it was set)", off ? "; " : "", m->refused_msg[i]);
    if (!why[0] && resolve_choices(m, why, sizeof why) == 0) { /* the internal as it counts: m->eff */
        if (m->b[B_THERMAL] && bn_film_why(m)[0])
            snprintf(why, sizeof why, "thermal = true needs the film's friction and flows, which internal = '%s' "
                     "does not have (%.1500s): use thermal = false%s", m->eff[S_INTERNAL], bn_film_why(m),
                     strcmp(m->eff[S_INTERNAL], "reynolds") == 0 ? "" : ", or internal = 'reynolds' (bearing-fmu "
                     "build --native --internal reynolds)");
        if (!why[0] && m->b[B_THERMAL]) bn_thermal_setup(m, why, sizeof why);
    }
    if (!why[0] && check_bearing(m, why, sizeof why) == 0 && check_bore(m, why, sizeof why) == 0) {
        if (bn_setup(m) == 0) {
            m->init_error[0] = 0;
            return 0;
        }
        snprintf(why, sizeof why, "%s", m->msg);
    }
    snprintf(m->init_error, sizeof m->init_error, "bearing FMU initialisation failed: %s", why);
    return 1;
}

void bn_show_choices(Instance *m) {
    memcpy(m->s, m->eff, sizeof m->s); /* same shape; gcc's -Wrestrict took snprintf here for an overlap */
    for (int j = 0; j < N_ENUM; j++) {
        char item[STRING_MAX];
        for (int v = 1; enum_choice(&ENUMS[j], v, item, sizeof item); v++)
            if (strcmp(item, m->s[ENUMS[j].string]) == 0) m->e[j] = v;
    }
}
