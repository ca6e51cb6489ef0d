/* aalab filters | aalab acuity | aalab enumerate --family 'P(4,1+,n)' --cost 1.25 */
#include "commands.h"

#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../table.h"
#include "view_util.h"

void filters_print(FILE *out, const json_t *resp, bool csv)
{
    const char *headers[] = {"name", "radius", "B", "C", "default"};
    table *t = table_new(5, headers);
    if (!t)
        return;
    size_t i;
    json_t *f;
    json_array_foreach(list_member(resp, "filters"), i, f)
    {
        char radius[32], b[32], c[32];
        const char *cells[] = {fmt_string(json_object_get(f, "name")),
                               fmt_number(radius, sizeof radius, json_object_get(f, "radius"), 2),
                               fmt_number(b, sizeof b, json_object_get(f, "B"), 4),
                               fmt_number(c, sizeof c, json_object_get(f, "C"), 4),
                               json_is_true(json_object_get(f, "default")) ? "yes" : ""};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}

void acuity_print(FILE *out, const json_t *resp, bool csv)
{
    const char *headers[] = {"name", "version", "default", "knots (deg:W)"};
    table *t = table_new(4, headers);
    if (!t)
        return;
    size_t i;
    json_t *a;
    json_array_foreach(list_member(resp, "tables"), i, a)
    {
        char knots[512] = "";
        size_t used = 0, k;
        json_t *knot;
        json_array_foreach(json_object_get(a, "knots"), k, knot)
        {
            int n = snprintf(knots + used, sizeof knots - used, "%s%g:%g", k ? " " : "",
                             json_number_value(json_array_get(knot, 0)),
                             json_number_value(json_array_get(knot, 1)));
            if (n < 0 || (size_t)n >= sizeof knots - used)
                break;
            used += (size_t)n;
        }
        char version[32];
        const char *cells[] = {
            fmt_string(json_object_get(a, "name")),
            fmt_number(version, sizeof version, json_object_get(a, "version"), 0),
            json_is_true(json_object_get(a, "default")) ? "yes" : "", knots};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
    /* What each table is, one sentence each (text only: CSV stays one table). */
    json_array_foreach(list_member(resp, "tables"), i, a)
    {
        const char *d = json_string_value(json_object_get(a, "description"));
        if (!csv && d)
            fprintf(out, "%s%s: %s\n", i ? "" : "\n", fmt_string(json_object_get(a, "name")), d);
    }
}

/* Four per-side counts as "0 0 0 1". */
static const char *side_counts(char *buf, size_t cap, const json_t *a)
{
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < json_array_size(a); i++) {
        int n = snprintf(buf + used, cap - used, "%s%lld", i ? " " : "",
                         (long long)json_integer_value(json_array_get(a, i)));
        if (n < 0 || (size_t)n >= cap - used)
            break;
        used += (size_t)n;
    }
    return buf;
}

static void enumerate_csv(FILE *out, const json_t *resp)
{
    const char *headers[] = {"index", "corners", "edges", "interior", "samples", "label"};
    table *t = table_new(6, headers);
    if (!t)
        return;
    size_t i;
    json_t *c;
    json_array_foreach(json_object_get(resp, "configurations"), i, c)
    {
        char index[32], corners[64], edges[64], interior[32], samples[32];
        snprintf(index, sizeof index, "%zu", i + 1);
        const char *cells[] = {
            index,
            side_counts(corners, sizeof corners, json_object_get(c, "corners")),
            side_counts(edges, sizeof edges, json_object_get(c, "edges")),
            fmt_number(interior, sizeof interior, json_object_get(c, "interior"), 0),
            fmt_number(samples, sizeof samples, json_object_get(c, "samples"), 0),
            fmt_string(json_object_get(c, "label"))};
        table_add_row(t, cells);
    }
    table_print_csv(t, out);
    table_free(t);
}

void enumerate_print(FILE *out, const json_t *resp, bool csv)
{
    if (csv) {
        enumerate_csv(out, resp);
        return;
    }
    char count[32];
    fprintf(out, "count  %s\n", fmt_number(count, sizeof count, json_object_get(resp, "count"), 0));
    size_t i;
    json_t *c;
    json_array_foreach(json_object_get(resp, "configurations"), i, c)
    {
        char *line = json_dumps(c, JSON_COMPACT | JSON_PRESERVE_ORDER);
        if (line)
            fprintf(out, "%4zu  %s\n", i + 1, line);
        free(line);
    }
}

int cmd_filters(cli_session *s)
{
    return cli_show(s, "GET", "/v1/filters", NULL, filters_print);
}

int cmd_acuity(cli_session *s)
{
    return cli_show(s, "GET", "/v1/acuity", NULL, acuity_print);
}

int cmd_enumerate(cli_session *s)
{
    json_t *req = json_pack("{s:s}", "family", s->args->family);
    if (s->args->has_cost)
        json_object_set_new(req, "cost", json_real(s->args->cost));
    int code = cli_show(s, "POST", "/v1/families/enumerate", req, enumerate_print);
    json_decref(req);
    return code;
}
