/* aalab render --pattern NAME|FILE [--scene S] [--size WxH] [--image pattern|reference|
 *               difference] -o tile.png */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "../table.h"
#include "view_util.h"

int render_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *pattern;
    if (pattern_argument_load(a->pattern, a, &pattern, NULL, err, errcap))
        return -1;
    /* The short wire form: "scene" by name and "size":[w,h] beside it (the renderer also takes
     * a scene object with more parameters; see proto/codec_scene.h). */
    json_t *r = json_object();
    json_object_set_new(r, "pattern", pattern);
    json_object_set_new(r, "scene", json_string(a->scene ? a->scene : "siemens-star"));
    if (a->width > 0)
        json_object_set_new(r, "size", json_pack("[ii]", a->width, a->height));
    *req = r;
    return 0;
}

/* The tile entry for an image: a path ("/v1/tiles/7.png"), an id ("7"), or {"url"|"id"}. */
static int tile_path(const json_t *resp, const char *image, char *out, size_t cap)
{
    const json_t *tiles = json_object_get(resp, "tiles");
    const json_t *t = json_object_get(tiles, image);
    if (json_is_object(t)) {
        const json_t *url = json_object_get(t, "url");
        t = url ? url : json_object_get(t, "id");
    }
    if (json_is_string(t)) {
        const char *v = json_string_value(t);
        if (v[0] == '/')
            snprintf(out, cap, "%s", v);
        else
            snprintf(out, cap, "/v1/tiles/%s.png", v);
        return 0;
    }
    if (json_is_integer(t)) {
        snprintf(out, cap, "/v1/tiles/%lld.png", (long long)json_integer_value(t));
        return 0;
    }
    return -1;
}

void render_print(FILE *out, const json_t *resp)
{
    const json_t *scene = json_object_get(resp, "scene");
    const json_t *stats = json_object_get(resp, "stats");
    const json_t *times = json_object_get(resp, "times");
    const json_t *pixels = json_object_get(resp, "pixels");
    char size[64], e2[32], rmse[32], maxdev[32], tp[32], tr[32], ss[32], total[32];
    snprintf(size, sizeof size, "%s x %s",
             fmt_number(tp, sizeof tp, json_object_get(scene, "width"), 0),
             fmt_number(tr, sizeof tr, json_object_get(scene, "height"), 0));
    const char *keys[] = {"scene",        "size",           "pattern",
                          "E2",           "RMSE (0..255)",  "max deviation",
                          "pattern time", "reference time", "supersampled pixels"};
    const char *values[] = {
        fmt_string(json_object_get(scene, "name")),
        size,
        fmt_string(json_object_get(json_object_get(resp, "pattern"), "family")),
        fmt_number(e2, sizeof e2, json_object_get(resp, "e2"), 6),
        fmt_number(rmse, sizeof rmse, json_object_get(stats, "rmse"), 3),
        fmt_number(maxdev, sizeof maxdev, json_object_get(stats, "max_dev"), 3),
        fmt_number(tp, sizeof tp, json_object_get(times, "pattern_seconds"), 4),
        fmt_number(tr, sizeof tr, json_object_get(times, "reference_seconds"), 4),
        NULL};
    char ssbuf[80];
    fmt_number(ss, sizeof ss, json_object_get(pixels, "supersampled"), 0);
    fmt_number(total, sizeof total, json_object_get(pixels, "total"), 0);
    snprintf(ssbuf, sizeof ssbuf, "%s of %s", ss, total);
    values[8] = ssbuf;
    print_key_values(out, keys, values, 9);
}

int cmd_render(cli_session *s)
{
    json_t *req, *resp;
    char err[512];
    if (render_request(s->args, &req, err, sizeof err)) {
        fprintf(s->err, "aalab render: %s\n", err);
        return EXIT_USAGE;
    }
    int code = cli_call(s, "POST", "/v1/render", req, &resp);
    json_decref(req);
    if (code != EXIT_OK)
        return code;
    if (s->args->output) {
        char path[512];
        if (tile_path(resp, s->args->image, path, sizeof path)) {
            fprintf(s->err, "aalab: the render answer has no '%s' tile\n", s->args->image);
            json_decref(resp);
            return EXIT_SERVER_5XX;
        }
        http_response png;
        code = cli_call_raw(s, "GET", path, &png);
        if (code == EXIT_OK) {
            code = write_output(s->out, s->err, s->args->output, png.body, png.len);
            http_response_free(&png);
        }
    }
    if (code == EXIT_OK) { /* with -o - the PNG went to stdout: stats go to stderr */
        FILE *stats = s->args->output && strcmp(s->args->output, "-") == 0 ? s->err : s->out;
        if (s->args->json)
            cli_print_json(stats, resp);
        else
            render_print(stats, resp);
    }
    json_decref(resp);
    return code;
}
