/* The evaluate request's decoder (request_evaluate.h). */
#include "request_evaluate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"

static const char *const evaluate_keys[] = {"pattern", "filter", "acuity", "angles",
                                            "lp",      "detail", NULL};

bool proto_evaluate_is_temporal(const json_t *body)
{
    const json_t *pj = json_object_get(body, "pattern");
    return json_is_object(pj) && json_object_get(pj, "temporal");
}

/* The acuity table and the angles, which both pattern forms take. */
static int decode_acuity_angles(const json_t *body, proto_evaluate_request *out, aa_error *err)
{
    int rc = proto_decode_acuity(json_object_get(body, "acuity"), &out->acuity, "acuity", err);
    if (!rc)
        rc = proto_decode_angles(json_object_get(body, "angles"), &out->angles, &out->angle_count,
                                 "angles", err);
    return rc;
}

/* filter, acuity and angles, and a temporal pattern (which takes no lp). */
static int decode_temporal(const json_t *body, proto_evaluate_request *out, aa_error *err)
{
    out->temporal = true;
    int rc = AA_OK;
    if (json_object_get(body, "lp"))
        rc = aa_error_set(err, AA_EINVAL, "lp", "lp is not computed for temporal patterns");
    if (!rc)
        rc = proto_decode_filter(json_object_get(body, "filter"), &out->filter, "filter", err);
    if (!rc)
        rc = decode_acuity_angles(body, out, err);
    if (!rc && !(out->spec = calloc(1, sizeof *out->spec)))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!rc)
        rc = proto_decode_temporal(json_object_get(body, "pattern"), out->spec, "pattern", err);
    return rc;
}

int proto_decode_evaluate_request(const json_t *body, const aa_error *refs,
                                  proto_evaluate_request *out, aa_error *err)
{
    out->detail = out->temporal = false;
    out->lp = 0;
    out->angles = NULL;
    out->angle_count = 0;
    out->pattern = (aa_pattern){0};
    out->spec = NULL;
    int rc = proto_check_keys(body, evaluate_keys, err, "");
    if (rc)
        return rc;
    if (refs && refs->code) {
        *err = *refs;
        return err->code;
    }
    const json_t *pj = json_object_get(body, "pattern");
    const json_t *dj = json_object_get(body, "detail");
    const json_t *lj = json_object_get(body, "lp");
    if (!pj)
        return aa_error_set(err, AA_EINVAL, "pattern", "pattern is required");
    if (dj && !json_is_boolean(dj))
        return aa_error_set(err, AA_EINVAL, "detail", "must be true or false");
    out->detail = dj && json_is_true(dj);
    if (lj) {
        if (!json_is_number(lj) || !(json_number_value(lj) >= 1) ||
            !isfinite(json_number_value(lj)))
            return aa_error_set(err, AA_EINVAL, "lp", "must be a number >= 1");
        out->lp = json_number_value(lj);
    }
    if (proto_evaluate_is_temporal(body))
        return decode_temporal(body, out, err);
    /* The filter first: a "points" pattern may take its weights from it. */
    rc = proto_decode_filter(json_object_get(body, "filter"), &out->filter, "filter", err);
    if (!rc)
        rc = proto_decode_pattern_filtered(pj, 0, &out->filter, &out->pattern, "pattern", err);
    if (!rc)
        rc = decode_acuity_angles(body, out, err);
    return rc;
}

void proto_evaluate_request_free(proto_evaluate_request *r)
{
    aa_pattern_free(&r->pattern);
    if (r->spec) {
        proto_temporal_free(r->spec);
        free(r->spec);
        r->spec = NULL;
    }
    free(r->angles);
    r->angles = NULL;
}
