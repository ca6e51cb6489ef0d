#define _POSIX_C_SOURCE 200809L
#include "pattern_source.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "args.h"

bool pattern_argument_is_file(const char *arg)
{
    size_t n = strlen(arg);
    struct stat st;
    return strchr(arg, '/') || (n > 5 && strcmp(arg + n - 5, ".json") == 0) || stat(arg, &st) == 0;
}

int pattern_argument_load(const char *arg, json_t **pattern, json_t **extras, char *err,
                          size_t errcap)
{
    *pattern = NULL;
    if (extras)
        *extras = NULL;
    if (strncmp(arg, "job:", 4) == 0) { /* the best pattern of a job, resolved by the daemon */
        if (!job_id_valid(arg + 4)) {
            snprintf(err, errcap, "'%s': job:ID wants a job ID", arg);
            return -1;
        }
        *pattern = json_pack("{s:s}", "job", arg + 4);
        return *pattern ? 0 : -1;
    }
    if (!pattern_argument_is_file(arg)) {
        *pattern = json_pack("{s:s}", "preset", arg);
        return *pattern ? 0 : -1;
    }
    json_error_t jerr;
    json_t *doc = json_load_file(arg, JSON_REJECT_DUPLICATES, &jerr);
    if (!doc) {
        if (jerr.line > 0)
            snprintf(err, errcap, "%s:%d:%d: %s", arg, jerr.line, jerr.column, jerr.text);
        else
            snprintf(err, errcap, "%s: %s", arg, jerr.text);
        return -1;
    }
    if (!json_is_object(doc)) {
        snprintf(err, errcap, "%s: a pattern file holds a JSON object", arg);
        json_decref(doc);
        return -1;
    }
    json_t *inner = json_object_get(doc, "pattern");
    if (inner) { /* a saved request: {"pattern":P, "filter":..., ...} */
        if (!json_is_object(inner)) {
            snprintf(err, errcap, "%s: field pattern: expected an object", arg);
            json_decref(doc);
            return -1;
        }
        *pattern = json_incref(inner);
        json_object_del(doc, "pattern");
        /* `aalab export ID --format json` writes {"job":ID,"pattern":P}: the id is provenance,
         * not a request field. Anything else stays and the daemon judges it. */
        json_object_del(doc, "job");
        if (extras && json_object_size(doc) > 0)
            *extras = json_incref(doc);
        json_decref(doc);
    } else {
        *pattern = doc;
    }
    char why[400];
    if (pattern_check(*pattern, why, sizeof why)) {
        snprintf(err, errcap, "%s: %s", arg, why);
        json_decref(*pattern);
        *pattern = NULL;
        if (extras) {
            json_decref(*extras);
            *extras = NULL;
        }
        return -1;
    }
    return 0;
}
