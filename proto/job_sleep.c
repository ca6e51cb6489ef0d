#include "job_sleep.h"

#include <string.h>

#include "codec.h"

static const char *const spec_keys[] = {"seconds", "fail", "pattern", NULL};

int proto_decode_sleep_spec(const json_t *spec, proto_sleep_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_check_keys(spec, spec_keys, err, "");
    if (rc)
        return rc;
    json_t *v = json_object_get(spec, "seconds");
    if (!v)
        return aa_error_set(err, AA_EINVAL, "seconds", "seconds is required");
    if (!json_is_number(v))
        return aa_error_set(err, AA_EINVAL, "seconds", "must be a number");
    s->seconds = json_number_value(v);
    if (!(s->seconds >= 0 && s->seconds <= 3600))
        return aa_error_set(err, AA_ERANGE, "seconds", "must be in 0..3600");
    v = json_object_get(spec, "fail");
    if (v && !json_is_boolean(v))
        return aa_error_set(err, AA_EINVAL, "fail", "must be true or false");
    s->fail = v && json_is_true(v);
    const json_t *pj = json_object_get(spec, "pattern");
    if (pj) {
        rc = proto_decode_pattern(pj, 0, &s->pattern, "pattern", err);
        if (rc)
            return rc;
        s->have_pattern = true;
    }
    return AA_OK;
}

void proto_sleep_spec_free(proto_sleep_spec *s)
{
    if (s->have_pattern)
        aa_pattern_free(&s->pattern);
    s->have_pattern = false;
}

json_t *proto_encode_sleep_result(const proto_sleep_result *r)
{
    json_t *o =
        json_pack("{s:f,s:I}", "slept_seconds", r->slept_seconds, "steps", (json_int_t)r->steps);
    if (o && r->have_pattern &&
        json_object_set_new(o, "pattern", proto_encode_pattern(&r->pattern))) {
        json_decref(o);
        return NULL;
    }
    return o;
}

static const char *const result_keys[] = {"slept_seconds", "steps", "pattern", NULL};

int proto_decode_sleep_result(const json_t *j, proto_sleep_result *r, aa_error *err)
{
    memset(r, 0, sizeof *r);
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, "", "must be an object");
    int rc = proto_check_keys(j, result_keys, err, "");
    if (rc)
        return rc;
    const json_t *v = json_object_get(j, "slept_seconds");
    if (!json_is_number(v))
        return aa_error_set(err, AA_EINVAL, "slept_seconds", "must be a number");
    r->slept_seconds = json_number_value(v);
    if (!(r->slept_seconds >= 0))
        return aa_error_set(err, AA_ERANGE, "slept_seconds", "must be >= 0");
    v = json_object_get(j, "steps");
    if (!json_is_integer(v))
        return aa_error_set(err, AA_EINVAL, "steps", "must be an integer");
    r->steps = json_integer_value(v);
    if (r->steps < 0)
        return aa_error_set(err, AA_ERANGE, "steps", "must be >= 0");
    const json_t *pj = json_object_get(j, "pattern");
    if (pj) {
        rc = proto_decode_pattern(pj, 0, &r->pattern, "pattern", err);
        if (rc)
            return rc;
        r->have_pattern = true;
    }
    return AA_OK;
}

void proto_sleep_result_free(proto_sleep_result *r)
{
    if (r->have_pattern)
        aa_pattern_free(&r->pattern);
    r->have_pattern = false;
}
