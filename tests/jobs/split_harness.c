/* In-process split runs for the tests (split_harness.h). */
#include "split_harness.h"

#include <stdlib.h>

static bool quiet_progress(void *user, double fraction, json_t *best)
{
    (void)user;
    (void)fraction;
    (void)best;
    return false;
}

char *split_harness_text(const json_t *v)
{
    return json_dumps(v, JSON_COMPACT | JSON_ENCODE_ANY | JSON_REAL_PRECISION(17));
}

json_t *split_harness_reparse(const json_t *v)
{
    char *text = split_harness_text(v);
    json_error_t je;
    json_t *back = text ? json_loads(text, JSON_REJECT_DUPLICATES, &je) : NULL;
    free(text);
    return back;
}

void *split_harness_decode(const job_kind *kind, const char *spec_text)
{
    json_error_t je;
    json_t *spec = json_loads(spec_text, JSON_REJECT_DUPLICATES, &je);
    if (!spec)
        return NULL;
    void *params = NULL;
    aa_error err = {0};
    int rc = kind->decode(spec, &params, &err);
    json_decref(spec);
    return rc == AA_OK ? params : NULL;
}

json_t *split_harness_run(const job_kind *kind, void *params, size_t max_shards, int workers)
{
    const job_split *split = kind->split;
    shard_ctx ctx = {quiet_progress, NULL, NULL, {NULL, NULL}, workers};
    json_t *prior = NULL;
    size_t most = 0;
    aa_error err = {0};
    for (int stage = 0; stage < split->stages; stage++) {
        json_t *shards = NULL;
        if (split->plan(params, stage, prior, max_shards, &shards, &err))
            return NULL;
        size_t n = json_array_size(shards);
        most = n > most ? n : most;
        json_t **outputs = calloc(n, sizeof *outputs);
        int rc = AA_OK;
        for (size_t i = 0; !rc && i < n; i++) {
            json_t *out = NULL;
            rc =
                split->run_shard(params, stage, json_array_get(shards, i), prior, &ctx, &out, &err);
            outputs[i] = rc ? NULL : split_harness_reparse(out);
            json_decref(out);
        }
        json_t *merged = NULL;
        if (!rc)
            rc = split->merge(params, stage, outputs, n, prior, &merged, &err);
        for (size_t i = 0; i < n; i++)
            json_decref(outputs[i]);
        free(outputs);
        json_decref(shards);
        json_decref(prior);
        prior = rc ? NULL : split_harness_reparse(merged);
        json_decref(merged);
        if (rc)
            return NULL;
    }
    void *result = NULL;
    json_t *enc = NULL;
    if (!split->finish(params, prior, "slurm", most, &result, &err)) {
        enc = kind->encode_result(result);
        kind->free_result(result);
    }
    json_decref(prior);
    return enc;
}
