/* Envelope keys of a job submission (job_envelope.h). */
#include "job_envelope.h"

#include <string.h>

int job_envelope_take(const json_t *spec, job_envelope *env, json_t **rest, aa_error *err)
{
    *env = (job_envelope){.visibility = "team"};
    *rest = NULL;
    const json_t *v = json_object_get(spec, "visibility");
    if (v) {
        const char *s = json_string_value(v);
        if (s && !strcmp(s, "team") && json_string_length(v) == 4)
            env->visibility = "team";
        else if (s && !strcmp(s, "private") && json_string_length(v) == 7)
            env->visibility = "private";
        else
            return aa_error_set(err, AA_EINVAL, "visibility",
                                "visibility must be \"team\" or \"private\"");
    }
    v = json_object_get(spec, "pinned");
    if (v && !json_is_boolean(v))
        return aa_error_set(err, AA_EINVAL, "pinned", "pinned must be true or false");
    env->pinned = v && json_is_true(v);
    v = json_object_get(spec, "priority");
    if (v && !json_is_integer(v))
        return aa_error_set(err, AA_EINVAL, "priority", "priority must be an integer");
    if (v && (json_integer_value(v) < -10 || json_integer_value(v) > 10))
        return aa_error_set(err, AA_ERANGE, "priority", "priority must be in -10..10");
    env->priority = v ? (int)json_integer_value(v) : 0;
    /* A shallow copy: the kind only reads the values it shares with spec. */
    json_t *copy = json_copy((json_t *)spec);
    if (!copy)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    json_object_del(copy, "visibility");
    json_object_del(copy, "pinned");
    json_object_del(copy, "priority");
    *rest = copy;
    return AA_OK;
}
