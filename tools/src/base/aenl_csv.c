/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_csv.c
 * @brief Host-only CSV reading (streaming and whole-table) and writing. See aenl_csv.h.
 *
 * Reader: the file is read in blocks into one buffer that grows only for a longer line, so
 * memory does not grow with the file's length, and each line is taken where it lies. Physical
 * lines are counted (comments and blank lines included), so "FILE:LINE:COLUMN" points at what
 * an editor shows; COLUMN is the 1-based field index and the header name follows in
 * parentheses. A plain decimal number whose digits make at most 2^53 and whose power of ten
 * is within 10^+-22 (where long double is x87 extended: of at most 19 significant digits, within
 * 10^+-27) is converted exactly by aenl_parse_decimal; any other goes through strtod(), and the
 * tools never call setlocale(), so that is the C locale.
 *
 * Statuses: AENL_E_IO cannot open/read/write; AENL_E_EMPTY no header row (empty file);
 * AENL_E_ARG malformed content (not a number, ragged row, bad header, binary data) or bad
 * arguments; AENL_E_NUMERIC an infinite or out-of-range number.
 */
#define _POSIX_C_SOURCE 200809L

#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_mem.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

struct aenl_csv
{
    FILE *fp;
    int own_fp; /* 0 for stdin */
    char *path;
    char *buf;  /* what has been read of the file: [beg, end) not yet taken as lines */
    size_t cap; /* buf's size; one byte more than end always fits */
    size_t beg;
    size_t end;
    int at_eof;            /* the file has no more bytes */
    char *line;            /* the last line read, in buf, NUL-terminated */
    unsigned long line_no; /* physical line of the last line read */
    size_t n_cols;
    char **names;
    aenl_status_t failed; /* sticky: once a read failed, later calls fail too */
    size_t data_rows;     /* data rows read so far */
    char sep;             /* the separator: ',', or the header's ';' or tab when it has no comma */
};

/* ---- small helpers ------------------------------------------------------------------------- */

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = (char *)malloc(n);
    if (d != NULL)
    {
        memcpy(d, s, n);
    }
    return d;
}

static int is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* Trim blanks on both sides in place; returns the new start. */
/* Blanks off both ends: s[0 .. *n) ends at a NUL; the trailing blanks become NULs and *n the
 * length of what is left. */
static char *trim_n(char *s, size_t *n)
{
    size_t k = *n;
    while (k > 0 && is_blank(*s))
    {
        ++s;
        --k;
    }
    while (k > 0 && is_blank(s[k - 1]))
    {
        s[--k] = '\0';
    }
    *n = k;
    return s;
}

static char *trim(char *s)
{
    size_t n = strlen(s);
    return trim_n(s, &n);
}

static int is_digit(char c)
{
    return (unsigned)((unsigned char)c - (unsigned char)'0') <= 9u;
}

static int ascii_lower(int c)
{
    return (c >= 'A' && c <= 'Z') ? c - 'A' + 'a' : c;
}

/* "nan" or "-nan" in any letter case. */
static int is_nan_word(const char *s)
{
    if (*s == '-')
    {
        ++s;
    }
    return ascii_lower((unsigned char)s[0]) == 'n' && ascii_lower((unsigned char)s[1]) == 'a' &&
           ascii_lower((unsigned char)s[2]) == 'n' && s[3] == '\0';
}

static void free_names(char **names, size_t n)
{
    size_t i;
    if (names == NULL)
    {
        return;
    }
    for (i = 0; i < n; ++i)
    {
        free(names[i]);
    }
    free(names);
}

/* ---- line reading -------------------------------------------------------------------------- */

#define CSV_BLOCK ((size_t)1 << 16u) /* bytes a read asks for, at least */

enum
{
    LINE_OK = 1,
    LINE_EOF = 0
};

/* From i, the first index of s[0 .. len) whose 8-byte word may hold a control byte (below 0x20,
 * tab included, or 0x7F), or len. The test is a word at a time: a byte-by-byte scan was a tenth
 * of the time of reading a large record. A word that may hold one is left to the caller's
 * byte-by-byte check, which lets the tab pass. */
static size_t clean_prefix(const char *s, size_t i, size_t len)
{
    const uint64_t ones = 0x0101010101010101u, highs = 0x8080808080808080u;
    for (; i + 8u <= len; i += 8u)
    {
        uint64_t x;
        memcpy(&x, s + i, sizeof(x));
        const uint64_t del = x ^ (0x7Fu * ones);
        /* nonzero exactly when some byte of x is below 0x20 or some byte of del is zero (x's is
         * 0x7F); a borrow may mark a byte after a true one too, never one on its own */
        if ((((x - 0x20u * ones) & ~x) | ((del - ones) & ~del)) & highs)
        {
            return i;
        }
    }
    return i;
}

/**
 * Read one physical line into csv->line without its "\n" / "\r\n". Rejects NUL and control bytes
 * (binary data). Returns LINE_OK, LINE_EOF or a negative status.
 */
static int read_line(aenl_csv_t *csv, aenl_err_t *err)
{
    size_t len;
    size_t i;
    char *s;

    /* the file is read in blocks and each line taken in place (getline's copy, lock and
     * allocation per line were a fifth of the time of reading a large record) */
    char *nl = NULL;
    for (;;)
    {
        nl = (csv->end > csv->beg) ? memchr(csv->buf + csv->beg, '\n', csv->end - csv->beg) : NULL;
        if (nl != NULL || csv->at_eof)
        {
            break;
        }
        if (csv->beg > 0)
        {
            memmove(csv->buf, csv->buf + csv->beg, csv->end - csv->beg);
            csv->end -= csv->beg;
            csv->beg = 0;
        }
        if (csv->cap - csv->end < CSV_BLOCK / 2u)
        {
            const size_t cap = (csv->cap < CSV_BLOCK) ? CSV_BLOCK : 2u * csv->cap;
            char *b = (cap > csv->cap) ? (char *)realloc(csv->buf, cap) : NULL;
            if (b == NULL)
            {
                aenl_err_set(err, "%s:%lu: out of memory (a line of %lu bytes)", csv->path,
                             csv->line_no + 1UL, (unsigned long)csv->end);
                return AENL_E_IO;
            }
            csv->buf = b;
            csv->cap = cap;
        }
        errno = 0;
        const size_t got = fread(csv->buf + csv->end, 1, csv->cap - 1u - csv->end, csv->fp);
        csv->end += got;
        if (got == 0)
        {
            if (ferror(csv->fp))
            {
                aenl_err_set(err, "%s:%lu: read error (%s)", csv->path, csv->line_no + 1UL,
                             strerror(errno != 0 ? errno : EIO));
                return AENL_E_IO;
            }
            csv->at_eof = 1;
        }
    }
    if (nl == NULL && csv->beg == csv->end)
    {
        return LINE_EOF;
    }
    s = csv->buf + csv->beg;
    if (nl != NULL)
    {
        len = (size_t)(nl - s);
        csv->beg += len + 1u;
    }
    else
    {
        len = csv->end - csv->beg; /* a last line without its newline */
        csv->beg = csv->end;
    }
    s[len] = '\0'; /* the newline's place, or the byte kept free after end */
    csv->line = s;
    ++csv->line_no;
    if (len > 0 && s[len - 1] == '\r')
    {
        s[--len] = '\0';
    }
    if (csv->line_no == 1 && len >= 3 && (unsigned char)s[0] == 0xEFU &&
        (unsigned char)s[1] == 0xBBU && (unsigned char)s[2] == 0xBFU)
    {
        memmove(s, s + 3, len - 3 + 1); /* UTF-8 byte order mark */
        len -= 3;
    }
    for (i = 0; i < len; ++i)
    {
        i = clean_prefix(s, i, len);
        if (i == len)
        {
            break;
        }
        unsigned char c = (unsigned char)s[i];
        if (c == 0U)
        {
            aenl_err_set(err, "%s:%lu: NUL byte at character %lu (binary file?)", csv->path,
                         csv->line_no, (unsigned long)(i + 1));
            return AENL_E_ARG;
        }
        if ((c < 0x20U && c != (unsigned char)'\t') || c == 0x7FU)
        {
            aenl_err_set(err, "%s:%lu: control byte 0x%02x at character %lu (binary file?)",
                         csv->path, csv->line_no, (unsigned)c, (unsigned long)(i + 1));
            return AENL_E_ARG;
        }
    }
    return LINE_OK;
}

/* Blank (only spaces/tabs) or a comment ('#' as first non-blank character). */
static int skip_line(const char *s)
{
    while (is_blank(*s))
    {
        ++s;
    }
    return *s == '\0' || *s == '#';
}

/* Next line that is not blank or a comment. */
static int read_content_line(aenl_csv_t *csv, aenl_err_t *err)
{
    for (;;)
    {
        int rc = read_line(csv, err);
        if (rc != LINE_OK)
        {
            return rc;
        }
        if (!skip_line(csv->line))
        {
            return LINE_OK;
        }
    }
}

/* ---- header -------------------------------------------------------------------------------- */

static aenl_status_t parse_header(aenl_csv_t *csv, aenl_err_t *err)
{
    size_t n = 1;
    size_t c;
    const char *p;
    char *cell;

    /* A spreadsheet's export in many locales separates by ';' (its decimals then are commas,
     * which parse_cell names), a tab-separated export by tabs: a header without a comma tells. */
    csv->sep = ',';
    if (strchr(csv->line, ',') == NULL && strchr(csv->line, ';') != NULL)
    {
        csv->sep = ';';
    }
    else if (strchr(csv->line, ',') == NULL && strchr(csv->line, '\t') != NULL)
    {
        csv->sep = '\t';
    }
    for (p = csv->line; *p != '\0'; ++p)
    {
        n += (*p == csv->sep) ? 1U : 0U;
    }
    csv->names = (char **)calloc(n, sizeof *csv->names);
    if (csv->names == NULL)
    {
        aenl_err_set(err, "%s: out of memory", csv->path);
        return AENL_E_IO;
    }
    cell = csv->line;
    for (c = 0; c < n; ++c)
    {
        char *name;
        size_t len;
        size_t k;
        char *next = strchr(cell, csv->sep);
        if (next != NULL)
        {
            *next = '\0';
        }
        name = trim(cell);
        len = strlen(name);
        if (len >= 2 && name[0] == '"' && name[len - 1] == '"')
        {
            name[len - 1] = '\0'; /* a quoted name: "t" */
            name = trim(name + 1);
        }
        if (name[0] == '\0')
        {
            aenl_err_set(err, "%s:%lu:%lu: empty column name in the header row", csv->path,
                         csv->line_no, (unsigned long)(c + 1));
            csv->n_cols = c;
            return AENL_E_ARG;
        }
        for (k = 0; k < c; ++k)
        {
            if (strcmp(csv->names[k], name) == 0)
            {
                aenl_err_set(err, "%s:%lu:%lu (%s): duplicate column name '%s' (also column %lu)",
                             csv->path, csv->line_no, (unsigned long)(c + 1), name, name,
                             (unsigned long)(k + 1));
                csv->n_cols = c;
                return AENL_E_ARG;
            }
        }
        csv->names[c] = dup_str(name);
        if (csv->names[c] == NULL)
        {
            aenl_err_set(err, "%s: out of memory", csv->path);
            csv->n_cols = c;
            return AENL_E_IO;
        }
        cell = (next != NULL) ? next + 1 : cell + strlen(cell);
    }
    csv->n_cols = n;
    return AENL_OK;
}

/* ---- streaming reader ---------------------------------------------------------------------- */

void aenl_csv_close(aenl_csv_t *csv)
{
    if (csv == NULL)
    {
        return;
    }
    if (csv->fp != NULL && csv->own_fp)
    {
        (void)fclose(csv->fp);
    }
    free_names(csv->names, csv->n_cols);
    free(csv->buf);
    free(csv->path);
    free(csv);
}

aenl_status_t aenl_csv_open(aenl_csv_t **out, const char *path, aenl_err_t *err)
{
    aenl_csv_t *csv;
    int rc;
    aenl_status_t st;

    if (out == NULL || path == NULL || path[0] == '\0')
    {
        aenl_err_set(err, "aenl_csv_open: NULL or empty argument");
        return AENL_E_ARG;
    }
    *out = NULL;
    csv = (aenl_csv_t *)calloc(1, sizeof *csv);
    if (csv == NULL)
    {
        aenl_err_set(err, "%s: out of memory", path);
        return AENL_E_IO;
    }
    csv->path = dup_str(path);
    if (csv->path == NULL)
    {
        free(csv);
        aenl_err_set(err, "%s: out of memory", path);
        return AENL_E_IO;
    }
    if (strcmp(path, "-") == 0)
    {
        csv->fp = stdin;
        csv->own_fp = 0;
    }
    else
    {
        csv->fp = fopen(path, "r");
        csv->own_fp = 1;
        aenl_input_note(path);
        if (csv->fp == NULL)
        {
            aenl_err_set(err, "%s: cannot open (%s)", path, strerror(errno));
            aenl_csv_close(csv);
            return AENL_E_IO;
        }
    }
    rc = read_content_line(csv, err);
    if (rc == LINE_EOF)
    {
        if (csv->line_no == 0)
        {
            aenl_err_set(err, "%s: empty file (no header row)", path);
        }
        else
        {
            aenl_err_set(err, "%s: empty file (no header row; only comments or blank lines)", path);
        }
        aenl_csv_close(csv);
        return AENL_E_EMPTY;
    }
    if (rc < 0)
    {
        aenl_csv_close(csv);
        return (aenl_status_t)rc;
    }
    st = parse_header(csv, err);
    if (st != AENL_OK)
    {
        aenl_csv_close(csv);
        return st;
    }
    *out = csv;
    return AENL_OK;
}

size_t aenl_csv_n_cols(const aenl_csv_t *csv)
{
    return (csv != NULL) ? csv->n_cols : 0U;
}

const char *aenl_csv_col_name(const aenl_csv_t *csv, size_t col)
{
    return (csv != NULL && col < csv->n_cols) ? csv->names[col] : NULL;
}

static long find_name(char *const *names, size_t n, const char *name)
{
    size_t i;
    if (names == NULL || name == NULL)
    {
        return -1;
    }
    for (i = 0; i < n; ++i)
    {
        if (strcmp(names[i], name) == 0)
        {
            return (long)i;
        }
    }
    return -1;
}

long aenl_csv_find(const aenl_csv_t *csv, const char *name)
{
    return (csv != NULL) ? find_name(csv->names, csv->n_cols, name) : -1;
}

unsigned long aenl_csv_line(const aenl_csv_t *csv)
{
    return (csv != NULL) ? csv->line_no : 0UL;
}

const char *aenl_csv_path(const aenl_csv_t *csv)
{
    return (csv != NULL) ? csv->path : NULL;
}

/* 1 for a cell that reads like a unit: a word ("s", "rad"), or anything in brackets or
 * parentheses ("[s]", "(m/s)", "[-]"). */
static int looks_like_unit(const char *cell)
{
    const size_t n = strlen(cell);
    return isalpha((unsigned char)cell[0]) ||
           (n >= 2u &&
            ((cell[0] == '[' && cell[n - 1u] == ']') || (cell[0] == '(' && cell[n - 1u] == ')')));
}

#if LDBL_MANT_DIG == 64 && (defined(__x86_64__) || defined(__i386__))
/* 1 when long double arithmetic here is what the type promises: an emulator (valgrind's, for
 * one) may carry it in doubles, where 2^53 + 1 is not exact. Probed once. */
static int extended_exact(void)
{
    static int state = 0; /* 0 unknown, 1 exact, -1 not */
    if (state == 0)
    {
        volatile uint64_t w = ((uint64_t)1 << 53u) + 1u;
        volatile long double x = (long double)w;
        volatile long double y = x * 1e27L / 1e27L;
        state = ((uint64_t)x == w && (uint64_t)y == w) ? 1 : -1;
    }
    return state > 0;
}

/* w 10^e10 (w > 0, at most 19 digits, |e10| <= 27) in x87 extended precision, whose 64-bit
 * significand holds w and 10^|e10| exactly, so that one multiplication or division rounds once;
 * rounding that to a double rounds twice, which differs from rounding once only when the
 * extended result lies exactly halfway between two doubles (its 11 bits below the double's
 * last are 10000000000): then 0, and strtod decides. 1 with *x set otherwise. */
static int parse_extended(uint64_t w, int e10, double *x)
{
    static const long double p10[28] = {1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,
                                        1e7L,  1e8L,  1e9L,  1e10L, 1e11L, 1e12L, 1e13L,
                                        1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L, 1e20L,
                                        1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};
    if (e10 > 27 || e10 < -27 || !extended_exact())
    {
        return 0;
    }
    const long double lw = (long double)w;
    const long double r = e10 >= 0 ? lw * p10[e10] : lw / p10[-e10];
    uint64_t sig = 0;
    memcpy(&sig, &r, sizeof(sig)); /* the significand, explicit leading bit included */
    if ((sig & 0x7FFu) == 0x400u)
    {
        return 0;
    }
    *x = (double)r;
    return 1;
}
#else
static int parse_extended(uint64_t w, int e10, double *x)
{
    (void)w;
    (void)e10;
    (void)x;
    return 0; /* no exact wider type: strtod */
}
#endif

/* 1 with *d the value of the 8 decimal digits at p (the first the most significant), 0 when a
 * byte of the 8 is not a digit; 8 bytes at p must be readable. A word at a time where the bytes'
 * order allows: b - '0' borrows into the high bit exactly when b < '0', b + 0x46 carries into it
 * exactly when b > '9' (a byte of 0x80 or more has one of them set), and then three
 * multiplications gather the digits pairwise. */
static int eight_digits(const char *p, uint32_t *d)
{
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__) &&                                 \
    __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    uint64_t x;
    memcpy(&x, p, sizeof(x));
    const uint64_t lo = x - 0x3030303030303030u;
    if (((lo | (x + 0x4646464646464646u)) & 0x8080808080808080u) != 0u)
    {
        return 0;
    }
    x = lo * 10u + (lo >> 8u); /* byte 2i: the two digits 2i, 2i + 1 */
    x = ((x & 0x000000FF000000FFu) * (100u + (1000000ull << 32u)) +
         ((x >> 16u) & 0x000000FF000000FFu) * (1u + (10000ull << 32u))) >>
        32u;
    *d = (uint32_t)x;
    return 1;
#else
    uint32_t v = 0;
    for (int i = 0; i < 8; ++i)
    {
        if (!is_digit(p[i]))
        {
            return 0;
        }
        v = 10u * v + (uint32_t)(p[i] - '0');
    }
    *d = v;
    return 1;
#endif
}

/* w = 10^k w + the k digits from s on; returns the byte after them. Reads nothing past end,
 * where the string's NUL is. */
static const char *take_digits(const char *s, const char *end, uint64_t *w)
{
    uint32_t d8;
    while (end - s >= 8 && eight_digits(s, &d8))
    {
        *w = 100000000u * *w + d8;
        s += 8;
    }
    while (is_digit(*s))
    {
        *w = 10u * *w + (uint64_t)(*s - '0');
        ++s;
    }
    return s;
}

/* aenl_parse_decimal of the n bytes at s, s[n] a NUL. */
static int parse_decimal_n(const char *s, size_t n, double *v)
{
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0
    const char *const end = s + n;
    /* Clinger's fast path: w and 10^|e| are both exact doubles, so w * 10^e and w / 10^-e are
     * each one correctly rounded operation, the value strtod gives */
    static const double p10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                   1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                   1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const int neg = *s == '-';
    s += (*s == '-' || *s == '+') ? 1 : 0;
    /* Digits are counted by where the scan stops, not one counter a character: this loop is
     * most of the time of reading a large record. w takes every digit after the leading zeros;
     * more than 19 of them may wrap it around, and are then left to strtod. */
    const char *const start = s;
    uint64_t w = 0;
    while (*s == '0')
    {
        ++s;
    }
    const char *sig_from = s;
    s = take_digits(s, end, &w);
    ptrdiff_t n_sig = s - sig_from;
    int any_digit = s > start;
    int e10 = 0;
    if (*s == '.')
    {
        const char *const frac = ++s;
        if (w == 0)
        {
            while (*s == '0')
            {
                ++s; /* a leading zero: only its place counts */
            }
        }
        sig_from = s;
        s = take_digits(s, end, &w);
        n_sig += s - sig_from;
        if (s - frac > 400)
        {
            return 0; /* hundreds of zeros after the point: strtod's */
        }
        e10 = -(int)(s - frac);
        any_digit = any_digit || s > frac;
    }
    if (!any_digit || n_sig > 19)
    {
        return 0; /* no digit; or w >= 10^19, beyond 64 bits soon */
    }
    if (*s == 'e' || *s == 'E')
    {
        ++s;
        const int eneg = *s == '-';
        s += (*s == '-' || *s == '+') ? 1 : 0;
        int x = 0, nx = 0;
        for (; is_digit(*s); ++s)
        {
            if (++nx > 4)
            {
                return 0;
            }
            x = 10 * x + (*s - '0');
        }
        if (nx == 0)
        {
            return 0;
        }
        e10 += eneg ? -x : x;
    }
    if (*s != '\0')
    {
        return 0;
    }
    double x = (double)w;
    const int exact_w = w <= ((uint64_t)1 << 53u); /* then w is an exact double */
    if (w == 0)
    {
        x = 0.0;
    }
    else if (exact_w && e10 >= 0 && e10 <= 22)
    {
        x *= p10[e10];
    }
    else if (exact_w && e10 < 0 && e10 >= -22)
    {
        x /= p10[-e10];
    }
    else if (!parse_extended(w, e10, &x))
    {
        return 0;
    }
    *v = neg ? -x : x;
    return 1;
#else
    (void)s;
    (void)n;
    (void)v;
    return 0; /* wider evaluation would round twice: strtod */
#endif
}

int aenl_parse_decimal(const char *s, double *v)
{
    return parse_decimal_n(s, strlen(s), v);
}

double aenl_strtod_decimal(const char *s, char **end)
{
    const char *p = s;
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r' || *p == '\f' || *p == '\v')
    {
        ++p;
    }
    p += (*p == '+' || *p == '-') ? 1 : 0;
    const double v = strtod(s, end);
    if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X'))
    {
        *end -= *end - s; /* strtod's convention for text it cannot read: *end = s */
        return 0.0;
    }
    return v;
}

/* One cell → value (NaN for a missing cell). `cell` is already trimmed. */
static aenl_status_t parse_cell(const aenl_csv_t *csv, size_t c, const char *cell, size_t n,
                                double *value, aenl_err_t *err)
{
    char *end = NULL;
    double v;
    if (cell[0] == '\0' || is_nan_word(cell))
    {
        *value = (double)NAN;
        return AENL_OK;
    }
    if (parse_decimal_n(cell, n, value))
    {
        return AENL_OK;
    }
    errno = 0;
    v = aenl_strtod_decimal(cell, &end);
    if (end == cell || *end != '\0' || isnan(v))
    {
        /* a unit where the first data row starts is most often a row of units */
        const int unit_row = csv->data_rows == 0 && c == 0 && looks_like_unit(cell);
        const int comma = csv->sep != ',' && strchr(cell, ',') != NULL;
        aenl_err_set(err, "%s:%lu:%lu (%s): not a number '%.60s'%s", csv->path, csv->line_no,
                     (unsigned long)(c + 1), csv->names[c], cell,
                     unit_row ? " (a row of units? remove it or start it with '#')"
                              : (comma ? " (a decimal comma? aenl reads '.' decimals: export "
                                         "the file with '.' as the decimal separator)"
                                       : ""));
        return AENL_E_ARG;
    }
    if (isinf(v))
    {
        if (errno == ERANGE)
        {
            aenl_err_set(err, "%s:%lu:%lu (%s): number out of range '%.60s'", csv->path,
                         csv->line_no, (unsigned long)(c + 1), csv->names[c], cell);
        }
        else
        {
            aenl_err_set(err,
                         "%s:%lu:%lu (%s): infinite value '%.60s' (use nan or an empty cell for "
                         "a missing sample)",
                         csv->path, csv->line_no, (unsigned long)(c + 1), csv->names[c], cell);
        }
        return AENL_E_NUMERIC;
    }
    *value = v; /* an underflow to a subnormal or zero is accepted */
    return AENL_OK;
}

static aenl_status_t parse_row(const aenl_csv_t *csv, char *line, double *row, aenl_err_t *err)
{
    size_t c = 0;
    char *cell = line;
    for (;;)
    {
        char *next = strchr(cell, csv->sep);
        aenl_status_t st;
        if (next != NULL)
        {
            *next = '\0';
        }
        if (c >= csv->n_cols)
        {
            size_t n_cells = c + 1;
            while (next != NULL)
            {
                next = strchr(next + 1, csv->sep);
                ++n_cells;
            }
            aenl_err_set(err, "%s:%lu:%lu: extra cell (row has %lu cells, header has %lu)",
                         csv->path, csv->line_no, (unsigned long)(c + 1), (unsigned long)n_cells,
                         (unsigned long)csv->n_cols);
            return AENL_E_ARG;
        }
        size_t n = (next != NULL) ? (size_t)(next - cell) : strlen(cell);
        char *const value = trim_n(cell, &n);
        st = parse_cell(csv, c, value, n, &row[c], err);
        if (st != AENL_OK)
        {
            return st;
        }
        ++c;
        if (next == NULL)
        {
            break;
        }
        cell = next + 1;
    }
    if (c < csv->n_cols)
    {
        aenl_err_set(err, "%s:%lu:%lu (%s): missing cell (row has %lu cells, header has %lu)",
                     csv->path, csv->line_no, (unsigned long)(c + 1), csv->names[c],
                     (unsigned long)c, (unsigned long)csv->n_cols);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

int aenl_csv_next(aenl_csv_t *csv, double *row, aenl_err_t *err)
{
    int rc;
    aenl_status_t st;
    if (csv == NULL || row == NULL)
    {
        aenl_err_set(err, "aenl_csv_next: NULL argument");
        return (int)AENL_E_ARG;
    }
    if (csv->failed != AENL_OK)
    {
        aenl_err_set(err, "%s:%lu: reading stopped at an earlier error", csv->path, csv->line_no);
        return (int)csv->failed;
    }
    rc = read_content_line(csv, err);
    if (rc == LINE_EOF)
    {
        return 0;
    }
    if (rc < 0)
    {
        csv->failed = (aenl_status_t)rc;
        return rc;
    }
    st = parse_row(csv, csv->line, row, err);
    if (st != AENL_OK)
    {
        csv->failed = st;
        return (int)st;
    }
    csv->data_rows++;
    return 1;
}

/* ---- whole table --------------------------------------------------------------------------- */

static void table_zero(aenl_table_t *t)
{
    t->n_rows = 0;
    t->n_cols = 0;
    t->names = NULL;
    t->data = NULL;
    t->n_nan = NULL;
}

void aenl_table_free(aenl_table_t *t)
{
    if (t == NULL)
    {
        return;
    }
    free_names(t->names, t->names != NULL ? t->n_cols : 0U);
    free(t->data);
    free(t->n_nan);
    table_zero(t);
}

long aenl_table_find(const aenl_table_t *t, const char *name)
{
    return (t != NULL) ? find_name(t->names, t->n_cols, name) : -1;
}

double *aenl_table_col(const aenl_table_t *t, size_t c)
{
    if (t == NULL || t->data == NULL || c >= t->n_cols)
    {
        return NULL;
    }
    return t->data + c * t->n_rows;
}

/* names[0..n-1] copied; NULL on allocation failure. */
static char **copy_names(const char *const *names, size_t n)
{
    size_t i;
    char **out = (char **)calloc(n, sizeof *out);
    if (out == NULL)
    {
        return NULL;
    }
    for (i = 0; i < n; ++i)
    {
        out[i] = dup_str(names[i]);
        if (out[i] == NULL)
        {
            free_names(out, i);
            return NULL;
        }
    }
    return out;
}

/**
 * Grow the column-major buffer (column stride cap) to new_cap rows in place: realloc, then move
 * the columns up from the last to the first (a column's destination never overlaps a column
 * that has not moved yet).
 */
static double *grow_columns(double *data, size_t n_cols, size_t n_rows, size_t cap, size_t new_cap)
{
    size_t c;
    double *grown = (double *)realloc(data, n_cols * new_cap * sizeof *grown);
    if (grown == NULL)
    {
        return NULL;
    }
    for (c = n_cols; c-- > 1;)
    {
        memmove(grown + c * new_cap, grown + c * cap, n_rows * sizeof *grown);
    }
    return grown;
}

/* Rows read so far: column-major, column stride cap. */
typedef struct
{
    double *data;
    size_t cap, n_rows;
    size_t *n_nan; /* per column */
} rows_t;

static void rows_free(rows_t *r)
{
    free(r->data);
    free(r->n_nan);
    memset(r, 0, sizeof(*r));
}

/* Room for cap rows in the empty r, so that a table whose size is known ahead is not grown and
 * moved row block by row block; r stays empty (and grows as it goes) when memory lacks. */
static void rows_reserve(rows_t *r, size_t n_cols, size_t cap)
{
    if (cap == 0 || cap > SIZE_MAX / sizeof(double) / n_cols)
    {
        return;
    }
    r->data = (double *)aenl_alloc_large(n_cols * cap * sizeof(double));
    r->cap = r->data != NULL ? cap : 0u;
}

/* The bytes of the regular file csv reads that its reader has not taken in yet, its size less
 * its position, into *left: 0 for anything else (a pipe, a device) or when it cannot be told. */
static int bytes_left(const aenl_csv_t *csv, uint64_t *left)
{
    struct stat sb;
    if (!csv->own_fp || fstat(fileno(csv->fp), &sb) != 0 || !S_ISREG(sb.st_mode))
    {
        return 0;
    }
    const off_t at = ftello(csv->fp);
    *left = (at >= 0 && sb.st_size > at) ? (uint64_t)(sb.st_size - at) : 0u;
    return at >= 0;
}

/* The data rows csv's file likely holds from where its reader stands (0: not known): the lines
 * in its buffer give the bytes a line, and a twentieth more is allowed; never more than the
 * bytes can hold, a row being at least n_cols bytes (its separators and its newline), so that
 * short lines at the top (comments) cannot ask for far more than the file. */
static size_t rows_likely(const aenl_csv_t *csv)
{
    uint64_t left = 0;
    if (!bytes_left(csv, &left))
    {
        return 0;
    }
    size_t lines = 0;
    for (const char *p = csv->buf + csv->beg, *end = csv->buf + csv->end;
         (p = (const char *)memchr(p, '\n', (size_t)(end - p))) != NULL; ++p)
    {
        ++lines;
    }
    if (lines < 16u)
    {
        return 0;
    }
    const double buffered = (double)(csv->end - csv->beg);
    const double bytes = buffered + (double)left;
    const double guess =
        fmin(1.05 * bytes * (double)lines / buffered + 1024.0, bytes / (double)csv->n_cols + 1.0);
    return guess < (double)(SIZE_MAX / 2u) ? (size_t)guess : 0u;
}

/* The data rows of csv from where it stands to its end, appended to r. */
static aenl_status_t read_rows(aenl_csv_t *csv, rows_t *r, aenl_err_t *err)
{
    const size_t n_cols = csv->n_cols;
    double *row = (double *)calloc(n_cols, sizeof *row);
    if (row == NULL)
    {
        aenl_err_set(err, "%s: out of memory", csv->path);
        return AENL_E_IO;
    }
    size_t *n_nan = r->n_nan;
    double *data = r->data;
    size_t cap = r->cap;
    size_t n_rows = r->n_rows;
    aenl_status_t st = AENL_OK;
    int rc;
    while ((rc = aenl_csv_next(csv, row, err)) == 1)
    {
        if (n_rows == cap)
        {
            const size_t new_cap = (cap == 0) ? 1024U : 2U * cap;
            if (new_cap > SIZE_MAX / sizeof(double) / n_cols)
            {
                aenl_err_set(err, "%s:%lu: table too large", csv->path, csv->line_no);
                st = AENL_E_IO;
                break;
            }
            double *grown = grow_columns(data, n_cols, n_rows, cap, new_cap);
            if (grown == NULL)
            {
                aenl_err_set(err, "%s:%lu: out of memory (%lu rows)", csv->path, csv->line_no,
                             (unsigned long)n_rows);
                st = AENL_E_IO;
                break;
            }
            data = grown;
            cap = new_cap;
        }
        for (size_t c = 0; c < n_cols; ++c)
        {
            data[c * cap + n_rows] = row[c];
            n_nan[c] += isnan(row[c]) ? 1U : 0U;
        }
        ++n_rows;
    }
    if (st == AENL_OK && rc < 0)
    {
        st = (aenl_status_t)rc;
    }
    r->data = data;
    r->cap = cap;
    r->n_rows = n_rows;
    free(row);
    return st;
}

aenl_status_t aenl_table_read(const char *path, aenl_table_t *out, aenl_err_t *err)
{
    if (out == NULL)
    {
        aenl_err_set(err, "aenl_table_read: NULL table");
        return AENL_E_ARG;
    }
    table_zero(out);
    aenl_csv_t *csv = NULL;
    aenl_status_t st = aenl_csv_open(&csv, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    rows_t r = {NULL, 0, 0, (size_t *)calloc(csv->n_cols, sizeof(size_t))};
    if (r.n_nan == NULL)
    {
        aenl_err_set(err, "%s: out of memory", path);
        st = AENL_E_IO;
    }
    else
    {
        /* sized ahead from the file's size and its first lines: a table grown by doubling is
         * moved once a doubling, and its new pages are faulted in each time (a tenth of reading
         * a large record); a guess too low costs a growth, one too high the shrink at the end */
        rows_reserve(&r, csv->n_cols, rows_likely(csv));
        st = read_rows(csv, &r, err);
    }
    if (st != AENL_OK)
    {
        aenl_csv_close(csv);
        rows_free(&r);
        return st;
    }
    const size_t n_cols = csv->n_cols;
    if (r.n_rows == 0)
    {
        /* no data row (a header, then only comments or blank lines): no table, as a table that
         * was never grown has none (realloc to 0 bytes would free it behind our back) */
        free(r.data);
        r.data = NULL;
        r.cap = 0;
    }
    /* Compact to stride n_rows (destinations below sources: move first to last), then shrink. */
    if (r.data != NULL && r.n_rows < r.cap)
    {
        for (size_t c = 1; c < n_cols; ++c)
        {
            memmove(r.data + c * r.n_rows, r.data + c * r.cap, r.n_rows * sizeof *r.data);
        }
        double *shrunk = (double *)realloc(r.data, n_cols * r.n_rows * sizeof *r.data);
        if (shrunk != NULL)
        {
            r.data = shrunk;
        }
    }
    out->names = csv->names; /* take the header names over from the reader */
    csv->names = NULL;
    out->n_cols = n_cols;
    out->n_rows = r.n_rows;
    out->data = r.data;
    out->n_nan = r.n_nan;
    aenl_csv_close(csv);
    return AENL_OK;
}

aenl_status_t aenl_table_alloc(aenl_table_t *t, size_t n_rows, size_t n_cols,
                               const char *const *names, aenl_err_t *err)
{
    size_t i;
    size_t n_vals;
    if (t == NULL)
    {
        aenl_err_set(err, "aenl_table_alloc: NULL table");
        return AENL_E_ARG;
    }
    table_zero(t);
    if (names == NULL || n_cols == 0)
    {
        aenl_err_set(err, "aenl_table_alloc: no column names");
        return AENL_E_ARG;
    }
    for (i = 0; i < n_cols; ++i)
    {
        if (names[i] == NULL)
        {
            aenl_err_set(err, "aenl_table_alloc: column %lu has a NULL name",
                         (unsigned long)(i + 1));
            return AENL_E_ARG;
        }
    }
    if (n_rows > SIZE_MAX / sizeof(double) / n_cols)
    {
        aenl_err_set(err, "aenl_table_alloc: %lu x %lu table too large", (unsigned long)n_rows,
                     (unsigned long)n_cols);
        return AENL_E_ARG;
    }
    n_vals = n_rows * n_cols;
    t->names = copy_names(names, n_cols);
    t->data = (double *)malloc((n_vals > 0 ? n_vals : 1U) * sizeof *t->data);
    t->n_nan = (size_t *)malloc(n_cols * sizeof *t->n_nan);
    t->n_cols = n_cols;
    if (t->names == NULL || t->data == NULL || t->n_nan == NULL)
    {
        aenl_table_free(t);
        aenl_err_set(err, "aenl_table_alloc: out of memory");
        return AENL_E_IO;
    }
    t->n_rows = n_rows;
    for (i = 0; i < n_vals; ++i)
    {
        t->data[i] = (double)NAN;
    }
    for (i = 0; i < n_cols; ++i)
    {
        t->n_nan[i] = n_rows; /* every cell starts missing */
    }
    return AENL_OK;
}

aenl_status_t aenl_table_write(const aenl_table_t *t, const char *path, aenl_err_t *err)
{
    aenl_csv_writer_t w;
    aenl_status_t st;
    double *row;
    size_t r;
    size_t c;
    if (t == NULL || t->names == NULL || t->n_cols == 0 || (t->data == NULL && t->n_rows > 0))
    {
        aenl_err_set(err, "aenl_table_write: empty or NULL table");
        return AENL_E_ARG;
    }
    row = (double *)calloc(t->n_cols, sizeof *row);
    if (row == NULL)
    {
        aenl_err_set(err, "%s: out of memory", path != NULL ? path : "(null)");
        return AENL_E_IO;
    }
    st = aenl_csv_writer_open(&w, path, (const char *const *)t->names, t->n_cols, err);
    for (r = 0; st == AENL_OK && r < t->n_rows; ++r)
    {
        for (c = 0; c < t->n_cols; ++c)
        {
            row[c] = t->data[c * t->n_rows + r];
        }
        st = aenl_csv_writer_row(&w, row, err);
    }
    if (st == AENL_OK)
    {
        st = aenl_csv_writer_commit(&w, err);
    }
    else
    {
        aenl_csv_writer_abort(&w);
    }
    free(row);
    return st;
}

/* ---- streaming writer ---------------------------------------------------------------------- */

aenl_status_t aenl_csv_writer_open(aenl_csv_writer_t *w, const char *path, const char *const *names,
                                   size_t n_cols, aenl_err_t *err)
{
    size_t c;
    size_t k;
    aenl_status_t st;
    if (w == NULL)
    {
        aenl_err_set(err, "aenl_csv_writer_open: NULL writer");
        return AENL_E_ARG;
    }
    w->out.fp = NULL;
    w->out.path = NULL;
    w->out.tmp_path = NULL;
    w->out.direct = 0;
    w->n_cols = 0;
    if (names == NULL || n_cols == 0)
    {
        aenl_err_set(err, "%s: no columns to write", path != NULL ? path : "(null)");
        return AENL_E_ARG;
    }
    /* A name the reader would reject, or read back differently, must not be written (a leading
     * UTF-8 byte order mark would be taken off the first line: found by fuzz_csv). */
    for (c = 0; c < n_cols; ++c)
    {
        const char *s = names[c];
        if (s == NULL || s[0] == '\0' || strpbrk(s, ",\r\n\"") != NULL || is_blank(s[0]) ||
            is_blank(s[strlen(s) - 1]) || s[0] == '#' || strncmp(s, "\xEF\xBB\xBF", 3) == 0)
        {
            aenl_err_set(err, "%s: column %lu: invalid column name '%s'",
                         path != NULL ? path : "(null)", (unsigned long)(c + 1),
                         s != NULL ? s : "(null)");
            return AENL_E_ARG;
        }
        for (k = 0; k < c; ++k)
        {
            if (strcmp(names[k], s) == 0)
            {
                aenl_err_set(err, "%s: column %lu: duplicate column name '%s'",
                             path != NULL ? path : "(null)", (unsigned long)(c + 1), s);
                return AENL_E_ARG;
            }
        }
    }
    st = aenl_outfile_open(&w->out, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    for (c = 0; c < n_cols; ++c)
    {
        if (fputs(names[c], w->out.fp) < 0 || fputc(c + 1 < n_cols ? ',' : '\n', w->out.fp) < 0)
        {
            aenl_err_set(err, "%s: write error (%s)", path, strerror(errno));
            aenl_outfile_abort(&w->out);
            return AENL_E_IO;
        }
    }
    w->n_cols = n_cols;
    return AENL_OK;
}

aenl_status_t aenl_csv_writer_row(aenl_csv_writer_t *w, const double *values, aenl_err_t *err)
{
    size_t c;
    if (w == NULL || w->out.fp == NULL || values == NULL)
    {
        aenl_err_set(err, "aenl_csv_writer_row: writer not open or NULL values");
        return AENL_E_ARG;
    }
    for (c = 0; c < w->n_cols; ++c)
    {
        int n;
        char sep = (c + 1 < w->n_cols) ? ',' : '\n';
        if (isnan(values[c]))
        {
            n = fprintf(w->out.fp, "nan%c", sep);
        }
        else if (isinf(values[c]))
        {
            aenl_err_set(err, "%s: column %lu: infinite value cannot be written", w->out.path,
                         (unsigned long)(c + 1));
            aenl_outfile_abort(&w->out); /* documented: a failed row drops the file */
            return AENL_E_NUMERIC;
        }
        else
        {
            n = fprintf(w->out.fp, "%.17g%c", values[c], sep);
        }
        if (n < 0)
        {
            aenl_err_set(err, "%s: write error (%s)", w->out.path, strerror(errno));
            aenl_outfile_abort(&w->out);
            return AENL_E_IO;
        }
    }
    return AENL_OK;
}

aenl_status_t aenl_csv_writer_commit(aenl_csv_writer_t *w, aenl_err_t *err)
{
    if (w == NULL)
    {
        aenl_err_set(err, "aenl_csv_writer_commit: NULL writer");
        return AENL_E_ARG;
    }
    return aenl_outfile_commit(&w->out, err);
}

void aenl_csv_writer_abort(aenl_csv_writer_t *w)
{
    if (w != NULL)
    {
        aenl_outfile_abort(&w->out);
    }
}

/* 1 when the first n characters of a equal b, ignoring ASCII case. */
static int equal_nocase(const char *a, const char *b, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        const int ca = (a[i] >= 'A' && a[i] <= 'Z') ? a[i] - 'A' + 'a' : a[i];
        if (ca != b[i])
        {
            return 0;
        }
    }
    return 1;
}

/* 1 when the n characters at s name a unit of time (any case). */
static int is_unit(const char *s, size_t n)
{
    static const char *const k_units[] = {"s",       "sec", "secs", "second",
                                          "seconds", "ms",  "us",   "ns"};
    for (size_t i = 0; i < sizeof(k_units) / sizeof(k_units[0]); ++i)
    {
        if (strlen(k_units[i]) == n && equal_nocase(s, k_units[i], n))
        {
            return 1;
        }
    }
    return 0;
}

int aenl_csv_is_time_column(const char *name, const char *time_column)
{
    return time_column != NULL ? strcmp(name, time_column) == 0 : aenl_csv_is_time_name(name);
}

int aenl_csv_is_time_name(const char *name)
{
    static const char *const k_time[] = {"timestamp", "time", "tau", "t"};
    const size_t len = strlen(name);
    for (size_t i = 0; i < sizeof(k_time) / sizeof(k_time[0]); ++i)
    {
        const size_t nb = strlen(k_time[i]);
        if (len < nb || !equal_nocase(name, k_time[i], nb))
        {
            continue;
        }
        const char *rest = name + nb;
        size_t nr = len - nb;
        if (nr == 0)
        {
            return 1;
        }
        if (rest[0] == '_')
        {
            return is_unit(rest + 1, nr - 1u);
        }
        if (rest[0] == ' ')
        {
            rest++;
            nr--;
        }
        if (nr >= 3 &&
            ((rest[0] == '[' && rest[nr - 1u] == ']') || (rest[0] == '(' && rest[nr - 1u] == ')')))
        {
            return is_unit(rest + 1, nr - 2u);
        }
        return 0;
    }
    return 0;
}

/* Whether v is a whole number to the printed-resolution test's tolerance. */
static int near_whole(double v)
{
    return fabs(v - nearbyint(v)) <= 1e-9 * fmax(1.0, fabs(v));
}

/* 10^k by repeated multiplication (exact for k <= 22), as the resolution test scales: from a
 * table up to 22 (the test runs on every time value of a record), multiplied on beyond. */
static double pow10_exact(int k)
{
    static const double p10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                   1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                   1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    if (k <= 0)
    {
        return 1.0;
    }
    double p = p10[k < 22 ? k : 22];
    for (int i = 22; i < k; ++i)
    {
        p *= 10.0;
    }
    return p;
}

/* The decimals a time value was written with: the fewest k (0..17) whose 10^-k reproduces it
 * (12.3457 -> 4), -1 for 0 (exact at any resolution) or when none does. A value that happens to
 * be round (12.3 in a record printed to 1e-4) reads coarser than it was written. */
static int printed_decimals(double t)
{
    if (!(fabs(t) > 0.0))
    {
        return -1;
    }
    double p = 1.0;
    for (int k = 0; k <= 17; ++k)
    {
        if (near_whole(t * p))
        {
            return k;
        }
        p *= 10.0;
    }
    return -1;
}

/* How far the printed t may be from the time it stands for. The column is written either with
 * a fixed number of decimals (its finest resolution seen, s->q_dec) or with a fixed number of
 * significant digits (the most seen, s->digits, which gives a resolution growing with |t|, as
 * %g does); the larger of the two bounds holds under either. */
static double rounding_of(const aenl_time_steps_t *s, double t)
{
    if (!(fabs(t) > 0.0))
    {
        return 0.0;
    }
    const double sig = pow(10.0, floor(log10(fabs(t))) - (double)s->digits + 1.0);
    return fmax(s->q_dec, sig);
}

/* floor(log10(a)) for a > 0. A time column stays in one decade for most of its rows, and a
 * logarithm of every value is a tenth of reading a long record: a value well inside the last
 * value's decade takes its exponent. Within 1e-12 of a decade's ends, where log10's rounding
 * decides the floor, it is computed, so the result is always floor(log10(a)). */
static int decade_of(aenl_time_steps_t *s, double a)
{
    if (a > s->dec_lo && a < s->dec_hi)
    {
        return s->dec_e;
    }
    const int e = (int)floor(log10(a));
    s->dec_e = e;
    s->dec_lo = pow(10.0, (double)e) * (1.0 + 1e-12);
    s->dec_hi = pow(10.0, (double)e + 1.0) * (1.0 - 1e-12);
    return e;
}

/* The finest resolution and the most significant digits, with t seen. A value whole at the
 * fewer of the finest decimals seen and the decimals that the most digits give at its
 * magnitude changes neither (a value whole at k decimals is whole at more, beyond 1e-9 of
 * zero): one test instead of the search for its own decimals, which runs only when it
 * fails. */
static void note_resolution(aenl_time_steps_t *s, double t)
{
    const double a = fabs(t);
    if (!(a > 0.0))
    {
        return; /* zero is exact at any resolution */
    }
    const int e = decade_of(s, a);
    if (a > 1e-9 && s->q_dec > 0.0)
    {
        const int k_dig = s->digits - 1 - e;
        const int k = k_dig < s->k_dec ? k_dig : s->k_dec;
        if (k >= 0 && near_whole(t * pow10_exact(k)))
        {
            return;
        }
    }
    const int k = printed_decimals(t);
    if (k >= 0)
    {
        const double q = 1.0 / pow10_exact(k);
        if (!(s->q_dec > 0.0) || q < s->q_dec)
        {
            s->q_dec = q;
            s->k_dec = k;
        }
        const int d = e + k + 1; /* significant digits: k decimals below 10^e */
        s->digits = d > s->digits ? d : s->digits;
    }
}

int aenl_time_steps_take(aenl_time_steps_t *s, double t, double *step, double *ref)
{
    int ok = 1;
    note_resolution(s, t);
    if (s->k == 0)
    {
        s->t0 = t;
    }
    else if (s->k >= 2)
    {
        *step = t - s->t_prev;
        *ref = (s->t_prev - s->t0) / (double)(s->k - 1u);
        const double off = fabs(*step - *ref);
        /* the rounding's bound only when the step is off by more than the tolerance */
        ok =
            *step <= AENL_TIME_GAP * *ref && (off <= AENL_TIME_STEP_TOL * *ref ||
                                              off <= rounding_of(s, t) + rounding_of(s, s->t_prev));
    }
    s->t_prev = t;
    s->k++;
    return ok;
}
