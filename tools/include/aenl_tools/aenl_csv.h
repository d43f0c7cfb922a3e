/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_csv.h
 * @brief Host-only CSV reading (streaming and whole-table) and writing.
 *
 * Format: a header row naming the columns, comma separators, optional CRLF line ends, C locale
 * numbers. A cell may be empty, "nan" or "NaN" (a missing sample: read as NaN and counted).
 * Any other non-numeric cell, a ragged row, an "inf" cell, a duplicated or empty column name is an
 * error whose message names file:line:column. Lines that are empty or start with '#' are skipped.
 * Writers use "%.17g" so doubles round-trip, and go through aenl_outfile_t (no partial files).
 */
#ifndef AENL_TOOLS_CSV_H
#define AENL_TOOLS_CSV_H

#include <stddef.h>

#include "aenl_tools/aenl_io.h"

/* ---- streaming reader: memory does not grow with the file's length ------------------------ */

typedef struct aenl_csv aenl_csv_t; /**< opaque reader */

/** Open `path` ("-" is stdin) and read its header row. */
aenl_status_t aenl_csv_open(aenl_csv_t **out, const char *path, aenl_err_t *err);
size_t aenl_csv_n_cols(const aenl_csv_t *csv);
const char *aenl_csv_col_name(const aenl_csv_t *csv, size_t col);
/** Column index of `name`, or -1 when absent. */
long aenl_csv_find(const aenl_csv_t *csv, const char *name);
/**
 * @brief Read the next data row into row[0 .. n_cols-1] (missing cells as NaN).
 * @return 1 a row was read, 0 end of file, a negative aenl_status_t on error (err: file:line:col).
 */
int aenl_csv_next(aenl_csv_t *csv, double *row, aenl_err_t *err);
/** 1-based line number of the row last read (for messages). */
unsigned long aenl_csv_line(const aenl_csv_t *csv);
/** The path as given to aenl_csv_open. */
const char *aenl_csv_path(const aenl_csv_t *csv);
void aenl_csv_close(aenl_csv_t *csv);
/**
 * 1 for the names a time column goes by: t, time, tau or timestamp, in any case, alone or with
 * a unit of time (s, sec, secs, second, seconds, ms, us, ns) after '_' or in brackets, with or
 * without a space ("t_s", "Time [s]", "time (ms)", "TIMESTAMP").
 */
int aenl_csv_is_time_name(const char *name);
/**
 * 1 when the column called name is the record's time column: the one named time_column exactly,
 * when that is given (a user's name for it, `--time COL`), else one aenl_csv_is_time_name knows.
 */
int aenl_csv_is_time_column(const char *name, const char *time_column);
/**
 * The value of s when s is a plain decimal number ([+-] digits [. [digits]] or [+-] . digits,
 * then [e|E [+-] 1 to 4 digits]; at most 400 digits) that one correctly rounded operation
 * converts: significant digits that make at most 2^53 and a power of ten within 10^+-22 (both
 * exact doubles: Clinger's fast path); or, where long double is the x87 extended type and
 * its arithmetic is carried out as such (a probe at first use: an emulator may carry it in
 * doubles), at most 19 significant digits and a power of ten within 10^+-27 (both exact in its
 * 64-bit significand), unless that result lies exactly halfway between two doubles. The value is
 * strtod's, bit for bit. Returns 1 with *v set, else 0 (*v untouched): the caller then uses
 * strtod.
 */
int aenl_parse_decimal(const char *s, double *v);

/**
 * strtod for decimal text only: a hexadecimal number ("0x10", "0x1p-3"), which strtod reads but
 * no data file or option of aenl means, is not a number (*end = s, 0 returned).
 */
double aenl_strtod_decimal(const char *s, char **end);

/** Largest relative departure of a time step from the record's step (jitter), beyond the
 *  rounding of the two printed times. */
#define AENL_TIME_STEP_TOL 0.1
/** A step longer than this many times the record's step is a gap (a missing sample at least). */
#define AENL_TIME_GAP 1.5

/** Check of uniform sampling, one time value at a time (zero it before the first). */
typedef struct aenl_time_steps
{
    double t0, t_prev;     /* first and last value seen */
    size_t k;              /* values seen */
    double q_dec;          /* finest decimal resolution seen (0: none yet) */
    int k_dec;             /* its decimals: q_dec = 10^-k_dec */
    int digits;            /* most significant digits seen */
    double dec_lo, dec_hi; /* the decade of the last value, shrunk by 1e-12 at both ends */
    int dec_e;             /* its exponent: floor(log10 |t|) inside (dec_lo, dec_hi) */
} aenl_time_steps_t;

/**
 * @brief Take the next time value t (finite, larger than the last). The record's step so far
 *        is (t_prev − t0) / (k − 1), a mean over every earlier step, so the rounding of printed
 *        times does not accumulate in it. Returns 0 for a gap (a step longer than AENL_TIME_GAP
 *        record steps) or for jitter (a step further from the record's step than
 *        AENL_TIME_STEP_TOL of it and than the rounding of the two times as printed, judged from
 *        the digits the column has shown: 12.3457 may be 1e-4 off), with the step and the reference
 * in *step and *ref; else 1. Every value before the third is accepted.
 */
int aenl_time_steps_take(aenl_time_steps_t *s, double t, double *step, double *ref);

/* ---- whole table in memory --------------------------------------------------------------- */

/** Column-major table: column c, row r is data[c * n_rows + r]. */
typedef struct aenl_table
{
    size_t n_rows, n_cols;
    char **names;  /**< n_cols names */
    double *data;  /**< n_cols * n_rows values, NaN = missing */
    size_t *n_nan; /**< per column: missing cells */
} aenl_table_t;

/** Read a whole file. On error *out is left empty (all zero) and nothing leaks. */
aenl_status_t aenl_table_read(const char *path, aenl_table_t *out, aenl_err_t *err);
/** A new table of n_rows x n_cols, values NaN, names copied. */
aenl_status_t aenl_table_alloc(aenl_table_t *t, size_t n_rows, size_t n_cols,
                               const char *const *names, aenl_err_t *err);
/** Column index of `name`, or -1 when absent. */
long aenl_table_find(const aenl_table_t *t, const char *name);
/** Pointer to column c (n_rows values). */
double *aenl_table_col(const aenl_table_t *t, size_t c);
/** Free and zero. Safe on a zeroed table. */
void aenl_table_free(aenl_table_t *t);

/** Write a table (header + rows, "%.17g", missing as "nan") to `path` atomically. */
aenl_status_t aenl_table_write(const aenl_table_t *t, const char *path, aenl_err_t *err);

/* ---- streaming writer -------------------------------------------------------------------- */

typedef struct aenl_csv_writer
{
    aenl_outfile_t out;
    size_t n_cols;
} aenl_csv_writer_t;

/** Open `path` (atomically, see aenl_outfile_t) and write the header row. */
aenl_status_t aenl_csv_writer_open(aenl_csv_writer_t *w, const char *path, const char *const *names,
                                   size_t n_cols, aenl_err_t *err);
/** Append one row of n_cols values. */
aenl_status_t aenl_csv_writer_row(aenl_csv_writer_t *w, const double *values, aenl_err_t *err);
/** Finish: the file appears under its final name only now. */
aenl_status_t aenl_csv_writer_commit(aenl_csv_writer_t *w, aenl_err_t *err);
/** Drop everything written; no file is left. */
void aenl_csv_writer_abort(aenl_csv_writer_t *w);

#endif /* AENL_TOOLS_CSV_H */
