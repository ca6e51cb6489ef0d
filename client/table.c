#define _POSIX_C_SOURCE 200809L
#include "table.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

struct table {
    size_t columns, rows, cap;
    char **cells; /* rows * columns, headers are row 0 */
};

static char *dup_cell(const char *s)
{
    return strdup(s ? s : "-");
}

table *table_new(size_t columns, const char *const *headers)
{
    table *t = calloc(1, sizeof *t);
    if (!t || columns == 0) {
        free(t);
        return NULL;
    }
    t->columns = columns;
    if (table_add_row(t, headers)) {
        table_free(t);
        return NULL;
    }
    t->rows = 0; /* the header row does not count */
    return t;
}

int table_add_row(table *t, const char *const *cells)
{
    size_t used = t->cells ? (t->rows + 1) : 0; /* rows stored, header included */
    if (used + 1 > t->cap) {
        size_t cap = t->cap ? t->cap * 2 : 8;
        char **p = realloc(t->cells, cap * t->columns * sizeof *p);
        if (!p)
            return -1;
        t->cells = p;
        t->cap = cap;
    }
    char **row = t->cells + used * t->columns;
    for (size_t c = 0; c < t->columns; c++) {
        row[c] = dup_cell(cells[c]);
        if (!row[c]) {
            while (c--)
                free(row[c]);
            return -1;
        }
    }
    if (used > 0)
        t->rows++;
    return 0;
}

size_t table_rows(const table *t)
{
    return t->rows;
}

/* A cell that reads as a number (or "-") is right-aligned so digits line up. */
static bool looks_numeric(const char *s)
{
    if (strcmp(s, "-") == 0)
        return true;
    char *end;
    strtod(s, &end);
    return end != s && (*end == '\0' || strcmp(end, "%") == 0 || strcmp(end, "s") == 0);
}

void table_print(const table *t, FILE *out)
{
    size_t *width = calloc(t->columns, sizeof *width);
    bool *right = calloc(t->columns, sizeof *right);
    if (!width || !right) {
        free(width);
        free(right);
        return;
    }
    for (size_t c = 0; c < t->columns; c++) {
        right[c] = t->rows > 0;
        for (size_t r = 0; r <= t->rows; r++) {
            const char *cell = t->cells[r * t->columns + c];
            size_t w = strlen(cell);
            if (w > width[c])
                width[c] = w;
            if (r > 0 && !looks_numeric(cell))
                right[c] = false;
        }
    }
    for (size_t r = 0; r <= t->rows; r++) {
        /* Stop after the last non-empty cell: no trailing blanks. */
        size_t end = t->columns;
        while (end > 1 && t->cells[r * t->columns + end - 1][0] == '\0')
            end--;
        for (size_t c = 0; c < end; c++) {
            const char *cell = t->cells[r * t->columns + c];
            bool last = c + 1 == end;
            if (right[c])
                fprintf(out, "%*s", (int)width[c], cell);
            else if (last)
                fputs(cell, out); /* no trailing blanks */
            else
                fprintf(out, "%-*s", (int)width[c], cell);
            if (!last)
                fputs("  ", out);
        }
        fputc('\n', out);
    }
    free(width);
    free(right);
}

void table_free(table *t)
{
    if (!t)
        return;
    size_t stored = t->cells ? (t->rows + 1) * t->columns : 0;
    for (size_t i = 0; i < stored; i++)
        free(t->cells[i]);
    free(t->cells);
    free(t);
}

void print_key_values(FILE *out, const char *const *keys, const char *const *values, size_t n)
{
    size_t w = 0;
    for (size_t i = 0; i < n; i++)
        if (strlen(keys[i]) > w)
            w = strlen(keys[i]);
    for (size_t i = 0; i < n; i++)
        fprintf(out, "%-*s  %s\n", (int)w, keys[i], values[i] ? values[i] : "-");
}

void csv_field(FILE *out, const char *s)
{
    if (!s)
        return;
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, out);
        return;
    }
    fputc('"', out);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', out);
        fputc(*s, out);
    }
    fputc('"', out);
}

/* "-" is how the text tables show a missing value; pandas reads an empty field as NaN. */
static const char *csv_value(const char *cell, bool header)
{
    return !header && cell && strcmp(cell, "-") == 0 ? "" : cell;
}

void table_print_csv(const table *t, FILE *out)
{
    for (size_t r = 0; r <= t->rows; r++) {
        for (size_t c = 0; c < t->columns; c++) {
            if (c)
                fputc(',', out);
            csv_field(out, csv_value(t->cells[r * t->columns + c], r == 0));
        }
        fputs("\r\n", out);
    }
}

void table_write(const table *t, FILE *out, bool csv)
{
    if (csv)
        table_print_csv(t, out);
    else
        table_print(t, out);
}

void print_key_values_csv(FILE *out, const char *const *keys, const char *const *values, size_t n)
{
    fputs("key,value\r\n", out);
    for (size_t i = 0; i < n; i++) {
        csv_field(out, keys[i]);
        fputc(',', out);
        csv_field(out, csv_value(values[i], false));
        fputs("\r\n", out);
    }
}
