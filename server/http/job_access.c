/* Job visibility checks (job_access.h). */
#include "job_access.h"

#include <string.h>

bool job_access_check(job_store *st, const api_caller *caller, long long id, bool *owns)
{
    long long owner = -1;
    bool private_job = false;
    if (id <= 0 || !job_store_owner(st, id, &owner, NULL, &private_job))
        return false;
    bool owner_or_admin = caller->admin || (caller->uid >= 0 && owner == caller->uid);
    if (owns)
        *owns = owner_or_admin;
    return !private_job || owner_or_admin;
}

bool job_visibility_valid(const json_t *value)
{
    return !value || (json_is_string(value) && (!strcmp(json_string_value(value), "team") ||
                                                !strcmp(json_string_value(value), "private")));
}
