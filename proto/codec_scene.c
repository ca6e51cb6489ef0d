/* Scene, reference and crop objects of the renderer (codec_scene.h). */
#include "codec_scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codec_internal.h"
#include "preset_suggest.h"
#include "aa_pattern.h"

static int expect_object(const json_t *j, const char *prefix, aa_error *err)
{
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, prefix, "must be an object");
    return AA_OK;
}

/* An optional integer member in lo..hi; *out keeps its value when key is absent. */
static int get_int(const json_t *obj, const char *prefix, const char *key, long long lo,
                   long long hi, int *out, aa_error *err)
{
    json_t *v = json_object_get(obj, key);
    if (!v)
        return AA_OK;
    if (!json_is_integer(v))
        return proto_fail(err, AA_EINVAL, prefix, key, "must be an integer");
    json_int_t x = json_integer_value(v);
    if (x < lo || x > hi) {
        char msg[96];
        snprintf(msg, sizeof msg, "must be in %lld..%lld", lo, hi);
        return proto_fail(err, AA_EINVAL, prefix, key, msg);
    }
    *out = (int)x;
    return AA_OK;
}

static int get_number(const json_t *obj, const char *prefix, const char *key, double *out,
                      aa_error *err)
{
    json_t *v = json_object_get(obj, key);
    if (!v)
        return AA_OK;
    if (!json_is_number(v) || !isfinite(json_number_value(v)))
        return proto_fail(err, AA_EINVAL, prefix, key, "must be a finite number");
    *out = json_number_value(v);
    return AA_OK;
}

static int get_bool(const json_t *obj, const char *prefix, const char *key, bool *out,
                    aa_error *err)
{
    json_t *v = json_object_get(obj, key);
    if (!v)
        return AA_OK;
    if (!json_is_boolean(v))
        return proto_fail(err, AA_EINVAL, prefix, key, "must be true or false");
    *out = json_is_true(v);
    return AA_OK;
}

static const char *const scene_keys[] = {"name",   "width",    "height",   "zoom",
                                         "angle",  "wedges",   "frames",   "frame",
                                         "offset", "mirror_x", "mirror_y", NULL};

int proto_decode_scene(const json_t *j, aa_scene_params *out, const char *prefix, aa_error *err)
{
    *out = aa_scene_params_default(AA_SCENE_SIEMENS_STAR);
    if (!j)
        return AA_OK;
    int rc = expect_object(j, prefix, err);
    if (!rc)
        rc = proto_check_keys(j, scene_keys, err, prefix);
    if (rc)
        return rc;
    json_t *name = json_object_get(j, "name");
    if (name) {
        int shape = json_is_string(name) ? aa_scene_shape_from_name(json_string_value(name)) : -1;
        if (shape < 0)
            return proto_fail(err, AA_EINVAL, prefix, "name",
                              "unknown scene (half-plane, checkerboard, siemens-star, rings, "
                              "sliver, spiral, rotating-triangle, translating-circle)");
        *out = aa_scene_params_default((aa_scene_shape)shape);
    }
    if ((rc = get_int(j, prefix, "width", 1, AA_IMAGE_MAX_SIDE, &out->width, err)) ||
        (rc = get_int(j, prefix, "height", 1, AA_IMAGE_MAX_SIDE, &out->height, err)) ||
        (rc = get_number(j, prefix, "zoom", &out->zoom, err)) ||
        (rc = get_number(j, prefix, "angle", &out->angle_deg, err)) ||
        (rc = get_int(j, prefix, "wedges", 1, AA_SCENE_MAX_WEDGES, &out->wedges, err)) ||
        (rc = get_int(j, prefix, "frames", 1, AA_SCENE_MAX_FRAMES, &out->frames, err)) ||
        (rc = get_int(j, prefix, "frame", 0, AA_SCENE_MAX_FRAMES - 1, &out->frame, err)) ||
        (rc = get_number(j, prefix, "offset", &out->offset, err)) ||
        (rc = get_bool(j, prefix, "mirror_x", &out->mirror_x, err)) ||
        (rc = get_bool(j, prefix, "mirror_y", &out->mirror_y, err)))
        return rc;
    aa_scene probe;
    rc = aa_scene_init(&probe, out, err);
    return rc ? proto_prefix_error(err, prefix) : AA_OK;
}

int proto_decode_scene_request(const json_t *request, aa_scene_params *out, aa_error *err)
{
    /* "scene" may be a plain name and "size":[w,h] may sit beside it; both fold into the
     * object form {"name","width","height",...}. */
    json_t *scene = json_object_get(request, "scene");
    json_t *size = json_object_get(request, "size");
    if (!size && !json_is_string(scene))
        return proto_decode_scene(scene, out, "scene", err);
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
        rc = proto_decode_scene(obj, out, "scene", err);
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

static const char *const filter_keys[] = {"name", "B", "C", "radius", "sigma", "a", NULL};

/* The reference's own filter form: a name, or an object whose parameters override the
 * defaults of that name; its radius is bounded by the reference's supersampling window. */
static int decode_filter(const json_t *j, aa_filter *f, const char *prefix, aa_error *err)
{
    char path[PROTO_FIELD_MAX];
    proto_join_field(path, sizeof path, prefix, "filter");
    aa_filter_params fp = aa_filter_params_default();
    const char *name = NULL;
    if (json_is_string(j)) {
        name = json_string_value(j);
    } else if (json_is_object(j)) {
        int rc = proto_check_keys(j, filter_keys, err, path);
        if (rc)
            return rc;
        json_t *n = json_object_get(j, "name");
        if (n && !json_is_string(n))
            return proto_fail(err, AA_EINVAL, path, "name", "must be a string");
        name = json_string_value(n);
        if ((rc = get_number(j, path, "B", &fp.B, err)) ||
            (rc = get_number(j, path, "C", &fp.C, err)) ||
            (rc = get_number(j, path, "radius", &fp.radius, err)) ||
            (rc = get_number(j, path, "sigma", &fp.sigma, err)) ||
            (rc = get_number(j, path, "a", &fp.a, err)))
            return rc;
        if (!name)
            return proto_fail(err, AA_EINVAL, path, "name", "is required");
    } else {
        return aa_error_set(err, AA_EINVAL, path, "must be a filter name or object");
    }
    int rc = aa_filter_by_name(f, name, &fp, err);
    if (rc && err && !err->field[0])
        proto_join_field(err->field, sizeof err->field, path, "name");
    else if (rc)
        proto_prefix_error(err, path);
    if (!rc && !(f->radius > 0 && f->radius <= 8))
        rc = aa_error_set(err, AA_EINVAL, path, "the reference filter radius must be <= 8");
    return rc;
}

static const char *const reference_keys[] = {"spp", "seed", "filter", NULL};

int proto_decode_reference(const json_t *j, proto_reference_spec *out, const char *prefix,
                           aa_error *err)
{
    memset(out, 0, sizeof *out);
    out->params = aa_reference_params_default();
    if (!j)
        return AA_OK;
    int rc = expect_object(j, prefix, err);
    if (!rc)
        rc = proto_check_keys(j, reference_keys, err, prefix);
    if (!rc && json_object_get(j, "spp")) {
        rc = get_int(j, prefix, "spp", 1, AA_REFERENCE_MAX_SPP, &out->params.spp, err);
        int m = (int)lround(sqrt((double)out->params.spp));
        if (!rc && m * m != out->params.spp)
            rc = proto_fail(err, AA_EINVAL, prefix, "spp",
                            "must be a square: 16, 64, 256, 1024, 4096");
    }
    json_t *seed = json_object_get(j, "seed");
    if (!rc && seed) {
        if (!json_is_integer(seed) || json_integer_value(seed) < 0)
            rc = proto_fail(err, AA_EINVAL, prefix, "seed", "must be a non-negative integer");
        else
            out->params.seed = (uint64_t)json_integer_value(seed);
    }
    json_t *filter = json_object_get(j, "filter");
    if (!rc && filter) {
        rc = decode_filter(filter, &out->filter, prefix, err);
        if (!rc)
            out->params.filter = &out->filter;
    }
    return rc;
}

static const char *const crop_keys[] = {"x", "y", "width", "height", "scale", NULL};

int proto_decode_crop(const json_t *j, int width, int height, proto_crop *out, const char *prefix,
                      aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!j || json_is_null(j))
        return AA_OK;
    int rc = expect_object(j, prefix, err);
    if (!rc)
        rc = proto_check_keys(j, crop_keys, err, prefix);
    if (rc)
        return rc;
    int x = 0, y = 0, w = width < 32 ? width : 32, h = height < 32 ? height : 32, scale = 8;
    if ((rc = get_int(j, prefix, "x", 0, width - 1, &x, err)) ||
        (rc = get_int(j, prefix, "y", 0, height - 1, &y, err)) ||
        (rc = get_int(j, prefix, "width", 1, width, &w, err)) ||
        (rc = get_int(j, prefix, "height", 1, height, &h, err)) ||
        (rc = get_int(j, prefix, "scale", 1, PROTO_MAX_CROP_SCALE, &scale, err)))
        return rc;
    if (x + w > width)
        return proto_fail(err, AA_EINVAL, prefix, "width", "crop extends beyond the image");
    if (y + h > height)
        return proto_fail(err, AA_EINVAL, prefix, "height", "crop extends beyond the image");
    if ((long long)w * h * scale * scale > PROTO_MAX_CROP_PIXELS)
        return proto_fail(err, AA_EINVAL, prefix, "scale",
                          "magnified crop too large (1 Mpixel at most)");
    out->enabled = true;
    out->rect = (aa_rect){x, y, x + w, y + h};
    out->scale = scale;
    return AA_OK;
}

int proto_pattern_from_preset_name(const json_t *j, aa_pattern *p, const char *field, aa_error *err)
{
    if (!json_is_string(j))
        return 1;
    const aa_preset *pr = aa_preset_find(json_string_value(j));
    if (!pr)
        return proto_unknown_preset(err, field, json_string_value(j));
    int rc = aa_pattern_from_preset(p, pr, err);
    return rc ? proto_prefix_error(err, field) : AA_OK;
}

int proto_decode_pattern_or_name(const json_t *j, unsigned flags, aa_pattern *p, const char *field,
                                 aa_error *err)
{
    int rc = proto_pattern_from_preset_name(j, p, field, err);
    return rc == 1 ? proto_decode_pattern(j, flags, p, field, err) : rc;
}

json_t *proto_encode_scene(const aa_scene_params *p)
{
    json_t *o = json_pack("{s:s, s:I, s:I, s:f, s:f, s:I, s:b, s:b}", "name",
                          aa_scene_shape_name(p->shape), "width", (json_int_t)p->width, "height",
                          (json_int_t)p->height, "zoom", p->zoom, "angle", p->angle_deg, "wedges",
                          (json_int_t)p->wedges, "mirror_x", p->mirror_x, "mirror_y", p->mirror_y);
    if (o && aa_scene_shape_is_animation(p->shape)) {
        json_object_set_new(o, "frames", json_integer(p->frames));
        json_object_set_new(o, "frame", json_integer(p->frame));
    }
    if (o && p->shape == AA_SCENE_HALF_PLANE)
        json_object_set_new(o, "offset", json_real(p->offset));
    return o;
}

json_t *proto_encode_diff(const aa_diff_stats *d)
{
    json_t *hist = json_array(), *pen = json_array();
    for (int i = 0; i < 256; i++) {
        json_array_append_new(hist, json_integer((json_int_t)d->histogram[i]));
        json_array_append_new(pen, json_real(d->penalised[i]));
    }
    return json_pack("{s:f, s:f, s:I, s:o, s:o}", "rmse", d->rmse, "max_dev", d->max_dev, "pixels",
                     (json_int_t)d->pixels, "histogram", hist, "penalised_histogram", pen);
}
