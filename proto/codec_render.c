/* The POST /v1/render request and answer (codec_render.h). */
#include "codec_render.h"

#include <string.h>

#include "codec.h"
#include "codec_temporal.h"
#include "job_temporal_render.h"

static const char *const render_keys[] = {"scene",  "size",       "pattern", "reference", "crop",
                                          "acuity", "visibility", "phase",   NULL};

int proto_decode_visibility(const json_t *j, bool *private_out, const char *field, aa_error *err)
{
    *private_out = false;
    if (!j || (json_is_string(j) && !strcmp(json_string_value(j), "team")))
        return AA_OK;
    if (json_is_string(j) && !strcmp(json_string_value(j), "private")) {
        *private_out = true;
        return AA_OK;
    }
    return aa_error_set(err, AA_EINVAL, field, "%s must be \"team\" or \"private\"", field);
}

/* The steady state of one phase of a temporal pattern, as a spatial pattern: its kernels. The
 * expansion is bounded like the temporal-render kind's (proto_temporal_planned_samples). */
static int decode_temporal_phase(const json_t *body, const json_t *pj, proto_render_request *out,
                                 aa_error *err)
{
    proto_temporal spec;
    int rc = proto_decode_temporal(pj, &spec, "pattern", err);
    if (rc)
        return rc;
    aa_temporal t = {0};
    if (proto_temporal_planned_samples(&spec) > (double)AA_MAX_KERNEL_SAMPLES * AA_MAX_KERNELS)
        rc = aa_error_set(err, AA_ERANGE, "pattern.temporal",
                          "more than %d samples per output pixel over the frames",
                          AA_MAX_KERNEL_SAMPLES);
    if (!rc)
        rc = proto_temporal_build(&spec, "pattern.temporal", &t, err);
    const json_t *ph = json_object_get(body, "phase");
    if (!rc && ph &&
        (!json_is_integer(ph) || json_integer_value(ph) < 0 ||
         json_integer_value(ph) >= (json_int_t)t.phase_count))
        rc = aa_error_set(err, AA_EINVAL, "phase", "phase must be an integer in [0, %zu]",
                          t.phase_count - 1);
    if (!rc) {
        out->phase = ph ? (long)json_integer_value(ph) : 0;
        out->phase_count = t.phase_count;
        rc = aa_taa_phase_pattern(&t, (size_t)out->phase, &out->pattern, err);
        if (rc) /* more than AA_MAX_KERNEL_SAMPLES per output pixel */
            snprintf(err->field, sizeof err->field, "pattern.temporal.jitter");
    }
    aa_temporal_free(&t);
    proto_temporal_free(&spec);
    return rc;
}

int proto_decode_render_request(const json_t *body, proto_render_request *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (!json_is_object(body))
        return aa_error_set(err, AA_EINVAL, "", "body must be a JSON object");
    int rc = proto_check_keys(body, render_keys, err, "");
    if (!rc)
        rc = proto_decode_visibility(json_object_get(body, "visibility"), &out->private_tiles,
                                     "visibility", err);
    if (!rc)
        rc = proto_decode_scene_request(body, &out->scene, err);
    json_t *pj = json_object_get(body, "pattern");
    if (!rc && !pj)
        rc = aa_error_set(err, AA_EINVAL, "pattern", "a pattern is required");
    out->phase = -1;
    bool temporal = json_is_object(pj) && json_object_get(pj, "temporal");
    if (!rc && temporal)
        rc = decode_temporal_phase(body, pj, out, err);
    else if (!rc && json_object_get(body, "phase"))
        rc = aa_error_set(err, AA_EINVAL, "phase", "phase is for a temporal pattern only");
    else if (!rc)
        rc = proto_decode_pattern_or_name(pj, 0, &out->pattern, "pattern", err);
    if (!rc)
        rc = proto_decode_reference(json_object_get(body, "reference"), &out->reference,
                                    "reference", err);
    if (!rc)
        rc = proto_decode_crop(json_object_get(body, "crop"), out->scene.width, out->scene.height,
                               &out->crop, "crop", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(body, "acuity"), &out->acuity, "acuity", err);
    if (rc)
        proto_render_request_free(out);
    return rc;
}

void proto_render_request_free(proto_render_request *r)
{
    aa_pattern_free(&r->pattern);
    memset(&r->pattern, 0, sizeof r->pattern);
}

aa_render_params proto_render_params(const proto_render_request *r)
{
    aa_render_params rp = aa_render_params_default(r->scene.shape);
    rp.scene = r->scene;
    rp.reference = r->reference.params;
    rp.acuity = &r->acuity;
    return rp;
}

json_t *proto_encode_render_result(const aa_render_params *rp, const aa_pattern *p,
                                   const aa_render_result *r, json_t *tiles)
{
    if (!tiles)
        return NULL;
    const aa_filter *f = rp->reference.filter;
    return json_pack(
        "{s:o, s:{s:s, s:f, s:I, s:I, s:b}, s:{s:I, s:I, s:s}, s:f, s:o, "
        "s:{s:f, s:f}, s:{s:I, s:I, s:I, s:I, s:I, s:I}, s:o}",
        "scene", proto_encode_scene(&rp->scene), "pattern", "family", p->family,
        "samples_per_pixel", p->cost_spp, "kernels", (json_int_t)p->kernel_count, "kernel_size",
        (json_int_t)p->kernel_size, "border", p->border, "reference", "spp",
        (json_int_t)rp->reference.spp, "seed", (json_int_t)rp->reference.seed, "filter",
        f ? f->name : "mitchell", "e2", r->e2, "stats", proto_encode_diff(&r->diff), "times",
        "pattern_seconds", r->pattern_seconds, "reference_seconds", r->reference_seconds, "pixels",
        "total", (json_int_t)r->ref.pixels, "pattern_sampled", (json_int_t)r->raster.pixels_sampled,
        "pattern_coverage_samples", (json_int_t)r->raster.samples_evaluated, "supersampled",
        (json_int_t)r->ref.pixels_supersampled, "reference_input_pixels_sampled",
        (json_int_t)r->ref.input_pixels, "reference_samples", (json_int_t)r->ref.samples, "tiles",
        tiles);
}

void proto_encode_render_phase(json_t *answer, const proto_render_request *r)
{
    if (answer && r->phase >= 0)
        json_object_set_new(answer, "temporal",
                            json_pack("{s:I, s:I}", "phase", (json_int_t)r->phase, "phase_count",
                                      (json_int_t)r->phase_count));
}
