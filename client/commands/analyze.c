/* aalab analyze NAME|FILE.json|POINTS [--metrics LIST] [--radius R] [--pcf-bins N]
 *               [--set N|all] */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "../table.h"
#include "../views/view_kv.h"

int analyze_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *pattern, *extras;
    *req = NULL;
    if (pattern_argument_load(a->target, a, &pattern, &extras, err, errcap))
        return -1;
    json_decref(extras); /* a saved evaluate request's other members do not apply */
    json_t *r = json_object();
    json_object_set_new(r, "pattern", pattern);
    if (a->metrics) {
        json_t *list = json_array();
        for (const char *p = a->metrics; *p;) {
            size_t len = strcspn(p, ",");
            if (!len) {
                snprintf(err, errcap,
                         "--metrics wants names separated by commas, e.g. "
                         "discrepancy,spacing");
                json_decref(list);
                json_decref(r);
                return -1;
            }
            json_array_append_new(list, json_stringn(p, len));
            p += len + (p[len] == ',');
        }
        json_object_set_new(r, "metrics", list);
    }
    if (a->radius)
        json_object_set_new(r, "spectrum", json_pack("{s:I}", "radius", (json_int_t)a->radius));
    if (a->pcf_bins)
        json_object_set_new(r, "pcf", json_pack("{s:I}", "bins", (json_int_t)a->pcf_bins));
    *req = r;
    return 0;
}

/* "0.208333 (square 0.0434028)" for a discrepancy; nothing when absent. */
static void add_root_square(view_kv *kv, const char *key, const json_t *d, const char *name)
{
    char sq[64];
    snprintf(sq, sizeof sq, "%s_squared", name);
    const json_t *r = json_object_get(d, name), *s = json_object_get(d, sq);
    if (json_is_number(r) && json_is_number(s))
        view_kv_add(kv, key, "%.6g (square %.6g)", json_number_value(r), json_number_value(s));
}

static void print_radial(FILE *out, const json_t *spectrum, bool csv)
{
    const json_t *radial = json_object_get(spectrum, "radial"),
                 *ani = json_object_get(spectrum, "anisotropy_db"),
                 *count = json_object_get(spectrum, "annulus_count");
    const char *headers[] = {"annulus", "frequencies", "power", "anisotropy_db"};
    table *t = table_new(4, headers);
    if (!t)
        return;
    for (size_t b = 0; b < json_array_size(radial); b++) {
        char c[4][32];
        snprintf(c[0], sizeof c[0], "%zu", b);
        snprintf(c[1], sizeof c[1], "%lld",
                 (long long)json_integer_value(json_array_get(count, b)));
        const json_t *p = json_array_get(radial, b), *a = json_array_get(ani, b);
        snprintf(c[2], sizeof c[2], json_is_number(p) ? "%.4f" : "-", json_number_value(p));
        snprintf(c[3], sizeof c[3], json_is_number(a) ? "%.2f" : "-", json_number_value(a));
        const char *cells[4] = {c[0], c[1], c[2], c[3]};
        table_add_row(t, cells);
    }
    if (csv) {
        table_print_csv(t, out);
    } else {
        fprintf(out, "\nradial spectrum (mean power per annulus |k| ~ annulus)\n");
        table_print(t, out);
    }
    table_free(t);
}

void analyze_print(FILE *out, const json_t *resp, bool csv)
{
    const json_t *spectrum = json_object_get(resp, "spectrum");
    if (csv) {
        if (spectrum)
            print_radial(out, spectrum, true);
        return;
    }
    view_kv kv = {0};
    view_kv_add(&kv, "points", "%lld",
                (long long)json_integer_value(json_object_get(resp, "points")));
    view_kv_add(&kv, "tile", "%lld", (long long)json_integer_value(json_object_get(resp, "tile")));
    const char *family = json_string_value(json_object_get(resp, "family"));
    view_kv_add(&kv, "family", "%s", family ? family : "-");
    const json_t *sets = json_object_get(resp, "sets");
    if (sets) /* --set all: the figures below are the means (--json for each set's) */
        view_kv_add(&kv, "sets", "means over %lld sets (the spectrum of the mean periodogram)",
                    (long long)json_integer_value(json_object_get(sets, "count")));
    const json_t *d = json_object_get(resp, "discrepancy");
    add_root_square(&kv, "CD", d, "centered");
    add_root_square(&kv, "WD", d, "wrap_around");
    add_root_square(&kv, "MD", d, "mixture");
    add_root_square(&kv, "L2-star", d, "l2_star");
    if (json_is_number(json_object_get(d, "star_linf")))
        view_kv_number(&kv, "Linf-star", json_object_get(d, "star_linf"), 6);
    const json_t *sp = json_object_get(resp, "spacing");
    if (sp) {
        view_kv_add(&kv, "min distance", "%.6g (%.3f of d_hex)",
                    json_number_value(json_object_get(sp, "min_distance")),
                    json_number_value(json_object_get(sp, "min_distance_normalized")));
        view_kv_add(&kv, "mean nn distance", "%.6g (%.3f of d_hex)",
                    json_number_value(json_object_get(sp, "mean_nn_distance")),
                    json_number_value(json_object_get(sp, "mean_nn_distance_normalized")));
        view_kv_add(&kv, "d_hex", "%.6g",
                    json_number_value(json_object_get(sp, "packing_distance")));
    }
    if (spectrum) {
        view_kv_add(&kv, "effective Nyquist", "%g (%.3f sqrt(n))",
                    json_number_value(json_object_get(spectrum, "effective_nyquist")),
                    json_number_value(json_object_get(spectrum, "effective_nyquist_normalized")));
        view_kv_number(&kv, "oscillation", json_object_get(spectrum, "oscillation"), 3);
    }
    const json_t *pcf = json_object_get(resp, "pcf");
    if (pcf)
        view_kv_add(&kv, "pcf", "%zu bins to r = %.4g, sigma %.4g (--json for the values)",
                    json_array_size(json_object_get(pcf, "g")),
                    json_number_value(json_object_get(pcf, "r_max")),
                    json_number_value(json_object_get(pcf, "sigma")));
    view_kv_print(out, &kv);
    if (spectrum)
        print_radial(out, spectrum, false);
}

int cmd_analyze(cli_session *s)
{
    json_t *req, *resp;
    char err[512];
    if (analyze_request(s->args, &req, err, sizeof err)) {
        fprintf(s->err, "aalab analyze: %s\n", err);
        return EXIT_USAGE;
    }
    int code = cli_call(s, "POST", "/v1/analyze", req, &resp);
    json_decref(req);
    if (code != EXIT_OK)
        return code;
    if (s->args->json)
        cli_print_json(s->out, resp);
    else
        analyze_print(s->out, resp, s->args->csv);
    json_decref(resp);
    return EXIT_OK;
}
