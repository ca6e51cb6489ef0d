#include "job_envelope.h"

#include <string.h>

int job_envelope_take(const json_t *spec, job_envelope *env, json_t **kind_spec, aa_error *err)
{
    *env = (job_envelope){0};
    *kind_spec = NULL;
    json_t *v = json_object_get(spec, "priority");
    if (v) {
        if (!json_is_integer(v))
            return aa_error_set(err, AA_EINVAL, "priority", "must be an integer");
        json_int_t p = json_integer_value(v);
        if (p < JOB_PRIORITY_MIN || p > JOB_PRIORITY_MAX)
            return aa_error_set(err, AA_ERANGE, "priority", "must be in %d..%d", JOB_PRIORITY_MIN,
                                JOB_PRIORITY_MAX);
        env->priority = (int)p;
    }
    v = json_object_get(spec, "visibility");
    if (v) {
        const char *s = json_string_value(v);
        if (!s || (strcmp(s, "team") && strcmp(s, "private")) || strlen(s) != json_string_length(v))
            return aa_error_set(err, AA_EINVAL, "visibility", "must be \"team\" or \"private\"");
        env->private_job = !strcmp(s, "private");
    }
    v = json_object_get(spec, "pinned");
    if (v) {
        if (!json_is_boolean(v))
            return aa_error_set(err, AA_EINVAL, "pinned", "must be true or false");
        env->pinned = json_is_true(v);
    }
    v = json_object_get(spec, "label");
    if (v) {
        const char *s = json_string_value(v);
        if (!s || strlen(s) != json_string_length(v) || json_string_length(v) > JOB_LABEL_MAX)
            return aa_error_set(err, AA_EINVAL, "label", "must be a string of at most %d bytes",
                                JOB_LABEL_MAX);
        memcpy(env->label, s, json_string_length(v) + 1);
    }
    v = json_object_get(spec, "executor");
    if (v) {
        const char *s = json_string_value(v);
        if (!s || (strcmp(s, "local") && strcmp(s, "slurm")) || strlen(s) != json_string_length(v))
            return aa_error_set(err, AA_EINVAL, "executor", "must be \"local\" or \"slurm\"");
        env->slurm = !strcmp(s, "slurm");
    }
    json_t *copy = json_deep_copy(spec);
    if (!copy)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    json_object_del(copy, "kind");
    json_object_del(copy, "priority");
    json_object_del(copy, "visibility");
    json_object_del(copy, "pinned");
    json_object_del(copy, "label");
    json_object_del(copy, "executor");
    *kind_spec = copy;
    return AA_OK;
}

const char *job_envelope_visibility(const job_envelope *env)
{
    return env->private_job ? "private" : "team";
}

const char *job_envelope_executor(const job_envelope *env)
{
    return env->slurm ? "slurm" : "local";
}
