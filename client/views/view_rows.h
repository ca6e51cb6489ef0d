/* A table read from an array of JSON objects: a row per object, a column per member. */
#ifndef AALAB_VIEW_ROWS_H
#define AALAB_VIEW_ROWS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <jansson.h>

#include "../table.h"

#define VIEW_ROWS_MAX_COLUMNS 12

/* How a column's cells are written. */
typedef enum view_cell {
    VIEW_STRING,  /* the member's string ("-" when it is none) */
    VIEW_FIXED,   /* a number with `decimals` places, in text and CSV alike */
    VIEW_MEASURE, /* a number with `decimals` places in text, every digit in CSV */
} view_cell;

typedef struct view_column {
    const char *header;
    const char *member;
    view_cell cell;
    int decimals;
} view_column;

/* A table with the columns' headers (NULL when out of memory). */
table *view_rows_new(const view_column *cols, size_t n);
/* The cells of one row object into cells[0..n), formatted in bufs. */
void view_rows_cells(const char **cells, char (*bufs)[32], const json_t *row,
                     const view_column *cols, size_t n, bool csv);
/* A row per object of rows, written as text or CSV. */
void view_rows_write(FILE *out, const json_t *rows, const view_column *cols, size_t n, bool csv);

#endif
