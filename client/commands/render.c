/* aalab render --pattern NAME|FILE [--scene S] [--size WxH] [--image pattern|reference|
 *               difference] -o tile.png */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "view_util.h"

int render_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *pattern;
    if (pattern_argument_load(a->pattern, &pattern, NULL, err, errcap))
        return -1;
    /* The renderer's scene object (server/tiles/tile_render.h): {"name","width","height"}. */
    json_t *scene = json_pack("{s:s}", "name", a->scene ? a->scene : "siemens-star");
    if (a->width > 0) {
        json_object_set_new(scene, "width", json_integer(a->width));
        json_object_set_new(scene, "height", json_integer(a->height));
    }
    json_t *r = json_object();
    json_object_set_new(r, "pattern", pattern);
    json_object_set_new(r, "scene", scene);
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
    json_t *copy = json_deep_copy(resp);
    json_object_del(copy, "tiles");
    print_flat(out, copy);
    json_decref(copy);
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
