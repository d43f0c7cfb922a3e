/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_ini.c
 * @brief Model INI loading (keys in docs/simulate.md). Every mistake is an error naming file,
 *        line and key.
 *
 * inih calls the handler once per key; it does not report sections without keys, and the
 * handler is not told the line. We therefore feed inih through our own line reader, which counts
 * lines and checks every [section] header, and collect (section, key, value, line) entries. The
 * entries are interpreted after the whole file is read, because [model] type decides which keys
 * are valid.
 */
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "aenl_sim_internal.h"
#include "aenl_tools/aenl_csv.h"

#define DEG (3.14159265358979323846 / 180.0)

typedef struct entry
{
    char *section, *key, *value;
    int line;
} entry_t;

typedef struct aenl_run_dummy
{
    aenl_sim_run_t run;
} aenl_run_dummy_t;

typedef struct ini_ctx
{
    const char *path;
    FILE *fp;
    int line; /* line of the chunk last handed to inih */
    int at_line_start;
    entry_t *e;
    size_t n, cap;
    int sec_line[8]; /* header line of each known section, 0 if absent */
    int failed;      /* an error message has been set */
    int model_only;  /* [run] optional (flutter analysis) */
    int oom;
    aenl_err_t *err;
} ini_ctx_t;

static const char *const sections[8] = {"model",   "pitch",      "plunge", "flap",
                                        "initial", "excitation", "run",    "noise"};

static int section_index(const char *name)
{
    int i;
    for (i = 0; i < 8; ++i)
    {
        if (strcmp(name, sections[i]) == 0)
        {
            return i;
        }
    }
    return -1;
}

static char *dup_str(const char *s)
{
    const size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d != NULL)
    {
        memcpy(d, s, n);
    }
    return d;
}

/* fgets-like reader: counts lines and validates [section] headers. */
static char *reader(char *str, int num, void *stream)
{
    ini_ctx_t *c = stream;
    char *r = fgets(str, num, c->fp);
    const char *p;
    size_t len;
    if (r == NULL)
    {
        return NULL;
    }
    if (c->at_line_start)
    {
        ++c->line;
    }
    len = strlen(str);
    c->at_line_start = (len > 0 && str[len - 1] == '\n') ? 1 : 0;
    p = str;
    if (c->line == 1 && (unsigned char)p[0] == 0xEF && (unsigned char)p[1] == 0xBB &&
        (unsigned char)p[2] == 0xBF)
    {
        p += 3;
    }
    while (*p == ' ' || *p == '\t')
    {
        ++p;
    }
    if (*p == '[' && !c->failed)
    {
        char name[64];
        const char *end = strchr(p, ']');
        size_t n;
        int idx;
        if (end == NULL || (size_t)(end - p - 1) >= sizeof(name))
        {
            aenl_err_set(c->err, "%s:%d: malformed section header", c->path, c->line);
            c->failed = 1;
            return NULL;
        }
        n = (size_t)(end - p - 1);
        memcpy(name, p + 1, n);
        name[n] = '\0';
        idx = section_index(name);
        if (idx < 0)
        {
            aenl_err_set(c->err,
                         "%s:%d: unknown section [%s] (known: model, pitch, plunge, flap, "
                         "initial, excitation, run, noise)",
                         c->path, c->line, name);
            c->failed = 1;
            return NULL;
        }
        if (c->sec_line[idx] != 0)
        {
            aenl_err_set(c->err, "%s:%d: section [%s] repeated (first at line %d)", c->path,
                         c->line, name, c->sec_line[idx]);
            c->failed = 1;
            return NULL;
        }
        c->sec_line[idx] = c->line;
    }
    return r;
}

static int handler(void *user, const char *section, const char *name, const char *value)
{
    ini_ctx_t *c = user;
    entry_t *e;
    if (c->failed)
    {
        return 0;
    }
    if (section[0] == '\0')
    {
        aenl_err_set(c->err, "%s:%d: key '%s' outside any section", c->path, c->line, name);
        c->failed = 1;
        return 0;
    }
    if (c->n == c->cap)
    {
        const size_t cap = c->cap ? 2 * c->cap : 32;
        entry_t *ne = realloc(c->e, cap * sizeof(*ne));
        if (ne == NULL)
        {
            c->oom = 1;
            return 0;
        }
        c->e = ne;
        c->cap = cap;
    }
    e = &c->e[c->n];
    e->section = dup_str(section);
    e->key = dup_str(name);
    e->value = dup_str(value);
    e->line = c->line;
    if (e->section == NULL || e->key == NULL || e->value == NULL)
    {
        free(e->section);
        free(e->key);
        free(e->value);
        c->oom = 1;
        return 0;
    }
    ++c->n;
    return 1;
}

static void free_entries(ini_ctx_t *c)
{
    size_t i;
    for (i = 0; i < c->n; ++i)
    {
        free(c->e[i].section);
        free(c->e[i].key);
        free(c->e[i].value);
    }
    free(c->e);
    c->e = NULL;
    c->n = c->cap = 0;
}

/* ---- value parsing ------------------------------------------------------------------------ */

enum
{
    V_ANY = 0, /* finite */
    V_POS = 1, /* > 0 */
    V_NONNEG = 2
};

static aenl_status_t bad(ini_ctx_t *c, const entry_t *e, const char *what)
{
    aenl_err_set(c->err, "%s:%d: [%s] %s = '%s': %s", c->path, e->line, e->section, e->key,
                 e->value, what);
    return AENL_E_ARG;
}

/* Physical ranges: a value beyond them is a typo or an absurd input, rejected here with its key
 * and line rather than failing later inside the integrator. */
#define MAX_ABS_PARAM 1e6 /* any model parameter, in its own unit */
#define MAX_ABS_ANGLE                                                                              \
    1.5707963267948966       /* angles (gap, gap start, preload, initial angle): 90 deg */
#define MAX_ABS_PLUNGE 100.0 /* plunge lengths: xi = h/b, or metres */
#define MAX_ABS_RATE   1e4   /* initial rates per model time unit */

static aenl_status_t parse_num(ini_ctx_t *c, const entry_t *e, int range, double scale,
                               double max_abs, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = aenl_strtod_decimal(e->value, &end);
    if (end == e->value || *end != '\0')
    {
        return bad(c, e, "not a number");
    }
    if (!isfinite(v) || errno == ERANGE)
    {
        return bad(c, e, "must be a finite number");
    }
    if (range == V_POS && !(v > 0.0))
    {
        return bad(c, e, "must be > 0");
    }
    if (range == V_NONNEG && v < 0.0)
    {
        return bad(c, e, "must be >= 0");
    }
    if (!(fabs(v * scale) <= max_abs))
    {
        char what[96];
        (void)snprintf(what, sizeof(what), "outside the physical range (|value| <= %g%s)",
                       scale > 0.0 && scale < 1.0 ? max_abs / scale : max_abs,
                       scale > 0.0 && scale < 1.0 ? " deg" : "");
        return bad(c, e, what);
    }
    *out = v * scale;
    return AENL_OK;
}

static aenl_status_t parse_seed(ini_ctx_t *c, const entry_t *e, uint64_t *out)
{
    const char *p = e->value;
    uint64_t v = 0;
    if (*p == '\0')
    {
        return bad(c, e, "not an unsigned integer");
    }
    for (; *p != '\0'; ++p)
    {
        const unsigned d = (unsigned)(*p - '0');
        if (*p < '0' || *p > '9')
        {
            return bad(c, e, "not an unsigned integer");
        }
        if (v > (UINT64_MAX - d) / 10U)
        {
            return bad(c, e, "above 2^64 - 1");
        }
        v = v * 10U + d;
    }
    *out = v;
    return AENL_OK;
}

static aenl_status_t parse_bool(ini_ctx_t *c, const entry_t *e, int *out)
{
    const char *v = e->value;
    if (strcmp(v, "1") == 0 || strcmp(v, "true") == 0 || strcmp(v, "yes") == 0 ||
        strcmp(v, "on") == 0)
    {
        *out = 1;
        return AENL_OK;
    }
    if (strcmp(v, "0") == 0 || strcmp(v, "false") == 0 || strcmp(v, "no") == 0 ||
        strcmp(v, "off") == 0)
    {
        *out = 0;
        return AENL_OK;
    }
    return bad(c, e, "expected true or false");
}

static aenl_status_t parse_list(ini_ctx_t *c, const entry_t *e, aenl_sim_law_t *law)
{
    const char *p = e->value;
    size_t n = 0;
    while (1)
    {
        char *end;
        double v;
        while (*p == ' ' || *p == '\t')
        {
            ++p;
        }
        errno = 0;
        v = aenl_strtod_decimal(p, &end);
        if (end == p)
        {
            return bad(c, e, "expected a comma-separated list of numbers");
        }
        if (!isfinite(v) || errno == ERANGE)
        {
            return bad(c, e, "coefficients must be finite");
        }
        if (n == AENL_SIM_MAX_POLY)
        {
            return bad(c, e, "too many coefficients (at most 9: x^1 .. x^9)");
        }
        law->coeffs[n++] = v;
        p = end;
        while (*p == ' ' || *p == '\t')
        {
            ++p;
        }
        if (*p == '\0')
        {
            break;
        }
        if (*p != ',')
        {
            return bad(c, e, "expected a comma-separated list of numbers");
        }
        ++p;
    }
    law->n_coeffs = n;
    return AENL_OK;
}

/* ---- interpretation ----------------------------------------------------------------------- */

typedef struct key_spec
{
    const char *name;
    int range;
    double *target;
} key_spec_t;

static const entry_t *find(const ini_ctx_t *c, const char *sec, const char *key)
{
    size_t i;
    for (i = 0; i < c->n; ++i)
    {
        if (strcmp(c->e[i].section, sec) == 0 && strcmp(c->e[i].key, key) == 0)
        {
            return &c->e[i];
        }
    }
    return NULL;
}

/* Key in a table of plain numeric keys; 1 if handled (status in *st), 0 if not in the table. */
static int apply_table(ini_ctx_t *c, const entry_t *e, const key_spec_t *tab, size_t n,
                       aenl_status_t *st)
{
    size_t i;
    for (i = 0; i < n; ++i)
    {
        if (strcmp(e->key, tab[i].name) == 0)
        {
            *st = parse_num(c, e, tab[i].range, 1.0, MAX_ABS_PARAM, tab[i].target);
            return 1;
        }
    }
    return 0;
}

static aenl_status_t unknown_key(ini_ctx_t *c, const entry_t *e, const char *ctx_note)
{
    aenl_err_set(c->err, "%s:%d: unknown key '%s' in [%s]%s", c->path, e->line, e->key, e->section,
                 ctx_note);
    return AENL_E_ARG;
}

static aenl_status_t apply_model(ini_ctx_t *c, const entry_t *e, aenl_sim_model_t *m)
{
    aenl_status_t st = AENL_OK;
    if (strcmp(e->key, "type") == 0)
    {
        return AENL_OK;
    }
    if (m->type == AENL_SIM_AIRFOIL2DOF)
    {
        aenl_sim_airfoil_t *p = &m->airfoil;
        const key_spec_t tab[] = {{"mu", V_POS, &p->mu},
                                  {"a_h", V_ANY, &p->a_h},
                                  {"x_alpha", V_ANY, &p->x_alpha},
                                  {"r_alpha", V_POS, &p->r_alpha},
                                  {"omega_bar", V_POS, &p->omega_bar},
                                  {"zeta_alpha", V_NONNEG, &p->zeta_alpha},
                                  {"zeta_xi", V_NONNEG, &p->zeta_xi},
                                  {"ustar", V_POS, &p->ustar}};
        if (apply_table(c, e, tab, sizeof(tab) / sizeof(tab[0]), &st))
        {
            return st;
        }
        if (strcmp(e->key, "ic_forcing") == 0)
        {
            return parse_bool(c, e, &p->ic_forcing);
        }
        return unknown_key(c, e, " for type airfoil2dof");
    }
    {
        aenl_sim_section_t *p = &m->section;
        const key_spec_t tab[] = {{"b", V_POS, &p->b},
                                  {"a", V_ANY, &p->a},
                                  {"c", V_ANY, &p->c},
                                  {"m", V_POS, &p->m},
                                  {"m_t", V_POS, &p->m_t},
                                  {"x_alpha", V_ANY, &p->x_alpha},
                                  {"x_beta", V_ANY, &p->x_beta},
                                  {"r_alpha", V_POS, &p->r_alpha},
                                  {"r_beta", V_POS, &p->r_beta},
                                  {"omega_h", V_POS, &p->omega_h},
                                  {"omega_alpha", V_POS, &p->omega_alpha},
                                  {"omega_beta", V_POS, &p->omega_beta},
                                  {"zeta_h", V_NONNEG, &p->zeta_h},
                                  {"zeta_alpha", V_NONNEG, &p->zeta_alpha},
                                  {"zeta_beta", V_NONNEG, &p->zeta_beta},
                                  {"rho", V_NONNEG, &p->rho},
                                  {"velocity", V_POS, &p->velocity}};
        if (apply_table(c, e, tab, sizeof(tab) / sizeof(tab[0]), &st))
        {
            return st;
        }
        return unknown_key(c, e, " for type section3dof");
    }
}

/* Angle-like key with optional _deg suffix: base "delta" matches "delta" and "delta_deg". */
static int angle_key(const entry_t *e, const char *base, int allow_deg, double *scale)
{
    const size_t n = strlen(base);
    if (strcmp(e->key, base) == 0)
    {
        *scale = 1.0;
        return 1;
    }
    if (allow_deg && strncmp(e->key, base, n) == 0 && strcmp(e->key + n, "_deg") == 0)
    {
        *scale = DEG;
        return 1;
    }
    return 0;
}

static aenl_status_t apply_law(ini_ctx_t *c, const entry_t *e, aenl_sim_law_t *law, int angular)
{
    double scale = 1.0;
    const int piecewise =
        law->kind == AENL_SIM_LAW_FREEPLAY || law->kind == AENL_SIM_LAW_HYSTERESIS;
    if (strcmp(e->key, "law") == 0)
    {
        return AENL_OK;
    }
    if (piecewise && angle_key(e, "delta", angular, &scale))
    {
        return parse_num(c, e, V_POS, scale, angular ? MAX_ABS_ANGLE : MAX_ABS_PLUNGE, &law->delta);
    }
    if (piecewise && angle_key(e, "alpha_f", angular, &scale))
    {
        return parse_num(c, e, V_ANY, scale, angular ? MAX_ABS_ANGLE : MAX_ABS_PLUNGE, &law->x_f);
    }
    if (piecewise && angle_key(e, "preload", angular, &scale))
    {
        return parse_num(c, e, V_ANY, scale, angular ? MAX_ABS_ANGLE : MAX_ABS_PLUNGE,
                         &law->preload);
    }
    if (piecewise && strcmp(e->key, "inner_stiffness") == 0)
    {
        return parse_num(c, e, V_ANY, 1.0, MAX_ABS_PARAM, &law->inner_stiffness);
    }
    if (law->kind == AENL_SIM_LAW_POLYNOMIAL && strcmp(e->key, "coeffs") == 0)
    {
        return parse_list(c, e, law);
    }
    return unknown_key(c, e, " for this law");
}

static aenl_status_t apply_initial(ini_ctx_t *c, const entry_t *e, aenl_sim_model_t *m)
{
    static const char *const names2[3] = {"alpha", "xi", NULL};
    static const char *const names3[3] = {"alpha", "h", "beta"};
    const char *const *names = (m->type == AENL_SIM_AIRFOIL2DOF) ? names2 : names3;
    if (strcmp(e->key, "estimate") == 0)
    {
        int yes = 0;
        const aenl_status_t st = parse_bool(c, e, &yes);
        m->initial = yes ? AENL_SIM_INITIAL_ESTIMATE : AENL_SIM_INITIAL_GIVEN;
        return st;
    }
    int d;
    for (d = 0; d < AENL_SIM_N_DOF; ++d)
    {
        char dot[32];
        double scale = 1.0;
        const int angular = (d != AENL_SIM_DOF_PLUNGE);
        if (names[d] == NULL)
        {
            continue;
        }
        if (angle_key(e, names[d], angular, &scale))
        {
            return parse_num(c, e, V_ANY, scale, angular ? MAX_ABS_ANGLE : MAX_ABS_PLUNGE,
                             &m->x0[d]);
        }
        (void)snprintf(dot, sizeof(dot), "%s_dot", names[d]);
        if (angle_key(e, dot, angular, &scale))
        {
            return parse_num(c, e, V_ANY, scale, MAX_ABS_RATE, &m->v0[d]);
        }
    }
    return unknown_key(c, e,
                       m->type == AENL_SIM_AIRFOIL2DOF
                           ? " (airfoil2dof: alpha[_deg], xi, their _dot rates, estimate)"
                           : " (section3dof: h, alpha[_deg], beta[_deg], their _dot rates, "
                             "estimate)");
}

/* [excitation] with type = kicks (its dof is already read: it decides whether _deg keys are
 * allowed). */
static aenl_status_t apply_kick(ini_ctx_t *c, const entry_t *e, aenl_sim_run_t *r)
{
    const int angular = r->kick_dof != AENL_SIM_DOF_PLUNGE;
    double scale = 1.0;
    if (strcmp(e->key, "dof") == 0)
    {
        return AENL_OK;
    }
    if (strcmp(e->key, "seed") == 0)
    {
        return parse_seed(c, e, &r->kick_seed);
    }
    if (strcmp(e->key, "every") == 0)
    {
        return parse_num(c, e, V_POS, 1.0, MAX_ABS_PARAM, &r->kick_every);
    }
    if (angle_key(e, "rate", angular, &scale))
    {
        return parse_num(c, e, V_NONNEG, scale, MAX_ABS_RATE, &r->kick_rate);
    }
    if (angle_key(e, "rate_max", angular, &scale))
    {
        return parse_num(c, e, V_NONNEG, scale, MAX_ABS_RATE, &r->kick_rate_max);
    }
    if (strcmp(e->key, "sign") == 0)
    {
        static const char *const k_sign[3] = {"random", "alternate", "positive"};
        for (int i = 0; i < 3; ++i)
        {
            if (strcmp(e->value, k_sign[i]) == 0)
            {
                r->kick_sign = (aenl_sim_kick_sign_t)i;
                return AENL_OK;
            }
        }
        return bad(c, e, "expected random, alternate or positive");
    }
    return unknown_key(c, e,
                       angular ? " for type kicks (dof, every, rate[_deg], rate_max[_deg], sign, "
                                 "seed)"
                               : " for type kicks on plunge (dof, every, rate, rate_max, sign, "
                                 "seed; no _deg keys)");
}

/* [excitation] with type = sweep or multisine (its dof is already read). */
static aenl_status_t apply_force(ini_ctx_t *c, const entry_t *e, aenl_sim_run_t *r)
{
    const int angular = r->force_dof != AENL_SIM_DOF_PLUNGE;
    const int sweep = r->force == AENL_SIM_FORCE_SWEEP;
    double scale = 1.0;
    if (strcmp(e->key, "dof") == 0)
    {
        return AENL_OK;
    }
    if (sweep && angle_key(e, "amplitude", angular, &scale))
    {
        return parse_num(c, e, V_POS, scale, angular ? MAX_ABS_ANGLE : MAX_ABS_PLUNGE,
                         &r->force_amp);
    }
    if (!sweep && angle_key(e, "rms", angular, &scale))
    {
        return parse_num(c, e, V_POS, scale, angular ? MAX_ABS_ANGLE : MAX_ABS_PLUNGE,
                         &r->force_amp);
    }
    if (strcmp(e->key, sweep ? "f_start" : "f_min") == 0)
    {
        return parse_num(c, e, V_POS, 1.0, MAX_ABS_PARAM, &r->force_f0);
    }
    if (strcmp(e->key, sweep ? "f_end" : "f_max") == 0)
    {
        return parse_num(c, e, V_POS, 1.0, MAX_ABS_PARAM, &r->force_f1);
    }
    if (sweep && strcmp(e->key, "law") == 0)
    {
        if (strcmp(e->value, "linear") == 0 || strcmp(e->value, "log") == 0)
        {
            r->force_log = strcmp(e->value, "log") == 0;
            return AENL_OK;
        }
        return bad(c, e, "expected linear or log");
    }
    if (!sweep && strcmp(e->key, "period") == 0)
    {
        return parse_num(c, e, V_POS, 1.0, MAX_ABS_PARAM, &r->force_period);
    }
    if (!sweep && strcmp(e->key, "seed") == 0)
    {
        return parse_seed(c, e, &r->force_seed);
    }
    if (sweep)
    {
        return unknown_key(c, e,
                           angular ? " for type sweep (dof, amplitude[_deg], f_start, f_end, law)"
                                   : " for type sweep on plunge (dof, amplitude, f_start, f_end, "
                                     "law; no _deg keys)");
    }
    return unknown_key(c, e,
                       angular ? " for type multisine (dof, rms[_deg], f_min, f_max, period, seed)"
                               : " for type multisine on plunge (dof, rms, f_min, f_max, period, "
                                 "seed; no _deg keys)");
}

static aenl_status_t apply_entry(ini_ctx_t *c, const entry_t *e, aenl_sim_model_t *m,
                                 aenl_sim_run_t *r)
{
    const int sec = section_index(e->section);
    aenl_status_t st = AENL_OK;
    switch (sec)
    {
        case 0:
            return apply_model(c, e, m);
        case 1:
            return apply_law(c, e, &m->law[AENL_SIM_DOF_PITCH], 1);
        case 2:
            return apply_law(c, e, &m->law[AENL_SIM_DOF_PLUNGE], 0);
        case 3:
            return apply_law(c, e, &m->law[AENL_SIM_DOF_FLAP], 1);
        case 4:
            return apply_initial(c, e, m);
        case 5:
        {
            const key_spec_t tab[] = {{"intensity", V_NONNEG, &r->turb_intensity},
                                      {"length_scale", V_POS, &r->turb_length}};
            if (strcmp(e->key, "type") == 0)
            {
                return AENL_OK;
            }
            if (r->kicks)
            {
                return apply_kick(c, e, r);
            }
            if (r->force != AENL_SIM_FORCE_NONE)
            {
                return apply_force(c, e, r);
            }
            if (strcmp(e->key, "seed") == 0)
            {
                return parse_seed(c, e, &r->turb_seed);
            }
            if (strcmp(e->key, "spectrum") == 0)
            {
                if (strcmp(e->value, "first_order") == 0)
                {
                    r->turb_spectrum = AENL_SIM_GUST_FIRST_ORDER;
                    return AENL_OK;
                }
                if (strcmp(e->value, "dryden") == 0)
                {
                    r->turb_spectrum = AENL_SIM_GUST_DRYDEN;
                    return AENL_OK;
                }
                return bad(c, e, "expected first_order or dryden");
            }
            if (apply_table(c, e, tab, 2, &st))
            {
                return st;
            }
            return unknown_key(c, e,
                               " (type, intensity, length_scale, spectrum, seed; dof, every, "
                               "rate, rate_max and sign need type = kicks; amplitude, f_start, "
                               "f_end and law need type = sweep; rms, f_min, f_max and period "
                               "need type = multisine)");
        }
        case 6:
        {
            const key_spec_t tab[] = {{"duration", V_POS, &r->duration},
                                      {"dt", V_POS, &r->dt},
                                      {"rtol", V_POS, &r->rtol},
                                      {"atol", V_POS, &r->atol}};
            if (apply_table(c, e, tab, 4, &st))
            {
                return st;
            }
            return unknown_key(c, e, " (duration, dt, rtol, atol)");
        }
        case 7:
        {
            const key_spec_t tab[] = {{"snr", V_POS, &r->snr}};
            if (strcmp(e->key, "seed") == 0)
            {
                return parse_seed(c, e, &r->noise_seed);
            }
            if (apply_table(c, e, tab, 1, &st))
            {
                return st;
            }
            return unknown_key(c, e, " (snr, seed)");
        }
        default:
            break;
    }
    aenl_err_set(c->err, "%s:%d: unknown section [%s]", c->path, e->line, e->section);
    return AENL_E_ARG;
}

static aenl_status_t missing(ini_ctx_t *c, int sec, const char *key)
{
    if (c->sec_line[sec] > 0)
    {
        aenl_err_set(c->err, "%s:%d: [%s] lacks the required key '%s'", c->path, c->sec_line[sec],
                     sections[sec], key);
    }
    else
    {
        aenl_err_set(c->err, "%s: missing section [%s] with required key '%s'", c->path,
                     sections[sec], key);
    }
    return AENL_E_ARG;
}

/* The keys a forced excitation cannot do without (d: the DOF, for the _deg spelling). */
static aenl_status_t force_required(ini_ctx_t *c, const aenl_sim_run_t *r, int d)
{
    if (r->force == AENL_SIM_FORCE_NONE)
    {
        return AENL_OK;
    }
    const int sweep = r->force == AENL_SIM_FORCE_SWEEP;
    const char *amp = sweep ? "amplitude" : "rms";
    char amp_deg[16];
    (void)snprintf(amp_deg, sizeof(amp_deg), "%s_deg", amp);
    if (find(c, "excitation", amp) == NULL && find(c, "excitation", amp_deg) == NULL)
    {
        return missing(c, 5, d == AENL_SIM_DOF_PLUNGE ? amp : amp_deg);
    }
    if (find(c, "excitation", sweep ? "f_start" : "f_min") == NULL)
    {
        return missing(c, 5, sweep ? "f_start" : "f_min");
    }
    if (find(c, "excitation", sweep ? "f_end" : "f_max") == NULL)
    {
        return missing(c, 5, sweep ? "f_end" : "f_max");
    }
    return AENL_OK;
}

/* Two entries of one section name the same key (x and x_deg count as the same key). */
static aenl_status_t check_duplicates(ini_ctx_t *c)
{
    size_t i, j;
    for (i = 0; i < c->n; ++i)
    {
        for (j = 0; j < i; ++j)
        {
            size_t li = strlen(c->e[i].key), lj = strlen(c->e[j].key);
            const char *ki = c->e[i].key, *kj = c->e[j].key;
            if (strcmp(c->e[i].section, c->e[j].section) != 0)
            {
                continue;
            }
            if (li > 4 && strcmp(ki + li - 4, "_deg") == 0)
            {
                li -= 4;
            }
            if (lj > 4 && strcmp(kj + lj - 4, "_deg") == 0)
            {
                lj -= 4;
            }
            if (li == lj && strncmp(ki, kj, li) == 0)
            {
                aenl_err_set(c->err, "%s:%d: [%s] %s given twice (also at line %d)", c->path,
                             c->e[i].line, c->e[i].section, ki, c->e[j].line);
                return AENL_E_ARG;
            }
        }
    }
    return AENL_OK;
}

/* [model] type, and the defaults of that type in m and r. */
static aenl_status_t read_type(ini_ctx_t *c, aenl_sim_model_t *m, aenl_sim_run_t *r,
                               aenl_sim_type_t *type)
{
    const entry_t *e = find(c, "model", "type");
    if (e == NULL)
    {
        return missing(c, 0, "type");
    }
    if (strcmp(e->value, "airfoil2dof") == 0)
    {
        *type = AENL_SIM_AIRFOIL2DOF;
    }
    else if (strcmp(e->value, "section3dof") == 0)
    {
        *type = AENL_SIM_SECTION3DOF;
    }
    else
    {
        return bad(c, e, "expected airfoil2dof or section3dof");
    }
    aenl_sim_model_default(m, *type);
    aenl_sim_run_default(r, *type);
    if (*type == AENL_SIM_AIRFOIL2DOF && c->sec_line[3] > 0)
    {
        aenl_err_set(c->err, "%s:%d: section [flap] is not valid for type airfoil2dof", c->path,
                     c->sec_line[3]);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* The law of DOF d (its section sec present): its kind, and the keys that kind cannot do
 * without. */
static aenl_status_t read_law(ini_ctx_t *c, int d, int sec, aenl_sim_law_t *law)
{
    const entry_t *e = find(c, sections[sec], "law");
    if (e == NULL)
    {
        return missing(c, sec, "law");
    }
    if (strcmp(e->value, "linear") == 0)
    {
        law->kind = AENL_SIM_LAW_LINEAR;
    }
    else if (strcmp(e->value, "polynomial") == 0)
    {
        law->kind = AENL_SIM_LAW_POLYNOMIAL;
    }
    else if (strcmp(e->value, "freeplay") == 0)
    {
        law->kind = AENL_SIM_LAW_FREEPLAY;
    }
    else if (strcmp(e->value, "hysteresis") == 0)
    {
        law->kind = AENL_SIM_LAW_HYSTERESIS;
    }
    else
    {
        return bad(c, e, "expected linear, polynomial, freeplay or hysteresis");
    }
    if ((law->kind == AENL_SIM_LAW_FREEPLAY || law->kind == AENL_SIM_LAW_HYSTERESIS) &&
        find(c, sections[sec], "delta") == NULL && find(c, sections[sec], "delta_deg") == NULL)
    {
        return missing(c, sec, d == AENL_SIM_DOF_PLUNGE ? "delta" : "delta_deg");
    }
    if (law->kind == AENL_SIM_LAW_POLYNOMIAL && find(c, sections[sec], "coeffs") == NULL)
    {
        return missing(c, sec, "coeffs");
    }
    return AENL_OK;
}

/* Laws first: their kind decides the valid keys. */
static aenl_status_t read_laws(ini_ctx_t *c, aenl_sim_model_t *m)
{
    static const int sec_of_dof[3] = {1, 2, 3};
    aenl_status_t st;
    int d;
    for (d = 0; d < AENL_SIM_N_DOF; ++d)
    {
        const int sec = sec_of_dof[d];
        if (c->sec_line[sec] == 0)
        {
            continue;
        }
        if ((st = read_law(c, d, sec, &m->law[d])) != AENL_OK)
        {
            return st;
        }
    }
    return AENL_OK;
}

/* [excitation] type, which decides the excitation's valid and required keys. */
static aenl_status_t read_excitation_type(ini_ctx_t *c, aenl_sim_run_t *r)
{
    const entry_t *e = find(c, "excitation", "type");
    if (e == NULL)
    {
        return AENL_OK;
    }
    if (strcmp(e->value, "turbulence") == 0)
    {
        r->turbulence = 1;
    }
    else if (strcmp(e->value, "kicks") == 0)
    {
        r->kicks = 1;
    }
    else if (strcmp(e->value, "sweep") == 0)
    {
        r->force = AENL_SIM_FORCE_SWEEP;
    }
    else if (strcmp(e->value, "multisine") == 0)
    {
        r->force = AENL_SIM_FORCE_MULTISINE;
    }
    else if (strcmp(e->value, "none") != 0)
    {
        return bad(c, e, "expected none, turbulence, kicks, sweep or multisine");
    }
    return AENL_OK;
}

/* The DOF that kicks or a force drive, and the keys they cannot do without. */
static aenl_status_t read_excitation_dof(ini_ctx_t *c, aenl_sim_run_t *r, aenl_sim_type_t type)
{
    static const char *const k_dof[3] = {"pitch", "plunge", "flap"};
    const int n_dof = type == AENL_SIM_AIRFOIL2DOF ? 2 : 3;
    const entry_t *e;
    aenl_status_t st;
    int d;
    if (!r->kicks && r->force == AENL_SIM_FORCE_NONE)
    {
        return AENL_OK;
    }
    if ((e = find(c, "excitation", "dof")) == NULL)
    {
        return missing(c, 5, "dof");
    }
    for (d = 0; d < n_dof && strcmp(e->value, k_dof[d]) != 0; ++d)
    {
    }
    if (d == n_dof)
    {
        return bad(c, e,
                   n_dof == 2 ? "expected pitch or plunge" : "expected pitch, plunge or flap");
    }
    r->kick_dof = (aenl_sim_dof_t)d;
    r->force_dof = (aenl_sim_dof_t)d;
    if ((st = force_required(c, r, d)) != AENL_OK)
    {
        return st;
    }
    if (r->kicks)
    {
        if (find(c, "excitation", "every") == NULL)
        {
            return missing(c, 5, "every");
        }
        if (find(c, "excitation", "rate") == NULL && find(c, "excitation", "rate_deg") == NULL)
        {
            return missing(c, 5, d == AENL_SIM_DOF_PLUNGE ? "rate" : "rate_deg");
        }
    }
    return AENL_OK;
}

/* After every entry is applied: the keys no default stands in for, and the bounds between
 * keys. */
static aenl_status_t check_applied(ini_ctx_t *c, aenl_sim_run_t *r, aenl_sim_type_t type)
{
    const entry_t *e;
    if (find(c, "model", type == AENL_SIM_AIRFOIL2DOF ? "ustar" : "velocity") == NULL)
    {
        return missing(c, 0, type == AENL_SIM_AIRFOIL2DOF ? "ustar" : "velocity");
    }
    if (!c->model_only && find(c, "run", "duration") == NULL)
    {
        return missing(c, 6, "duration");
    }
    if (!c->model_only && find(c, "run", "dt") == NULL)
    {
        return missing(c, 6, "dt");
    }
    if (c->sec_line[7] > 0 && find(c, "noise", "snr") == NULL)
    {
        return missing(c, 7, "snr");
    }
    if (r->kicks && find(c, "excitation", "rate_max") == NULL &&
        find(c, "excitation", "rate_max_deg") == NULL)
    {
        r->kick_rate_max = r->kick_rate;
    }
    if (r->kicks && r->kick_rate_max < r->kick_rate)
    {
        e = find(c, "excitation", "rate_max");
        return bad(c, e != NULL ? e : find(c, "excitation", "rate_max_deg"),
                   "must not be below rate");
    }
    if (!c->model_only && r->dt > r->duration)
    {
        e = find(c, "run", "dt");
        return bad(c, e, "must not exceed duration");
    }
    return AENL_OK;
}

static aenl_status_t interpret(ini_ctx_t *c, aenl_sim_model_t *m, aenl_sim_run_t *r)
{
    aenl_status_t st;
    size_t i;
    aenl_sim_type_t type = AENL_SIM_AIRFOIL2DOF; /* read_type sets it before any use */
    if ((st = check_duplicates(c)) != AENL_OK || (st = read_type(c, m, r, &type)) != AENL_OK ||
        (st = read_laws(c, m)) != AENL_OK || (st = read_excitation_type(c, r)) != AENL_OK ||
        (st = read_excitation_dof(c, r, type)) != AENL_OK)
    {
        return st;
    }
    for (i = 0; i < c->n; ++i)
    {
        if ((st = apply_entry(c, &c->e[i], m, r)) != AENL_OK)
        {
            return st;
        }
    }
    if ((st = check_applied(c, r, type)) != AENL_OK)
    {
        return st;
    }
    if ((st = aenl_sim_validate(m, c->model_only ? NULL : r, c->err)) != AENL_OK)
    {
        aenl_err_t inner = *c->err;
        aenl_err_clear(c->err);
        aenl_err_set(c->err, "%s: %s", c->path, inner.msg);
        return st;
    }
    return AENL_OK;
}

aenl_status_t aenl_sim_load_ini(const char *path, aenl_sim_model_t *model, aenl_sim_run_t *run,
                                aenl_err_t *err)
{
    ini_ctx_t c;
    aenl_run_dummy_t dummy;
    aenl_status_t st;
    int rc;
    if (path == NULL || model == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    memset(&c, 0, sizeof(c));
    c.path = path;
    c.err = err;
    c.at_line_start = 1;
    if (run == NULL)
    {
        c.model_only = 1;
        run = &dummy.run;
    }
    struct stat sb;
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
    {
        aenl_err_set(err, "%s: is a folder, not a model file", path);
        return AENL_E_ARG;
    }
    c.fp = fopen(path, "r");
    if (c.fp == NULL)
    {
        aenl_err_set(err, "%s: cannot open: %s", path, strerror(errno));
        return AENL_E_IO;
    }
    aenl_input_note(path);
    rc = ini_parse_stream(reader, &c, handler, &c);
    (void)fclose(c.fp);
    if (c.oom || rc == -2)
    {
        free_entries(&c);
        aenl_err_set(err, "%s: out of memory", path);
        return AENL_E_DIM;
    }
    if (c.failed)
    {
        free_entries(&c);
        return AENL_E_ARG;
    }
    if (rc != 0)
    {
        free_entries(&c);
        aenl_err_set(err, "%s:%d: syntax error (expected [section] or key = value)", path, rc);
        return AENL_E_ARG;
    }
    st = interpret(&c, model, run);
    free_entries(&c);
    return st;
}

/* ---- writer -------------------------------------------------------------------------------- */

static void write_law(FILE *fp, const char *section, const aenl_sim_law_t *l)
{
    static const char *const k_kind[4] = {"linear", "polynomial", "freeplay", "hysteresis"};
    if (l->kind == AENL_SIM_LAW_LINEAR)
    {
        return;
    }
    fprintf(fp, "\n[%s]\nlaw = %s\n", section, k_kind[l->kind]);
    if (l->kind == AENL_SIM_LAW_POLYNOMIAL)
    {
        fprintf(fp, "coeffs = ");
        for (size_t k = 0; k < l->n_coeffs; ++k)
        {
            fprintf(fp, "%s%.17g", k > 0 ? ", " : "", l->coeffs[k]);
        }
        fprintf(fp, "\n");
        return;
    }
    fprintf(fp, "delta = %.17g\nalpha_f = %.17g\npreload = %.17g\n", l->delta, l->x_f, l->preload);
    if (l->kind == AENL_SIM_LAW_FREEPLAY)
    {
        fprintf(fp, "inner_stiffness = %.17g\n", l->inner_stiffness);
    }
}

/* The [initial] estimate key, only when the INI said it (its absence means AUTO). */
static void write_estimate(FILE *fp, const aenl_sim_model_t *m)
{
    if (m->initial != AENL_SIM_INITIAL_AUTO)
    {
        fprintf(fp, "estimate = %s\n", m->initial == AENL_SIM_INITIAL_ESTIMATE ? "true" : "false");
    }
}

void aenl_sim_write_ini(FILE *fp, const aenl_sim_model_t *m, const aenl_sim_run_t *run)
{
    if (m->type == AENL_SIM_AIRFOIL2DOF)
    {
        const aenl_sim_airfoil_t *p = &m->airfoil;
        fprintf(fp,
                "[model]\ntype = airfoil2dof\nmu = %.17g\na_h = %.17g\nx_alpha = %.17g\n"
                "r_alpha = %.17g\nomega_bar = %.17g\nzeta_alpha = %.17g\nzeta_xi = %.17g\n"
                "ustar = %.17g\nic_forcing = %s\n",
                p->mu, p->a_h, p->x_alpha, p->r_alpha, p->omega_bar, p->zeta_alpha, p->zeta_xi,
                p->ustar, p->ic_forcing ? "true" : "false");
        write_law(fp, "pitch", &m->law[AENL_SIM_DOF_PITCH]);
        write_law(fp, "plunge", &m->law[AENL_SIM_DOF_PLUNGE]);
        fprintf(fp, "\n[initial]\nalpha = %.17g\nxi = %.17g\nalpha_dot = %.17g\nxi_dot = %.17g\n",
                m->x0[AENL_SIM_DOF_PITCH], m->x0[AENL_SIM_DOF_PLUNGE], m->v0[AENL_SIM_DOF_PITCH],
                m->v0[AENL_SIM_DOF_PLUNGE]);
        write_estimate(fp, m);
    }
    else
    {
        const aenl_sim_section_t *p = &m->section;
        fprintf(fp,
                "[model]\ntype = section3dof\nvelocity = %.17g\nb = %.17g\na = %.17g\n"
                "c = %.17g\nm = %.17g\nm_t = %.17g\nx_alpha = %.17g\nx_beta = %.17g\n"
                "r_alpha = %.17g\nr_beta = %.17g\nomega_h = %.17g\nomega_alpha = %.17g\n"
                "omega_beta = %.17g\nzeta_h = %.17g\nzeta_alpha = %.17g\nzeta_beta = %.17g\n"
                "rho = %.17g\n",
                p->velocity, p->b, p->a, p->c, p->m, p->m_t, p->x_alpha, p->x_beta, p->r_alpha,
                p->r_beta, p->omega_h, p->omega_alpha, p->omega_beta, p->zeta_h, p->zeta_alpha,
                p->zeta_beta, p->rho);
        write_law(fp, "pitch", &m->law[AENL_SIM_DOF_PITCH]);
        write_law(fp, "plunge", &m->law[AENL_SIM_DOF_PLUNGE]);
        write_law(fp, "flap", &m->law[AENL_SIM_DOF_FLAP]);
        fprintf(fp,
                "\n[initial]\nh = %.17g\nalpha = %.17g\nbeta = %.17g\nh_dot = %.17g\n"
                "alpha_dot = %.17g\nbeta_dot = %.17g\n",
                m->x0[AENL_SIM_DOF_PLUNGE], m->x0[AENL_SIM_DOF_PITCH], m->x0[AENL_SIM_DOF_FLAP],
                m->v0[AENL_SIM_DOF_PLUNGE], m->v0[AENL_SIM_DOF_PITCH], m->v0[AENL_SIM_DOF_FLAP]);
        write_estimate(fp, m);
    }
    if (run->turbulence)
    {
        fprintf(fp,
                "\n[excitation]\ntype = turbulence\nintensity = %.17g\nlength_scale = %.17g\n"
                "spectrum = %s\nseed = %llu\n",
                run->turb_intensity, run->turb_length,
                run->turb_spectrum == AENL_SIM_GUST_DRYDEN ? "dryden" : "first_order",
                (unsigned long long)run->turb_seed);
    }
    if (run->kicks)
    {
        static const char *const k_dof[3] = {"pitch", "plunge", "flap"};
        static const char *const k_sign[3] = {"random", "alternate", "positive"};
        fprintf(fp,
                "\n[excitation]\ntype = kicks\ndof = %s\nevery = %.17g\nrate = %.17g\n"
                "rate_max = %.17g\nsign = %s\nseed = %llu\n",
                k_dof[run->kick_dof], run->kick_every, run->kick_rate, run->kick_rate_max,
                k_sign[run->kick_sign], (unsigned long long)run->kick_seed);
    }
    if (run->force == AENL_SIM_FORCE_SWEEP)
    {
        static const char *const k_dof[3] = {"pitch", "plunge", "flap"};
        fprintf(fp,
                "\n[excitation]\ntype = sweep\ndof = %s\namplitude = %.17g\nf_start = %.17g\n"
                "f_end = %.17g\nlaw = %s\n",
                k_dof[run->force_dof], run->force_amp, run->force_f0, run->force_f1,
                run->force_log ? "log" : "linear");
    }
    if (run->force == AENL_SIM_FORCE_MULTISINE)
    {
        static const char *const k_dof[3] = {"pitch", "plunge", "flap"};
        fprintf(fp,
                "\n[excitation]\ntype = multisine\ndof = %s\nrms = %.17g\nf_min = %.17g\n"
                "f_max = %.17g\nseed = %llu\n",
                k_dof[run->force_dof], run->force_amp, run->force_f0, run->force_f1,
                (unsigned long long)run->force_seed);
        if (run->force_period > 0.0)
        {
            fprintf(fp, "period = %.17g\n", run->force_period);
        }
    }
    fprintf(fp, "\n[run]\nduration = %.17g\ndt = %.17g\nrtol = %.17g\natol = %.17g\n",
            run->duration, run->dt, run->rtol, run->atol);
    if (run->snr > 0.0)
    {
        fprintf(fp, "\n[noise]\nsnr = %.17g\nseed = %llu\n", run->snr,
                (unsigned long long)run->noise_seed);
    }
}
