/* aalab predict --pattern NAME|FILE[,NAME|FILE...] [--scene S] [--size WxH] [--angle DEG]
 * [--model M]: the predicted RMSE of each pattern on a scene (POST /v1/predict), no render. */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "../table.h"
#include "view_util.h"

int predict_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *patterns = json_array();
    char *list = strdup(a->pattern ? a->pattern : "");
    if (!patterns || !list) {
        json_decref(patterns);
        free(list);
        snprintf(err, errcap, "out of memory");
        return -1;
    }
    char *save = NULL;
    for (char *item = strtok_r(list, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        json_t *p;
        if (pattern_argument_load(item, a, &p, NULL, err, errcap)) {
            json_decref(patterns);
            free(list);
            return -1;
        }
        json_array_append_new(patterns, p);
    }
    free(list);
    if (json_array_size(patterns) == 0) {
        json_decref(patterns);
        snprintf(err, errcap, "--pattern wants NAME|FILE[,NAME|FILE...]");
        return -1;
    }
    json_t *r = json_object();
    json_object_set_new(r, "patterns", patterns);
    const char *scene = a->scene ? a->scene : "siemens-star";
    /* A scene by name, or an object when an angle is given (proto/codec_scene.h). */
    if (a->has_angle)
        json_object_set_new(r, "scene", json_pack("{s:s, s:f}", "name", scene, "angle", a->angle));
    else
        json_object_set_new(r, "scene", json_string(scene));
    if (a->width > 0)
        json_object_set_new(r, "size", json_pack("[ii]", a->width, a->height));
    if (a->model)
        json_object_set_new(r, "model", json_string(a->model));
    *req = r;
    return 0;
}

/* The costliest angle of a prediction: "27° 100%". */
static void top_angle(char *buf, size_t cap, const json_t *prediction)
{
    const json_t *first = json_array_get(json_object_get(prediction, "angles"), 0);
    if (!first) {
        snprintf(buf, cap, "-");
        return;
    }
    snprintf(buf, cap, "%lld° %.0f%%",
             (long long)json_integer_value(json_object_get(first, "angle")),
             100 * json_number_value(json_object_get(first, "share")));
}

void predict_print(FILE *out, const json_t *resp, bool csv)
{
    static const char *const head[] = {"pattern",        "family",       "spp",
                                       "predicted RMSE", "locked share", "costliest angle"};
    table *t = table_new(6, head);
    if (!t)
        return;
    const json_t *list = json_object_get(resp, "predictions");
    for (size_t i = 0; i < json_array_size(list); i++) {
        const json_t *p = json_array_get(list, i), *pat = json_object_get(p, "pattern");
        const char *name = json_string_value(json_object_get(pat, "name"));
        char c[6][48];
        if (name && *name)
            snprintf(c[0], sizeof c[0], "%s", name);
        else
            snprintf(c[0], sizeof c[0], "#%zu", i + 1);
        snprintf(c[1], sizeof c[1], "%s", fmt_string(json_object_get(pat, "family")));
        fmt_number(c[2], sizeof c[2], json_object_get(pat, "samples_per_pixel"), 3);
        fmt_number(c[3], sizeof c[3], json_object_get(p, "predicted_rmse"), 3);
        fmt_number(c[4], sizeof c[4], json_object_get(p, "locked_share"), 3);
        top_angle(c[5], sizeof c[5], p);
        const char *cells[6] = {c[0], c[1], c[2], c[3], c[4], c[5]};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
    if (csv)
        return;
    const json_t *scene = json_object_get(resp, "scene"), *edges = json_object_get(resp, "edges");
    char w[16], h[16], len[32], locked[32];
    fprintf(out, "scene %s %sx%s: edge length %s px (%s px pixel-locked)",
            fmt_string(json_object_get(scene, "name")),
            fmt_number(w, sizeof w, json_object_get(scene, "width"), 0),
            fmt_number(h, sizeof h, json_object_get(scene, "height"), 0),
            fmt_number(len, sizeof len, json_object_get(edges, "total_length"), 1),
            fmt_number(locked, sizeof locked, json_object_get(edges, "locked_length"), 1));
    double sub = json_number_value(json_object_get(edges, "subpixel_area_share"));
    if (sub > 0)
        fprintf(out, "; %.1f%% of the image is below the pixel scale (its error is not predicted)",
                100 * sub);
    fprintf(out, "\n");
    const char *model = json_string_value(json_object_get(resp, "model"));
    if (model)
        fprintf(out, "model %s, reference filter %s\n", model,
                fmt_string(json_object_get(json_object_get(resp, "reference"), "filter")));
}

void predict_name_rows(json_t *resp, const char *pattern_list)
{
    char *list = strdup(pattern_list ? pattern_list : "");
    if (!list)
        return;
    const json_t *predictions = json_object_get(resp, "predictions");
    char *save = NULL;
    size_t i = 0;
    for (char *item = strtok_r(list, ",", &save); item; item = strtok_r(NULL, ",", &save), i++) {
        json_t *pat = json_object_get(json_array_get(predictions, i), "pattern");
        const char *name = json_string_value(json_object_get(pat, "name"));
        if (json_is_object(pat) && (!name || !*name))
            json_object_set_new(pat, "name", json_string(item));
    }
    free(list);
}

int cmd_predict(cli_session *s)
{
    json_t *req;
    char err[512];
    if (predict_request(s->args, &req, err, sizeof err)) {
        fprintf(s->err, "aalab predict: %s\n", err);
        return EXIT_USAGE;
    }
    json_t *resp;
    int code = cli_call(s, "POST", "/v1/predict", req, &resp);
    json_decref(req);
    if (code != EXIT_OK)
        return code;
    if (s->args->json) {
        cli_print_json(s->out, resp);
    } else {
        predict_name_rows(resp, s->args->pattern);
        predict_print(s->out, resp, s->args->csv);
    }
    json_decref(resp);
    return EXIT_OK;
}
