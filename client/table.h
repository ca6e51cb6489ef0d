/* Plain-text tables for humans: columns sized to their widest cell, numbers right-aligned. */
#ifndef AALAB_TABLE_H
#define AALAB_TABLE_H

#include <stddef.h>
#include <stdio.h>

typedef struct table table;

table *table_new(size_t columns, const char *const *headers);
/* Copies the cells; a NULL cell prints as "-". Returns 0 or -1 (out of memory). */
int table_add_row(table *t, const char *const *cells);
size_t table_rows(const table *t);
void table_print(const table *t, FILE *out);
void table_free(table *t);

/* Two-column "key  value" listing, for single objects (health, one job). */
void print_key_values(FILE *out, const char *const *keys, const char *const *values, size_t n);

#endif
