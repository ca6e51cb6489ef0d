#include "view_rows.h"

#include "../cli.h"

table *view_rows_new(const view_column *cols, size_t n)
{
    const char *headers[VIEW_ROWS_MAX_COLUMNS];
    if (n > VIEW_ROWS_MAX_COLUMNS)
        return NULL;
    for (size_t c = 0; c < n; c++)
        headers[c] = cols[c].header;
    return table_new(n, headers);
}

void view_rows_cells(const char **cells, char (*bufs)[32], const json_t *row,
                     const view_column *cols, size_t n, bool csv)
{
    for (size_t c = 0; c < n; c++) {
        const json_t *v = json_object_get(row, cols[c].member);
        if (cols[c].cell == VIEW_STRING)
            cells[c] = fmt_string(v);
        else
            cells[c] = fmt_number(bufs[c], sizeof bufs[c], v,
                                  cols[c].cell == VIEW_MEASURE ? fmt_decimals(csv, cols[c].decimals)
                                                               : cols[c].decimals);
    }
}

void view_rows_write(FILE *out, const json_t *rows, const view_column *cols, size_t n, bool csv)
{
    table *t = view_rows_new(cols, n);
    if (!t)
        return;
    size_t i;
    json_t *row;
    json_array_foreach(rows, i, row)
    {
        const char *cells[VIEW_ROWS_MAX_COLUMNS];
        char bufs[VIEW_ROWS_MAX_COLUMNS][32];
        view_rows_cells(cells, bufs, row, cols, n, csv);
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}
