#include "job_result_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codec.h"

int proto_result_real(const json_t *obj, const char *key, double *out, aa_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (json_is_null(v)) {
        *out = NAN;
        return AA_OK;
    }
    if (!json_is_number(v))
        return aa_error_set(err, AA_EINVAL, key, "must be a number or null");
    *out = json_number_value(v);
    return AA_OK;
}

int proto_result_integer(const json_t *obj, const char *key, long long *out, aa_error *err)
{
    const json_t *v = json_object_get(obj, key);
    if (!json_is_integer(v))
        return aa_error_set(err, AA_EINVAL, key, "must be an integer");
    *out = json_integer_value(v);
    return AA_OK;
}

int proto_result_pattern(const json_t *obj, const char *key, bool optional, aa_pattern *out,
                         bool *present, aa_error *err)
{
    const json_t *v = json_object_get(obj, key);
    memset(out, 0, sizeof *out);
    if (present)
        *present = false;
    if (!v || json_is_null(v))
        return optional ? AA_OK : aa_error_set(err, AA_EINVAL, key, "a pattern is required");
    int rc = proto_decode_pattern(v, 0, out, key, err);
    if (!rc && present)
        *present = true;
    return rc;
}

int proto_result_method(const json_t *obj, const char *key, aa_optimize_method *out, aa_error *err)
{
    const char *name = json_string_value(json_object_get(obj, key));
    if (!name || aa_optimize_method_parse(name, out))
        return aa_error_set(err, AA_EINVAL, key, "must be laine-aila, minimax or smooth");
    return AA_OK;
}

bool proto_run_info_encode(json_t *o, const proto_run_info *ri)
{
    return o &&
           !json_object_set_new(o, "executor",
                                json_string(ri->executor[0] ? ri->executor : "local")) &&
           !json_object_set_new(o, "shards", json_integer(ri->shards > 0 ? ri->shards : 1)) &&
           !json_object_set_new(o, "reproducible", json_boolean(ri->reproducible)) &&
           proto_acuity_ref_encode(o, ri->acuity_name, ri->acuity_version);
}

int proto_run_info_decode(const json_t *obj, proto_run_info *out, aa_error *err)
{
    *out = (proto_run_info){.executor = "local", .shards = 1};
    const json_t *executor = json_object_get(obj, "executor");
    const json_t *shards = json_object_get(obj, "shards");
    const json_t *reproducible = json_object_get(obj, "reproducible");
    if (executor) {
        const char *e = json_string_value(executor);
        if (!e || (strcmp(e, "local") && strcmp(e, "slurm")))
            return aa_error_set(err, AA_EINVAL, "executor", "must be local or slurm");
        snprintf(out->executor, sizeof out->executor, "%s", e);
    }
    if (shards) {
        if (!json_is_integer(shards) || json_integer_value(shards) < 1)
            return aa_error_set(err, AA_EINVAL, "shards", "must be a positive integer");
        out->shards = (long)json_integer_value(shards);
    }
    if (reproducible) {
        if (!json_is_boolean(reproducible))
            return aa_error_set(err, AA_EINVAL, "reproducible", "must be true or false");
        out->reproducible = json_is_true(reproducible);
    }
    return proto_acuity_ref_decode(obj, out->acuity_name, sizeof out->acuity_name,
                                   &out->acuity_version, err);
}

proto_run_info proto_run_info_make(const char *executor, size_t shards, bool reproducible,
                                   const aa_acuity *acuity)
{
    proto_run_info ri = {.shards = (long)shards, .reproducible = reproducible};
    snprintf(ri.executor, sizeof ri.executor, "%s", executor);
    if (acuity)
        proto_acuity_ref_set(acuity, ri.acuity_name, sizeof ri.acuity_name, &ri.acuity_version);
    return ri;
}
