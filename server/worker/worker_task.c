/* Reading and validating TASK.json (worker_task.h). */
#include "worker_task.h"

#include <stdio.h>
#include <string.h>

#include "job_split.h"

static int absolute_path(const char *p, const char *field, aa_error *err)
{
    if (!p[0] || p[0] != '/')
        return aa_error_set(err, AA_EINVAL, field, "must be an absolute path");
    return AA_OK;
}

static const char *const keys[] = {"format", "job_id",      "kind",  "spec",   "stage",
                                   "shard",  "shard_index", "prior", "output", "trace"};
#define KEY_COUNT (sizeof keys / sizeof keys[0])

/* Every key present, none other: the message names the first that is not. */
static int check_keys(const json_t *root, aa_error *err)
{
    if (!json_is_object(root))
        return aa_error_set(err, AA_EINVAL, "", "the task must be a JSON object");
    const char *key;
    json_t *v;
    json_object_foreach((json_t *)root, key, v)
    {
        size_t i = 0;
        while (i < KEY_COUNT && strcmp(keys[i], key))
            i++;
        if (i == KEY_COUNT)
            return aa_error_set(err, AA_EINVAL, key, "unknown key");
    }
    for (size_t i = 0; i < KEY_COUNT; i++)
        if (!json_object_get(root, keys[i]))
            return aa_error_set(err, AA_EINVAL, keys[i], "missing");
    return AA_OK;
}

static int get_value(const json_t *root, const char *key, json_t **out, aa_error *err)
{
    *out = json_object_get(root, key);
    return *out ? AA_OK : aa_error_set(err, AA_EINVAL, key, "missing");
}

static int get_string(const json_t *root, const char *key, const char **out, aa_error *err)
{
    json_t *v = json_object_get(root, key);
    json_error_t je;
    if (json_unpack_ex(v, &je, JSON_STRICT, "s", out))
        return aa_error_set(err, AA_EINVAL, key, "must be a string");
    return AA_OK;
}

static int get_integer(const json_t *root, const char *key, json_int_t *out, aa_error *err)
{
    json_t *v = json_object_get(root, key);
    json_error_t je;
    if (json_unpack_ex(v, &je, JSON_STRICT, "I", out))
        return aa_error_set(err, AA_EINVAL, key, "must be an integer");
    return AA_OK;
}

int worker_task_load(const char *path, worker_task *t, aa_error *err)
{
    memset(t, 0, sizeof *t);
    json_error_t je;
    json_t *root = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
    if (!root)
        return aa_error_set(err, AA_EINVAL, "", "%s: line %d: %s", path, je.line, je.text);
    const char *format = NULL, *kind = NULL, *output = NULL, *trace = NULL;
    json_int_t job_id = -1, stage = -1, shard_index = -1;
    json_t *spec = NULL, *shard = NULL, *prior = NULL;
    int rc = check_keys(root, err);
    if (!rc)
        rc = get_string(root, "format", &format, err);
    if (!rc)
        rc = get_integer(root, "job_id", &job_id, err);
    if (!rc)
        rc = get_string(root, "kind", &kind, err);
    if (!rc)
        rc = get_value(root, "spec", &spec, err);
    if (!rc)
        rc = get_integer(root, "stage", &stage, err);
    if (!rc)
        rc = get_integer(root, "shard_index", &shard_index, err);
    if (!rc)
        rc = get_value(root, "shard", &shard, err);
    if (!rc)
        rc = get_value(root, "prior", &prior, err);
    if (!rc)
        rc = get_string(root, "output", &output, err);
    if (!rc)
        rc = get_string(root, "trace", &trace, err);
    if (!rc && strcmp(format, "aalab-task/1"))
        rc = aa_error_set(err, AA_EINVAL, "format", "must be \"aalab-task/1\"");
    if (!rc && job_id < 0)
        rc = aa_error_set(err, AA_EINVAL, "job_id", "must be a non-negative integer");
    if (!rc) {
        t->kind = job_kind_find(kind);
        if (!t->kind || !t->kind->split)
            rc = aa_error_set(err, AA_EINVAL, "kind",
                              "\"%s\" is not a kind that splits into shards", kind);
    }
    if (!rc && !json_is_object(spec))
        rc = aa_error_set(err, AA_EINVAL, "spec", "must be an object");
    if (!rc && (stage < 0 || stage >= t->kind->split->stages))
        rc = aa_error_set(err, AA_EINVAL, "stage", "must be 0..%d for %s",
                          t->kind->split->stages - 1, kind);
    if (!rc && shard_index < 0)
        rc = aa_error_set(err, AA_EINVAL, "shard_index", "must be a non-negative integer");
    if (!rc && !json_is_null(prior) && !json_is_object(prior))
        rc = aa_error_set(err, AA_EINVAL, "prior", "must be an object or null");
    if (!rc && stage > 0 && json_is_null(prior))
        rc =
            aa_error_set(err, AA_EINVAL, "prior", "stage %lld needs the merged state of stage %lld",
                         (long long)stage, (long long)stage - 1);
    if (!rc)
        rc = absolute_path(output, "output", err);
    if (!rc)
        rc = absolute_path(trace, "trace", err);
    if (!rc && !strcmp(output, trace))
        rc = aa_error_set(err, AA_EINVAL, "trace", "must differ from output");
    if (!rc) {
        rc = t->kind->decode(spec, &t->params, err);
        if (rc) {
            /* The kind names its field relative to the spec. */
            char field[sizeof err->field + 8] = {0};
            snprintf(field, sizeof field, "spec%s%s", err->field[0] ? "." : "", err->field);
            memcpy(err->field, field, sizeof err->field - 1);
            err->field[sizeof err->field - 1] = 0;
        }
    }
    if (rc) {
        json_decref(root);
        memset(t, 0, sizeof *t);
        return rc;
    }
    t->root = root;
    t->job_id = job_id;
    t->stage = (int)stage;
    t->shard_index = shard_index;
    t->shard = shard;
    t->prior = json_is_null(prior) ? NULL : prior;
    t->output = output;
    t->trace = trace;
    return AA_OK;
}

void worker_task_free(worker_task *t)
{
    if (t->kind && t->params)
        t->kind->free_params(t->params);
    json_decref(t->root);
    memset(t, 0, sizeof *t);
}
