/* The split of the test-only "sleep" kind (job_split.h), so that the Slurm executor can be
 * driven end to end without the engine: at most 4 shards, each sleeping its part of the spec's
 * seconds; a shard's output is {"index", "steps", "e2": 1/(index+2)}; merge checks that the
 * outputs come in shard order and sums the steps. A fake worker (tests/cluster/fake_worker.py)
 * writes the same outputs. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "codec.h"
#include "job_sleep.h"
#include "job_split.h"
#include "kinds.h"

#define SLEEP_MAX_SHARDS 4

static int sleep_plan(const void *params, int stage, const json_t *prior, size_t max_shards,
                      json_t **shards, aa_error *err)
{
    (void)prior;
    const proto_sleep_spec *p = params;
    if (stage != 0)
        return aa_error_set(err, AA_EINVAL, "", "sleep has one stage");
    size_t n = max_shards < SLEEP_MAX_SHARDS ? max_shards : SLEEP_MAX_SHARDS;
    if (n < 1)
        n = 1;
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; i++)
        if (json_array_append_new(a, json_pack("{s:I,s:f}", "index", (json_int_t)i, "seconds",
                                               p->seconds / (double)n))) {
            json_decref(a);
            a = NULL;
        }
    if (!a)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    *shards = a;
    return AA_OK;
}

static int sleep_run_shard(const void *params, int stage, const json_t *shard, const json_t *prior,
                           const shard_ctx *ctx, json_t **output, aa_error *err)
{
    (void)stage;
    (void)prior;
    const proto_sleep_spec *p = params;
    json_int_t index;
    double seconds;
    if (json_unpack((json_t *)shard, "{s:I,s:F!}", "index", &index, "seconds", &seconds))
        return aa_error_set(err, AA_EINVAL, "shard", "not a sleep shard");
    double t0 = aa_clock_seconds(&ctx->clock);
    long steps = 0;
    for (;;) {
        double t = aa_clock_seconds(&ctx->clock) - t0;
        if (ctx->progress(ctx->user, seconds > 0 ? fmin(1.0, t / seconds) : 1.0, NULL))
            return AA_ECANCELED;
        job_trace_point pt = {t, steps, steps, 1.0 / (double)(index + 2)};
        ctx->trace(ctx->user, &pt);
        if (t >= seconds)
            break;
        struct timespec d = {0, 10 * 1000 * 1000};
        nanosleep(&d, NULL);
        steps++;
    }
    if (p->fail)
        return aa_error_set(err, AA_EINVAL, "fail", "failed on request");
    *output = json_pack("{s:I,s:I,s:f}", "index", index, "steps", (json_int_t)steps, "e2",
                        1.0 / (double)(index + 2));
    return *output ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

static int sleep_merge(const void *params, int stage, json_t *const *outputs, size_t count,
                       const json_t *prior, json_t **merged, aa_error *err)
{
    (void)params;
    (void)stage;
    (void)prior;
    json_int_t steps = 0;
    for (size_t i = 0; i < count; i++) {
        json_int_t index, s;
        double e2;
        if (json_unpack(outputs[i], "{s:I,s:I,s:F!}", "index", &index, "steps", &s, "e2", &e2))
            return aa_error_set(err, AA_EINVAL, "", "shard %zu: not a sleep output", i);
        /* The executors must hand the outputs over in shard order. */
        if (index != (json_int_t)i)
            return aa_error_set(err, AA_EINVAL, "", "output %zu is shard %lld's: out of order", i,
                                (long long)index);
        steps += s;
    }
    *merged = json_pack("{s:I,s:I}", "steps", steps, "shards", (json_int_t)count);
    return *merged ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

static int sleep_finish(const void *params, const json_t *merged, const char *executor,
                        size_t shards, void **result, aa_error *err)
{
    (void)executor;
    (void)shards;
    const proto_sleep_spec *p = params;
    json_int_t steps, count;
    if (json_unpack((json_t *)merged, "{s:I,s:I!}", "steps", &steps, "shards", &count))
        return aa_error_set(err, AA_EINVAL, "", "not a merged sleep state");
    proto_sleep_result *r = calloc(1, sizeof *r);
    if (!r)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    r->slept_seconds = p->seconds;
    r->steps = steps;
    if (p->have_pattern) {
        if (aa_pattern_copy(&r->pattern, &p->pattern)) {
            free(r);
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        }
        r->have_pattern = true;
    }
    *result = r;
    return AA_OK;
}

static json_t *sleep_best_of_output(const void *params, int stage, const json_t *output)
{
    (void)params;
    (void)stage;
    json_t *e2 = json_object_get(output, "e2");
    return json_is_number(e2) ? json_pack("{s:O}", "e2", e2) : NULL;
}

const job_split kind_sleep_split = {.stages = 1,
                                    .plan = sleep_plan,
                                    .run_shard = sleep_run_shard,
                                    .merge = sleep_merge,
                                    .finish = sleep_finish,
                                    .best_of_output = sleep_best_of_output};
