/* aalab eval NAME|FILE.json [--filter ...] [--acuity ...] [--angles ...] [--detail]; a temporal
 * pattern (--temporal, or a file holding one) goes to eval_temporal.c */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "../table.h"
#include "../views/view_kv.h"
#include "../views/view_rows.h"
#include "eval_temporal.h"

static json_t *parse_json_argument(const char *what, const char *text, char *err, size_t cap)
{
    json_error_t jerr;
    json_t *v = json_loads(text, JSON_REJECT_DUPLICATES, &jerr);
    if (!v)
        snprintf(err, cap, "%s: invalid JSON (%s)", what, jerr.text);
    else if (!json_is_object(v)) {
        snprintf(err, cap, "%s: expected a JSON object", what);
        json_decref(v);
        v = NULL;
    }
    return v;
}

int filter_argument(const char *arg, json_t **filter, char *err, size_t errcap)
{
    *filter = NULL;
    if (arg[0] == '{') {
        *filter = parse_json_argument("--filter", arg, err, errcap);
        return *filter ? 0 : -1;
    }
    const char *colon = strchr(arg, ':');
    size_t name_len = colon ? (size_t)(colon - arg) : strlen(arg);
    if (name_len == 0) {
        snprintf(err, errcap, "--filter needs a name, e.g. mitchell or mitchell:B=0.3,C=0.3");
        return -1;
    }
    json_t *f = json_object();
    json_object_set_new(f, "name", json_stringn(arg, name_len));
    /* NAME:KEY=NUMBER,KEY=NUMBER */
    for (const char *p = colon ? colon + 1 : NULL; p && *p;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        char item[64];
        if (len >= sizeof item) {
            snprintf(err, errcap, "--filter parameter too long: '%.*s'", (int)len, p);
            json_decref(f);
            return -1;
        }
        memcpy(item, p, len);
        item[len] = '\0';
        char *eq = strchr(item, '=');
        double v;
        if (!eq || eq == item || parse_double(eq + 1, -1e300, 1e300, &v)) {
            snprintf(err, errcap, "--filter parameter '%s' is not KEY=NUMBER", item);
            json_decref(f);
            return -1;
        }
        *eq = '\0';
        json_object_set_new(f, item, json_real(v));
        p = comma ? comma + 1 : NULL;
    }
    *filter = f;
    return 0;
}

int acuity_argument(const char *arg, json_t **acuity, char *err, size_t errcap)
{
    *acuity = NULL;
    if (arg[0] == '{') {
        *acuity = parse_json_argument("--acuity", arg, err, errcap);
        return *acuity ? 0 : -1;
    }
    if (pattern_argument_is_file(arg)) {
        json_error_t jerr;
        json_t *v = json_load_file(arg, JSON_REJECT_DUPLICATES, &jerr);
        if (!v || !json_is_object(v)) {
            snprintf(err, errcap, "--acuity %s: %s", arg, v ? "expected a JSON object" : jerr.text);
            json_decref(v);
            return -1;
        }
        *acuity = v;
        return 0;
    }
    *acuity = json_pack("{s:s}", "name", arg);
    return 0;
}

int angles_argument(const char *arg, json_t **angles, char *err, size_t errcap)
{
    json_t *list = json_array();
    const char *p = arg;
    while (1) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        char item[40];
        double v;
        if (len == 0 || len >= sizeof item) {
            snprintf(err, errcap, "--angles wants degrees separated by commas, e.g. 0,15,30");
            json_decref(list);
            return -1;
        }
        memcpy(item, p, len);
        item[len] = '\0';
        if (parse_double(item, -1e6, 1e6, &v)) {
            snprintf(err, errcap, "--angles: '%s' is not a number", item);
            json_decref(list);
            return -1;
        }
        json_array_append_new(list, json_real(v));
        if (!comma)
            break;
        p = comma + 1;
    }
    *angles = list;
    return 0;
}

int eval_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *pattern, *extras;
    *req = NULL;
    if (eval_is_temporal(a)) /* docs/temporal.md: eval_temporal.c */
        return eval_temporal_request(a, req, err, errcap);
    if (a->has_alpha || a->blend_text || a->cut_frames || a->resolve || a->frame_pattern) {
        snprintf(err, errcap,
                 "--alpha, --blend, --cut-frames, --resolve and --frame-pattern "
                 "apply to a temporal pattern (--temporal)");
        return -1;
    }
    if (pattern_argument_load(a->target, a, &pattern, &extras, err, errcap))
        return -1;
    json_t *r = extras ? extras : json_object();
    json_object_set_new(r, "pattern", pattern);
    json_t *v;
    if (a->filter) {
        if (filter_argument(a->filter, &v, err, errcap))
            goto fail;
        json_object_set_new(r, "filter", v);
    }
    if (a->acuity) {
        if (acuity_argument(a->acuity, &v, err, errcap))
            goto fail;
        json_object_set_new(r, "acuity", v);
    }
    if (a->angles) {
        if (angles_argument(a->angles, &v, err, errcap))
            goto fail;
        json_object_set_new(r, "angles", v);
    }
    if (a->detail)
        json_object_set_new(r, "detail", json_true());
    *req = r;
    return 0;
fail:
    json_decref(r);
    return -1;
}

/* The kernel number of a detail block: its "kernel", else its position. */
static const char *detail_kernel(char *buf, size_t cap, size_t index, const json_t *block)
{
    json_t *k = json_object_get(block, "kernel");
    if (json_is_integer(k))
        return fmt_number(buf, cap, k, 0);
    snprintf(buf, cap, "%zu", index);
    return buf;
}

/* One row of the detail: an angle of a kernel; the same places in text and CSV. */
static const view_column detail_cols[] = {
    {"angle_deg", "angle_deg", VIEW_FIXED, 1},
    {"weight", "weight", VIEW_FIXED, 4},
    {"e1", "e1", VIEW_FIXED, 6},
    {"weighted", "weighted", VIEW_FIXED, 6},
};
enum { DETAIL_COLS = sizeof detail_cols / sizeof detail_cols[0] };

/* The detail as one CSV table, a row per kernel and angle. */
static void print_detail_csv(FILE *out, const json_t *blocks)
{
    view_column cols[1 + DETAIL_COLS] = {{"kernel", NULL, VIEW_STRING, 0}};
    memcpy(cols + 1, detail_cols, sizeof detail_cols);
    table *t = view_rows_new(cols, 1 + DETAIL_COLS);
    if (!t)
        return;
    size_t b, i;
    json_t *block, *row;
    json_array_foreach(blocks, b, block)
    {
        char kbuf[32];
        detail_kernel(kbuf, sizeof kbuf, b, block);
        const json_t *angles = json_is_array(block) ? block : json_object_get(block, "angles");
        json_array_foreach(angles, i, row)
        {
            char c[DETAIL_COLS][32];
            const char *cells[1 + DETAIL_COLS] = {kbuf};
            view_rows_cells(cells + 1, c, row, detail_cols, DETAIL_COLS, true);
            table_add_row(t, cells);
        }
    }
    table_print_csv(t, out);
    table_free(t);
}

/* One per-kernel block of the detail: either {"kernel":k,"angles":[...]} or a bare array. */
static void print_detail_kernel(FILE *out, size_t index, const json_t *block)
{
    const json_t *angles = json_is_array(block) ? block : json_object_get(block, "angles");
    char kbuf[32];
    detail_kernel(kbuf, sizeof kbuf, index, block);
    fprintf(out, "\nkernel %s\n", kbuf);
    view_rows_write(out, angles, detail_cols, DETAIL_COLS, false);
}

void eval_print(FILE *out, const json_t *resp, bool detail, bool csv)
{
    if (eval_answer_is_temporal(resp)) {
        eval_temporal_print(out, resp, detail, csv);
        return;
    }
    const json_t *argmax = json_object_get(resp, "argmax");
    char e2[32], cost[32], kernel[32], angle[32], acuity[96];
    const char *keys[] = {"family",        "cost_spp",         "E2",
                          "argmax kernel", "argmax angle_deg", "acuity"};
    const char *values[] = {
        fmt_string(json_object_get(resp, "family")),
        fmt_number(cost, sizeof cost, json_object_get(resp, "cost_spp"), 4),
        fmt_number(e2, sizeof e2, json_object_get(resp, "e2"), 6),
        fmt_number(kernel, sizeof kernel, json_object_get(argmax, "kernel"), 0),
        fmt_number(angle, sizeof angle, json_object_get(argmax, "angle_deg"), 1),
        view_acuity_text(acuity, sizeof acuity, resp)};
    /* The table the E2 uses; a daemon from before it was reported has no acuity line. */
    size_t lines = values[5] ? 6 : 5;
    const json_t *blocks = json_object_get(resp, "detail");
    if (!json_is_array(blocks))
        blocks = json_object_get(resp, "kernels");
    if (csv && detail) {
        print_detail_csv(out, blocks);
        return;
    }
    if (csv) {
        print_key_values_csv(out, keys, values, lines);
        return;
    }
    print_key_values(out, keys, values, lines);
    if (!detail)
        return;
    size_t i;
    json_t *block;
    json_array_foreach(blocks, i, block) print_detail_kernel(out, i, block);
}

int cmd_eval(cli_session *s)
{
    json_t *req, *resp;
    char err[512];
    if (eval_request(s->args, &req, err, sizeof err)) {
        fprintf(s->err, "aalab eval: %s\n", err);
        return EXIT_USAGE;
    }
    int code = cli_call(s, "POST", "/v1/evaluate", req, &resp);
    json_decref(req);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else
        eval_print(s->out, resp, s->args->detail, s->args->csv);
    json_decref(resp);
    return EXIT_OK;
}
