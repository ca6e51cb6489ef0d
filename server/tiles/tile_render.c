/* Render requests and results as JSON; images as stored PNG tiles (tile_render.h). */
#include "tile_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "png_encode.h"
#include "aa_pattern.h"

/* out = a "." b (or b when a is empty), truncated to cap. */
static void join_path(char *out, size_t cap, const char *a, const char *b)
{
    size_t n = 0;
    for (const char *p = a; *p && n + 1 < cap; p++)
        out[n++] = *p;
    if (*a && *b && n + 1 < cap)
        out[n++] = '.';
    for (const char *p = b; *p && n + 1 < cap; p++)
        out[n++] = *p;
    out[n] = 0;
}

static int field_error(aa_error *err, const char *prefix, const char *key, const char *msg)
{
    char field[96];
    join_path(field, sizeof field, prefix, key);
    return aa_error_set(err, AA_EINVAL, field, "%s", msg);
}

static int expect_object(const json_t *j, const char *prefix, aa_error *err)
{
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, prefix, "must be an object");
    return AA_OK;
}

static int get_int(json_t *v, const char *prefix, const char *key, long long lo, long long hi,
                   int *out, aa_error *err)
{
    if (!json_is_integer(v))
        return field_error(err, prefix, key, "must be an integer");
    json_int_t x = json_integer_value(v);
    if (x < lo || x > hi) {
        char msg[96];
        snprintf(msg, sizeof msg, "must be in %lld..%lld", lo, hi);
        return field_error(err, prefix, key, msg);
    }
    *out = (int)x;
    return AA_OK;
}

static int get_number(json_t *v, const char *prefix, const char *key, double *out, aa_error *err)
{
    if (!json_is_number(v) || !isfinite(json_number_value(v)))
        return field_error(err, prefix, key, "must be a finite number");
    *out = json_number_value(v);
    return AA_OK;
}

static int get_bool(json_t *v, const char *prefix, const char *key, bool *out, aa_error *err)
{
    if (!json_is_boolean(v))
        return field_error(err, prefix, key, "must be true or false");
    *out = json_is_true(v);
    return AA_OK;
}

/* Engine errors name fields relative to the object; make them full paths. */
static int prefix_engine_error(int rc, aa_error *err, const char *prefix)
{
    if (rc && err && *prefix) {
        char field[96];
        join_path(field, sizeof field, prefix, err->field);
        memcpy(err->field, field, sizeof field);
    }
    return rc;
}

int tile_decode_scene(const json_t *j, aa_scene_params *out, const char *prefix, aa_error *err)
{
    *out = aa_scene_params_default(AA_SCENE_SIEMENS_STAR);
    if (!j)
        return AA_OK;
    int rc = expect_object(j, prefix, err);
    if (rc)
        return rc;
    json_t *name = json_object_get(j, "name");
    if (name) {
        int kind = json_is_string(name) ? aa_scene_kind_from_name(json_string_value(name)) : -1;
        if (kind < 0)
            return field_error(err, prefix, "name",
                               "unknown scene (half-plane, checkerboard, siemens-star, rings, "
                               "sliver, spiral, rotating-triangle, translating-circle)");
        *out = aa_scene_params_default((aa_scene_kind)kind);
    }
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)j, key, v)
    {
        if (strcmp(key, "name") == 0)
            continue;
        else if (strcmp(key, "width") == 0)
            rc = get_int(v, prefix, key, 1, AA_IMAGE_MAX_SIDE, &out->width, err);
        else if (strcmp(key, "height") == 0)
            rc = get_int(v, prefix, key, 1, AA_IMAGE_MAX_SIDE, &out->height, err);
        else if (strcmp(key, "zoom") == 0)
            rc = get_number(v, prefix, key, &out->zoom, err);
        else if (strcmp(key, "angle") == 0)
            rc = get_number(v, prefix, key, &out->angle_deg, err);
        else if (strcmp(key, "wedges") == 0)
            rc = get_int(v, prefix, key, 1, AA_SCENE_MAX_WEDGES, &out->wedges, err);
        else if (strcmp(key, "frames") == 0)
            rc = get_int(v, prefix, key, 1, AA_SCENE_MAX_FRAMES, &out->frames, err);
        else if (strcmp(key, "frame") == 0)
            rc = get_int(v, prefix, key, 0, AA_SCENE_MAX_FRAMES - 1, &out->frame, err);
        else if (strcmp(key, "offset") == 0)
            rc = get_number(v, prefix, key, &out->offset, err);
        else if (strcmp(key, "mirror_x") == 0)
            rc = get_bool(v, prefix, key, &out->mirror_x, err);
        else if (strcmp(key, "mirror_y") == 0)
            rc = get_bool(v, prefix, key, &out->mirror_y, err);
        else
            rc = field_error(err, prefix, key, "unknown field");
        if (rc)
            return rc;
    }
    aa_scene probe;
    return prefix_engine_error(aa_scene_init(&probe, out, err), err, prefix);
}

int tile_decode_scene_request(const json_t *request, aa_scene_params *out, aa_error *err)
{
    /* The short form: "scene" may be a plain name and "size":[w,h] sits beside it;
     * both fold into the object form {"name","width","height",...}. */
    json_t *scene = json_object_get(request, "scene");
    json_t *size = json_object_get(request, "size");
    if (!size && !json_is_string(scene))
        return tile_decode_scene(scene, out, "scene", err);
    json_t *obj = json_is_string(scene) ? json_pack("{s:O}", "name", scene)
                  : scene               ? json_deep_copy(scene)
                                        : json_object();
    if (!obj)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int rc = AA_OK;
    if (!json_is_object(obj)) {
        rc = aa_error_set(err, AA_EINVAL, "scene", "a scene name or an object {\"name\": ...}");
    } else if (size) {
        if (!json_is_array(size) || json_array_size(size) != 2 ||
            !json_is_integer(json_array_get(size, 0)) || !json_is_integer(json_array_get(size, 1)))
            rc = aa_error_set(err, AA_EINVAL, "size", "size must be [width, height] in pixels");
        else if (json_object_get(obj, "width") || json_object_get(obj, "height"))
            rc = aa_error_set(err, AA_EINVAL, "size",
                              "give the size either as size or as scene.width/height");
        else {
            json_object_set(obj, "width", json_array_get(size, 0));
            json_object_set(obj, "height", json_array_get(size, 1));
        }
    }
    if (!rc) {
        rc = tile_decode_scene(obj, out, "scene", err);
        if (rc && err && json_is_string(scene) && !strcmp(err->field, "scene.name"))
            snprintf(err->field, sizeof err->field, "scene");
        if (rc && size && err) {
            if (!strcmp(err->field, "scene.width"))
                snprintf(err->field, sizeof err->field, "size[0]");
            else if (!strcmp(err->field, "scene.height"))
                snprintf(err->field, sizeof err->field, "size[1]");
        }
    }
    json_decref(obj);
    return rc;
}

static int decode_filter(const json_t *j, aa_filter *f, const char *prefix, aa_error *err)
{
    char path[96];
    join_path(path, sizeof path, prefix, "filter");
    aa_filter_params fp = aa_filter_params_default();
    const char *name = NULL;
    if (json_is_string(j)) {
        name = json_string_value(j);
    } else if (json_is_object(j)) {
        const char *key;
        json_t *v;
        json_object_foreach((json_t *)j, key, v)
        {
            int rc = AA_OK;
            if (strcmp(key, "name") == 0) {
                if (!json_is_string(v))
                    return field_error(err, path, key, "must be a string");
                name = json_string_value(v);
            } else if (strcmp(key, "B") == 0) {
                rc = get_number(v, path, key, &fp.B, err);
            } else if (strcmp(key, "C") == 0) {
                rc = get_number(v, path, key, &fp.C, err);
            } else if (strcmp(key, "radius") == 0) {
                rc = get_number(v, path, key, &fp.radius, err);
            } else if (strcmp(key, "sigma") == 0) {
                rc = get_number(v, path, key, &fp.sigma, err);
            } else if (strcmp(key, "a") == 0) {
                rc = get_number(v, path, key, &fp.a, err);
            } else {
                rc = field_error(err, path, key, "unknown field");
            }
            if (rc)
                return rc;
        }
        if (!name)
            return field_error(err, path, "name", "is required");
    } else {
        return aa_error_set(err, AA_EINVAL, path, "must be a filter name or object");
    }
    int rc = aa_filter_by_name(f, name, &fp, err);
    if (rc && err && !err->field[0])
        join_path(err->field, sizeof err->field, path, "name");
    else if (rc)
        prefix_engine_error(rc, err, path);
    if (!rc && !(f->radius > 0 && f->radius <= 8))
        rc = aa_error_set(err, AA_EINVAL, path, "the reference filter radius must be <= 8");
    return rc;
}

int tile_decode_reference(const json_t *j, tile_reference_spec *out, const char *prefix,
                          aa_error *err)
{
    memset(out, 0, sizeof *out);
    out->params = aa_reference_params_default();
    if (!j)
        return AA_OK;
    int rc = expect_object(j, prefix, err);
    if (rc)
        return rc;
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)j, key, v)
    {
        if (strcmp(key, "spp") == 0) {
            rc = get_int(v, prefix, key, 1, AA_REFERENCE_MAX_SPP, &out->params.spp, err);
            int m = (int)lround(sqrt((double)out->params.spp));
            if (!rc && m * m != out->params.spp)
                rc = field_error(err, prefix, key, "must be a square: 16, 64, 256, 1024, 4096");
        } else if (strcmp(key, "seed") == 0) {
            if (!json_is_integer(v) || json_integer_value(v) < 0)
                rc = field_error(err, prefix, key, "must be a non-negative integer");
            else
                out->params.seed = (uint64_t)json_integer_value(v);
        } else if (strcmp(key, "filter") == 0) {
            rc = decode_filter(v, &out->filter, prefix, err);
            if (!rc)
                out->params.filter = &out->filter;
        } else {
            rc = field_error(err, prefix, key, "unknown field");
        }
        if (rc)
            return rc;
    }
    return AA_OK;
}

int tile_decode_crop(const json_t *j, int width, int height, tile_crop *out, const char *prefix,
                     aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!j || json_is_null(j))
        return AA_OK;
    int rc = expect_object(j, prefix, err);
    if (rc)
        return rc;
    int x = 0, y = 0, w = width < 32 ? width : 32, h = height < 32 ? height : 32, scale = 8;
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)j, key, v)
    {
        if (strcmp(key, "x") == 0)
            rc = get_int(v, prefix, key, 0, width - 1, &x, err);
        else if (strcmp(key, "y") == 0)
            rc = get_int(v, prefix, key, 0, height - 1, &y, err);
        else if (strcmp(key, "width") == 0)
            rc = get_int(v, prefix, key, 1, width, &w, err);
        else if (strcmp(key, "height") == 0)
            rc = get_int(v, prefix, key, 1, height, &h, err);
        else if (strcmp(key, "scale") == 0)
            rc = get_int(v, prefix, key, 1, TILE_MAX_CROP_SCALE, &scale, err);
        else
            rc = field_error(err, prefix, key, "unknown field");
        if (rc)
            return rc;
    }
    if (x + w > width)
        return field_error(err, prefix, "width", "crop extends beyond the image");
    if (y + h > height)
        return field_error(err, prefix, "height", "crop extends beyond the image");
    if ((long long)w * h * scale * scale > TILE_MAX_CROP_PIXELS)
        return field_error(err, prefix, "scale", "magnified crop too large (1 Mpixel at most)");
    out->enabled = true;
    out->rect = (aa_rect){x, y, x + w, y + h};
    out->scale = scale;
    return AA_OK;
}

int tile_pattern_from_preset_name(const json_t *j, aa_pattern *p, const char *field, aa_error *err)
{
    if (!json_is_string(j))
        return 1;
    const aa_preset *pr = aa_preset_find(json_string_value(j));
    if (!pr)
        return aa_error_set(err, AA_EINVAL, field, "unknown preset '%s'", json_string_value(j));
    int rc = aa_pattern_from_preset(p, pr, err);
    return prefix_engine_error(rc, err, field);
}

json_t *tile_encode_scene(const aa_scene_params *p)
{
    json_t *o = json_pack("{s:s, s:I, s:I, s:f, s:f, s:I, s:b, s:b}", "name",
                          aa_scene_kind_name(p->kind), "width", (json_int_t)p->width, "height",
                          (json_int_t)p->height, "zoom", p->zoom, "angle", p->angle_deg, "wedges",
                          (json_int_t)p->wedges, "mirror_x", p->mirror_x, "mirror_y", p->mirror_y);
    if (o && aa_scene_kind_is_animation(p->kind)) {
        json_object_set_new(o, "frames", json_integer(p->frames));
        json_object_set_new(o, "frame", json_integer(p->frame));
    }
    if (o && p->kind == AA_SCENE_HALF_PLANE)
        json_object_set_new(o, "offset", json_real(p->offset));
    return o;
}

json_t *tile_encode_diff(const aa_diff_stats *d)
{
    json_t *hist = json_array(), *pen = json_array();
    for (int i = 0; i < 256; i++) {
        json_array_append_new(hist, json_integer((json_int_t)d->histogram[i]));
        json_array_append_new(pen, json_real(d->penalised[i]));
    }
    return json_pack("{s:f, s:f, s:I, s:o, s:o}", "rmse", d->rmse, "max_dev", d->max_dev, "pixels",
                     (json_int_t)d->pixels, "histogram", hist, "penalised_histogram", pen);
}

json_t *tile_put_gray8_as(tile_store *ts, const tile_access *access, const uint8_t *px, int width,
                          int height, aa_error *err)
{
    void *png;
    size_t len;
    char id[TILE_ID_LEN + 1];
    if (tile_png_encode_gray(px, width, height, &png, &len, err))
        return NULL;
    int rc = tile_store_put_as(ts, png, len, access, id, err);
    free(png);
    if (rc)
        return NULL;
    char url[64];
    snprintf(url, sizeof url, "/v1/tiles/%s.png", id);
    return json_pack("{s:s, s:s, s:I, s:I, s:I}", "id", id, "url", url, "width", (json_int_t)width,
                     "height", (json_int_t)height, "bytes", (json_int_t)len);
}

json_t *tile_put_image(tile_store *ts, const tile_access *access, const aa_image *img,
                       aa_error *err)
{
    uint8_t *px = malloc((size_t)img->width * (size_t)img->height);
    if (!px) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    aa_image_to_gray8(img, px);
    json_t *o = tile_put_gray8_as(ts, access, px, img->width, img->height, err);
    free(px);
    return o;
}

json_t *tile_put_difference(tile_store *ts, const tile_access *access, const aa_image *a,
                            const aa_image *ref, aa_error *err)
{
    uint8_t *px = malloc((size_t)a->width * (size_t)a->height);
    if (!px) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    aa_image_difference_gray8(a, ref, 0.1, px);
    json_t *o = tile_put_gray8_as(ts, access, px, a->width, a->height, err);
    free(px);
    return o;
}

static json_t *put_crop(tile_store *ts, const tile_access *access, const uint8_t *full, int width,
                        const tile_crop *c, aa_error *err)
{
    int w = (c->rect.x1 - c->rect.x0) * c->scale, h = (c->rect.y1 - c->rect.y0) * c->scale;
    uint8_t *px = malloc((size_t)w * (size_t)h);
    if (!px) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    aa_gray8_crop_magnify(full, width, c->rect, c->scale, px);
    json_t *o = tile_put_gray8_as(ts, access, px, w, h, err);
    free(px);
    return o;
}

json_t *tile_put_render_images_as(tile_store *ts, const tile_access *access,
                                  const aa_image *pattern, const aa_image *reference,
                                  const tile_crop *crop, aa_error *err)
{
    size_t n = (size_t)pattern->width * (size_t)pattern->height;
    uint8_t *g[3] = {malloc(n), malloc(n), malloc(n)};
    json_t *out = json_object(), *crops = NULL;
    const char *names[3] = {"pattern", "reference", "difference"};
    if (!g[0] || !g[1] || !g[2] || !out) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto fail;
    }
    aa_image_to_gray8(pattern, g[0]);
    aa_image_to_gray8(reference, g[1]);
    aa_image_difference_gray8(pattern, reference, 0.1, g[2]);
    if (crop && crop->enabled)
        crops = json_object();
    for (int k = 0; k < 3; k++) {
        json_t *t = tile_put_gray8_as(ts, access, g[k], pattern->width, pattern->height, err);
        if (!t)
            goto fail;
        json_object_set_new(out, names[k], t);
        if (crops) {
            json_t *c = put_crop(ts, access, g[k], pattern->width, crop, err);
            if (!c)
                goto fail;
            json_object_set_new(crops, names[k], c);
        }
    }
    if (crops) {
        json_object_set_new(crops, "rect",
                            json_pack("{s:I, s:I, s:I, s:I, s:I}", "x", (json_int_t)crop->rect.x0,
                                      "y", (json_int_t)crop->rect.y0, "width",
                                      (json_int_t)(crop->rect.x1 - crop->rect.x0), "height",
                                      (json_int_t)(crop->rect.y1 - crop->rect.y0), "scale",
                                      (json_int_t)crop->scale));
        json_object_set_new(out, "crop", crops);
        crops = NULL;
    }
    for (int k = 0; k < 3; k++)
        free(g[k]);
    return out;
fail:
    for (int k = 0; k < 3; k++)
        free(g[k]);
    json_decref(crops);
    json_decref(out);
    return NULL;
}

json_t *tile_render_result_json(tile_store *ts, const tile_access *access,
                                const aa_render_params *rp, const aa_pattern *p,
                                const aa_render_result *r, const tile_crop *crop, aa_error *err)
{
    json_t *tiles = tile_put_render_images_as(ts, access, &r->pattern, &r->reference, crop, err);
    if (!tiles)
        return NULL;
    const aa_filter *f = rp->reference.filter;
    return json_pack(
        "{s:o, s:{s:s, s:f, s:I, s:I, s:b}, s:{s:I, s:I, s:s}, s:f, s:o, "
        "s:{s:f, s:f}, s:{s:I, s:I, s:I, s:I, s:I, s:I}, s:o}",
        "scene", tile_encode_scene(&rp->scene), "pattern", "family", p->family, "samples_per_pixel",
        p->cost_spp, "kernels", (json_int_t)p->kernel_count, "kernel_size",
        (json_int_t)p->kernel_size, "border", p->border, "reference", "spp",
        (json_int_t)rp->reference.spp, "seed", (json_int_t)rp->reference.seed, "filter",
        f ? f->name : "mitchell", "e2", r->e2, "stats", tile_encode_diff(&r->diff), "times",
        "pattern_seconds", r->pattern_seconds, "reference_seconds", r->reference_seconds, "pixels",
        "total", (json_int_t)r->ref.pixels, "pattern_sampled", (json_int_t)r->raster.pixels_sampled,
        "pattern_coverage_samples", (json_int_t)r->raster.samples_evaluated, "supersampled",
        (json_int_t)r->ref.pixels_supersampled, "reference_input_pixels_sampled",
        (json_int_t)r->ref.input_pixels, "reference_samples", (json_int_t)r->ref.samples, "tiles",
        tiles);
}
