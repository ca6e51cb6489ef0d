/* aalab submit SPEC.json|- [--wait]: any job kind (optimize, family-sweep, random-stats, compare,
 * animation, reference-convergence, ...) from a JSON spec, as POST /v1/jobs takes it. */
#include "commands.h"

#include <string.h>

#include "../exit_codes.h"
#include "../pattern_source.h"

int submit_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_error_t jerr;
    const char *name = strcmp(a->target, "-") == 0 ? "stdin" : a->target;
    json_t *spec = strcmp(a->target, "-") == 0
                       ? json_loadf(stdin, JSON_REJECT_DUPLICATES, &jerr)
                       : json_load_file(a->target, JSON_REJECT_DUPLICATES, &jerr);
    *req = NULL;
    if (!spec) {
        snprintf(err, errcap, "%s:%d:%d: %s", name, jerr.line, jerr.column, jerr.text);
        return -1;
    }
    if (!json_is_object(spec) || !json_is_string(json_object_get(spec, "kind"))) {
        snprintf(err, errcap, "%s: a job spec is an object with a \"kind\"", name);
        json_decref(spec);
        return -1;
    }
    /* A pattern in the spec is checked like a pattern file ({"job":ID} is the daemon's, and so
     * is a temporal one: the codec decodes it only for the kinds that take it). */
    const json_t *pattern = json_object_get(spec, "pattern");
    char why[400];
    if (json_is_object(pattern) && !json_object_get(pattern, "job") &&
        !json_object_get(pattern, "temporal") && pattern_check(pattern, why, sizeof why)) {
        snprintf(err, errcap, "%s: %s", name, why);
        json_decref(spec);
        return -1;
    }
    *req = spec;
    return 0;
}

int cmd_submit(cli_session *s)
{
    return job_submit_built(s, "submit", submit_request);
}
