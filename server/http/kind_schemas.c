#include "kind_schemas.h"

#include <stdio.h>
#include <string.h>

#include "job_manager.h"
#include "schemas_embedded.h"

static const char *schema_text(const char *path)
{
    for (size_t i = 0; i < embedded_schema_count; i++)
        if (!strcmp(embedded_schemas[i].path, path))
            return embedded_schemas[i].text;
    return NULL;
}

static json_t *kind_schema_load(const char *path)
{
    const char *text = schema_text(path);
    return text ? json_loads(text, JSON_REJECT_DUPLICATES, NULL) : NULL;
}

static void kind_schema_path(char *out, size_t cap, const job_kind *kind, const char *what)
{
    snprintf(out, cap, "kinds/%s.%s.json", kind->name, what);
}

static int check_one(const char *path, aa_error *err)
{
    const char *text = schema_text(path);
    if (!text)
        return aa_error_set(err, AA_EINVAL, "", "proto/schemas/%s is missing from this build",
                            path);
    json_error_t je;
    json_t *j = json_loads(text, JSON_REJECT_DUPLICATES, &je);
    if (!json_is_object(j)) {
        json_decref(j);
        return aa_error_set(err, AA_EINVAL, "", "proto/schemas/%s is not a JSON object: %s", path,
                            je.text);
    }
    json_decref(j);
    return AA_OK;
}

int kind_schemas_check(aa_error *err)
{
    int rc = check_one("job_envelope.json", err);
    size_t count;
    const job_kind *const *table = job_kinds_table(&count);
    for (size_t k = 0; k < count && !rc; k++) {
        if (table[k]->test_only)
            continue;
        char path[128];
        kind_schema_path(path, sizeof path, table[k], "spec");
        rc = check_one(path, err);
        kind_schema_path(path, sizeof path, table[k], "result");
        if (!rc)
            rc = check_one(path, err);
    }
    return rc;
}

static json_t *kind_schemas_describe(const job_kind *kind)
{
    char path[128];
    kind_schema_path(path, sizeof path, kind, "spec");
    json_t *spec = kind_schema_load(path);
    kind_schema_path(path, sizeof path, kind, "result");
    json_t *result = kind_schema_load(path);
    json_t *examples = json_object_get(spec, "examples");
    return json_pack("{s:s,s:s,s:o,s:o,s:o}", "name", kind->name, "summary", kind->summary,
                     "spec_schema", spec ? spec : json_null(), "result_schema",
                     result ? result : json_null(), "examples",
                     json_is_array(examples) ? json_incref(examples) : json_array());
}

char *kind_schemas_document(struct job_manager *jobs)
{
    json_t *kinds = json_array();
    size_t count;
    const job_kind *const *table = job_kinds_table(&count);
    for (size_t k = 0; k < count; k++)
        if (job_manager_kind(jobs, table[k]->name))
            json_array_append_new(kinds, kind_schemas_describe(table[k]));
    json_t *envelope = kind_schema_load("job_envelope.json");
    json_t *doc = json_pack("{s:o,s:o}", "envelope_schema", envelope ? envelope : json_null(),
                            "kinds", kinds);
    char *text = doc ? json_dumps(doc, JSON_COMPACT) : NULL;
    json_decref(doc);
    return text;
}
