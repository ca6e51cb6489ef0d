/* Plain-text tables for humans: columns sized to their widest cell, numbers right-aligned. */
#ifndef AALAB_TABLE_H
#define AALAB_TABLE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct table table;

table *table_new(size_t columns, const char *const *headers);
/* Copies the cells; a NULL cell prints as "-". Returns 0 or -1 (out of memory). */
int table_add_row(table *t, const char *const *cells);
size_t table_rows(const table *t);
void table_print(const table *t, FILE *out);
/* RFC 4180 CSV: the header row, then one record per row, CRLF line ends; a field holding a
 * comma, a quote, CR or LF is quoted with its quotes doubled. "-" cells (no value) are empty. */
void table_print_csv(const table *t, FILE *out);
/* table_print_csv when csv, else table_print. */
void table_write(const table *t, FILE *out, bool csv);
void table_free(table *t);

/* Two-column "key  value" listing, for single objects (health, one job). */
void print_key_values(FILE *out, const char *const *keys, const char *const *values, size_t n);
/* The same listing as a two-column CSV ("key,value" header). */
void print_key_values_csv(FILE *out, const char *const *keys, const char *const *values, size_t n);
/* One CSV field, quoted when it must be. */
void csv_field(FILE *out, const char *s);

#endif
