/* Job visibility checks (job_access.h). */
#include "job_access.h"

#include <string.h>

const char *job_visibility(const json_t *job)
{
    const json_t *v = json_object_get(job, JOB_VISIBILITY_KEY);
    if (!json_is_string(v))
        v = json_object_get(json_object_get(job, "spec"), JOB_VISIBILITY_KEY);
    return json_is_string(v) && !strcmp(json_string_value(v), "private") ? "private" : "team";
}

bool job_owned_by(const api_caller *caller, const json_t *job)
{
    if (caller->admin)
        return true;
    const json_t *owner = json_object_get(job, "owner_uid");
    return caller->uid >= 0 && json_is_integer(owner) && json_integer_value(owner) == caller->uid;
}

bool job_readable(const api_caller *caller, const json_t *job)
{
    return strcmp(job_visibility(job), "private") || job_owned_by(caller, job);
}

bool job_visibility_valid(const json_t *value)
{
    return !value || (json_is_string(value) && (!strcmp(json_string_value(value), "team") ||
                                                !strcmp(json_string_value(value), "private")));
}
