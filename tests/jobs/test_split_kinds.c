/* The splittable kinds (optimize, family-sweep, random-stats, table3; job_split.h) with a
 * clock-free budget (max_iterations): one shard and several shards merge to the same result, bit
 * for bit (the encoded best pattern, E2 and per-seed / per-configuration rows), through JSON text
 * as the files between aalab-worker and the daemon carry it; the local run (job_split_local.c,
 * against a stub job context) gives that result too, says executor "local", 1 shard; "reproducible"
 * follows the budget. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "job_split.h"
#include "kinds.h"
#include "split_harness.h"

static const job_kind kinds[] = {
    {.name = "optimize",
     .decode = kind_optimize_decode,
     .free_params = kind_optimize_free,
     .run = kind_optimize_run,
     .encode_result = kind_optimize_encode_result,
     .free_result = kind_optimize_free_result,
     .split = &kind_optimize_split},
    {.name = "family-sweep",
     .decode = kind_family_sweep_decode,
     .free_params = kind_family_sweep_free,
     .run = kind_family_sweep_run,
     .encode_result = kind_family_sweep_encode_result,
     .free_result = kind_family_sweep_free_result,
     .split = &kind_family_sweep_split},
    {.name = "random-stats",
     .decode = kind_random_stats_decode,
     .free_params = kind_random_stats_free,
     .run = kind_random_stats_run,
     .encode_result = kind_random_stats_encode_result,
     .free_result = kind_random_stats_free_result,
     .split = &kind_random_stats_split},
    {.name = "table3",
     .decode = kind_table3_decode,
     .free_params = kind_table3_free,
     .run = kind_table3_run,
     .encode_result = kind_table3_encode_result,
     .free_result = kind_table3_free_result,
     .split = &kind_table3_split},
};

/* Stub context: the worker pool is not part of this test. */
struct job_ctx {
    double last_fraction;
    double last_trace_seconds;
    int trace_points;
    int cancel_after;          /* progress calls; 0: never */
    double cancel_at_fraction; /* the first call at or past it cancels; 0: never */
    int progress_calls;
    bool cancelled;
};

bool job_ctx_progress(job_ctx *ctx, double fraction, json_t *best_so_far)
{
    (void)best_so_far;
    assert_true(fraction >= 0 && fraction <= 1 + 1e-12);
    /* A job's progress never steps back, whatever its kind runs inside. */
    assert_true(fraction >= ctx->last_fraction - 1e-12);
    ctx->last_fraction = fraction;
    ctx->progress_calls++;
    if ((ctx->cancel_after && ctx->progress_calls >= ctx->cancel_after) ||
        (ctx->cancel_at_fraction > 0 && fraction >= ctx->cancel_at_fraction))
        ctx->cancelled = true;
    return ctx->cancelled;
}

void job_ctx_trace(job_ctx *ctx, const job_trace_point *point)
{
    /* One continuous line over the shards and stages. */
    assert_true(point->seconds >= ctx->last_trace_seconds - 1e-9);
    ctx->last_trace_seconds = point->seconds;
    ctx->trace_points++;
}

bool job_ctx_cancelled(const job_ctx *ctx)
{
    return ctx->cancelled;
}

int job_ctx_workers(const job_ctx *ctx)
{
    (void)ctx;
    return 2;
}

aa_clock job_ctx_clock(job_ctx *ctx)
{
    (void)ctx;
    return (aa_clock){NULL, NULL};
}

/* The kind's params from spec text; the test fails if the spec does not decode. */
static void *decode(const job_kind *k, const char *text)
{
    void *params = split_harness_decode(k, text);
    assert_non_null(params);
    return params;
}

/* The same key of two results, as text. */
static void same_key(const json_t *a, const json_t *b, const char *key)
{
    char *ta = split_harness_text(json_object_get(a, key));
    char *tb = split_harness_text(json_object_get(b, key));
    assert_non_null(ta);
    assert_non_null(tb);
    assert_string_equal(ta, tb);
    free(ta);
    free(tb);
}

/* Split with 1 shard and with `shards`, and the local run: the same result. */
static void check_kind(const job_kind *k, const char *spec, size_t shards, long want_shards,
                       const char *const *keys)
{
    void *params = decode(k, spec);
    json_t *one = split_harness_run(k, params, 1, 1);
    json_t *many = split_harness_run(k, params, shards, 2);
    assert_non_null(one);
    assert_non_null(many);
    assert_true(json_is_object(json_object_get(one, "best")));
    assert_true(json_is_number(json_object_get(one, "e2")));
    for (size_t i = 0; keys[i]; i++)
        same_key(one, many, keys[i]);
    assert_string_equal(json_string_value(json_object_get(many, "executor")), "slurm");
    assert_int_equal(json_integer_value(json_object_get(many, "shards")), want_shards);
    assert_true(json_is_true(json_object_get(many, "reproducible")));

    job_ctx ctx = {0};
    void *result = NULL;
    aa_error err = {0};
    assert_int_equal(k->run(params, &ctx, &result, &err), AA_OK);
    json_t *local = k->encode_result(result);
    k->free_result(result);
    for (size_t i = 0; keys[i]; i++)
        same_key(one, local, keys[i]);
    assert_string_equal(json_string_value(json_object_get(local, "executor")), "local");
    assert_int_equal(json_integer_value(json_object_get(local, "shards")), 1);
    assert_true(ctx.last_fraction > 0.99);
    assert_true(ctx.trace_points > 0);
    json_decref(one);
    json_decref(many);
    json_decref(local);
    k->free_params(params);
}

static void optimize_mirrored_splits_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "argmax", "per_seed", "seeds_run", NULL};
    check_kind(&kinds[0], "{\"family\":\"P(4,1+,1.5)\",\"seeds\":7,\"max_iterations\":60}", 3, 3,
               keys);
}

static void optimize_tiled_splits_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "argmax", "per_seed", NULL};
    check_kind(&kinds[0], "{\"family\":\"P(4,4,1)\",\"seeds\":4,\"max_iterations\":30}", 4, 4,
               keys);
}

static void optimize_pattern_splits_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "per_seed", NULL};
    check_kind(&kinds[0], "{\"pattern\":{\"preset\":\"rgss\"},\"max_iterations\":50}", 3, 1, keys);
}

static void family_sweep_splits_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "ranked", NULL};
    check_kind(&kinds[1], "{\"cost\":1.25,\"seeds_per_config\":2,\"max_iterations\":40}", 3, 3,
               keys);
}

static void random_stats_splits_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best",  "e2",     "random", "best_random",
                                       "opt_w", "opt_wp", NULL};
    check_kind(&kinds[2], "{\"family\":\"P(1,4,2)\",\"count\":50,\"max_iterations\":60}", 4, 4,
               keys);
}

/* Point-set figures per pattern (issue 31): computed per shard, ranked after the merge; the
 * split result, the one-shard result and the local run agree to the digit. */
static void random_stats_metrics_split_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "random", "point_metrics", NULL};
    const char *spec = "{\"family\":\"P(1,1,4)\",\"count\":40,\"max_iterations\":30,"
                       "\"metrics\":[\"mixture\",\"star_linf\",\"min_distance\","
                       "\"oscillation\"]}";
    check_kind(&kinds[2], spec, 3, 3, keys);
    void *params = decode(&kinds[2], spec);
    json_t *r = split_harness_run(&kinds[2], params, 3, 1);
    const json_t *pm = json_object_get(r, "point_metrics");
    assert_int_equal(json_array_size(json_object_get(pm, "spearman")), 4);
    const json_t *mix = json_array_get(json_object_get(pm, "spearman"), 0);
    assert_string_equal(json_string_value(json_object_get(mix, "metric")), "mixture");
    assert_int_equal(json_integer_value(json_object_get(mix, "n")), 40);
    /* the study's strongest figure: clearly positive for uniform P(1,1,4) (rho 0.88 at 1000) */
    assert_true(json_real_value(json_object_get(mix, "rho")) > 0.5);
    const json_t *cols = json_object_get(pm, "patterns");
    assert_int_equal(json_array_size(json_object_get(cols, "e2")), 40);
    assert_int_equal(json_array_size(json_object_get(cols, "star_linf")), 40);
    /* the pattern E2 column holds the random patterns' E2: its minimum is the table's min */
    double mn = INFINITY;
    for (size_t i = 0; i < 40; i++)
        mn = fmin(mn, json_real_value(json_array_get(json_object_get(cols, "e2"), i)));
    assert_true(mn == json_real_value(json_object_get(json_object_get(r, "random"), "min")));
    json_decref(r);
    kinds[2].free_params(params);
}

/* table3: one shard per seed whatever the executor's limit (a fixed number of parts). */
static void table3_splits_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "rows", "seeds", "acuity", NULL};
    check_kind(&kinds[3],
               "{\"family\":\"P(4,4,2)\",\"seeds\":3,\"count\":8,\"max_iterations\":30,"
               "\"distributions\":[\"poisson\",\"jittered\"]}",
               2, 3, keys);
}

/* table3 with figures: each row's rho over every seed's patterns, the same split or local. */
static void table3_metrics_split_alike(void **state)
{
    (void)state;
    static const char *const keys[] = {"best", "e2", "rows", NULL};
    const char *spec = "{\"family\":\"P(4,4,2)\",\"seeds\":3,\"count\":8,\"max_iterations\":30,"
                       "\"distributions\":[\"poisson\",\"uniform\"],"
                       "\"metrics\":[\"centered\",\"mean_nn_distance\"]}";
    check_kind(&kinds[3], spec, 2, 3, keys);
    void *params = decode(&kinds[3], spec);
    json_t *r = split_harness_run(&kinds[3], params, 2, 1);
    const json_t *rows = json_object_get(r, "rows");
    for (size_t i = 0; i < 2; i++) {
        const json_t *pm = json_object_get(json_array_get(rows, i), "point_metrics");
        const json_t *cd = json_array_get(json_object_get(pm, "spearman"), 0);
        assert_int_equal(json_integer_value(json_object_get(cd, "n")), 24); /* 3 seeds x 8 */
        assert_true(json_is_number(json_object_get(cd, "rho")));
        assert_int_equal(json_array_size(json_object_get(json_object_get(pm, "patterns"), "e2")),
                         24);
    }
    json_decref(r);
    kinds[3].free_params(params);
}

/* max_iterations alone: reproducible; with max_seconds: best effort. */
static void reproducible_follows_the_budget(void **state)
{
    (void)state;
    const char *specs[][2] = {
        {"{\"family\":\"P(1,1,2)\",\"seeds\":2,\"max_iterations\":30}", "true"},
        {"{\"family\":\"P(1,1,2)\",\"seeds\":2,\"max_iterations\":30,\"max_seconds\":20}", "false"},
    };
    for (size_t i = 0; i < 2; i++) {
        void *params = decode(&kinds[0], specs[i][0]);
        job_ctx ctx = {0};
        void *result = NULL;
        aa_error err = {0};
        assert_int_equal(kinds[0].run(params, &ctx, &result, &err), AA_OK);
        json_t *j = kinds[0].encode_result(result);
        assert_int_equal(json_is_true(json_object_get(j, "reproducible")),
                         !strcmp(specs[i][1], "true"));
        json_decref(j);
        kinds[0].free_result(result);
        kinds[0].free_params(params);
    }
}

/* A cancelled local run ends AA_ECANCELED without a result. */
static void local_run_cancels(void **state)
{
    (void)state;
    void *params =
        decode(&kinds[1], "{\"cost\":1.25,\"seeds_per_config\":2,\"max_iterations\":100000}");
    job_ctx ctx = {.cancel_after = 3};
    void *result = NULL;
    aa_error err = {0};
    assert_int_equal(kinds[1].run(params, &ctx, &result, &err), AA_ECANCELED);
    assert_null(result);
    kinds[1].free_params(params);
}

/* table3 runs a seed's distributions side by side when the shard has threads (the stub lends
 * 2): a cancel reaches every cell, however long its budget, and the run ends AA_ECANCELED
 * without a result. The cancel comes once both cells of the first seed are in their Opt W+P
 * (a cell's first 20 %, a seed's half of the job: 0.1), which searches for about 0.3 s here;
 * a count of calls raced the cells' 10 ms report interval (a fast machine finished the seed). */
static void table3_local_run_cancels(void **state)
{
    (void)state;
    void *params = decode(&kinds[3], "{\"family\":\"P(4,4,2)\",\"seeds\":2,\"count\":8,"
                                     "\"max_iterations\":10000000}");
    job_ctx ctx = {.cancel_at_fraction = 0.099};
    void *result = NULL;
    aa_error err = {0};
    assert_int_equal(kinds[3].run(params, &ctx, &result, &err), AA_ECANCELED);
    assert_null(result);
    assert_true(ctx.last_fraction < 0.5); /* stopped within the first seed */
    kinds[3].free_params(params);
}

/* Plans: at most max_shards contiguous ranges covering every seed once; random-stats' second
 * stage has its two fixed parts. */
static void plans_cover_the_range(void **state)
{
    (void)state;
    void *params = decode(&kinds[0], "{\"family\":\"P(1,1,2)\",\"seeds\":10}");
    json_t *shards = NULL;
    aa_error err = {0};
    assert_int_equal(kind_optimize_split.plan(params, 0, NULL, 4, &shards, &err), AA_OK);
    assert_int_equal(json_array_size(shards), 4);
    json_int_t next = 0;
    for (size_t i = 0; i < 4; i++) {
        json_t *s = json_array_get(shards, i);
        assert_int_equal(json_integer_value(json_object_get(s, "first")), next);
        next += json_integer_value(json_object_get(s, "count"));
    }
    assert_int_equal(next, 10);
    json_decref(shards);
    assert_int_equal(kind_optimize_split.plan(params, 0, NULL, 64, &shards, &err), AA_OK);
    assert_int_equal(json_array_size(shards), 10);
    json_decref(shards);
    kinds[0].free_params(params);
    params = decode(&kinds[2], "{\"family\":\"P(1,4,2)\",\"count\":5}");
    assert_int_equal(kind_random_stats_split.plan(params, 1, NULL, 1, &shards, &err), AA_OK);
    assert_int_equal(json_array_size(shards), 2);
    json_decref(shards);
    kinds[2].free_params(params);
}

/* Each stage's share of progress comes from the split's stage_weight: random-stats' random
 * patterns are the first 20 %, a one-stage kind is all of it, and the shares tile [0, 1]. */
static void stage_spans_tile_the_progress(void **state)
{
    (void)state;
    double base, span;
    job_split_stage_span(&kind_random_stats_split, 0, &base, &span);
    assert_float_equal(base, 0, 1e-15);
    assert_float_equal(span, 0.2, 1e-15);
    job_split_stage_span(&kind_random_stats_split, 1, &base, &span);
    assert_float_equal(base, 0.2, 1e-15);
    assert_float_equal(span, 0.8, 1e-15);
    const job_split *splits[] = {&kind_optimize_split, &kind_family_sweep_split,
                                 &kind_random_stats_split, &kind_table3_split};
    for (size_t k = 0; k < sizeof splits / sizeof splits[0]; k++) {
        assert_in_range(splits[k]->stages, 1, JOB_SPLIT_STAGES_MAX);
        double end = 0;
        for (int st = 0; st < splits[k]->stages; st++) {
            job_split_stage_span(splits[k], st, &base, &span);
            assert_float_equal(base, end, 1e-12);
            assert_true(span > 0);
            end = base + span;
        }
        assert_float_equal(end, 1, 1e-12);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(stage_spans_tile_the_progress),
        cmocka_unit_test(plans_cover_the_range),
        cmocka_unit_test(optimize_mirrored_splits_alike),
        cmocka_unit_test(optimize_tiled_splits_alike),
        cmocka_unit_test(optimize_pattern_splits_alike),
        cmocka_unit_test(family_sweep_splits_alike),
        cmocka_unit_test(random_stats_splits_alike),
        cmocka_unit_test(random_stats_metrics_split_alike),
        cmocka_unit_test(table3_splits_alike),
        cmocka_unit_test(table3_metrics_split_alike),
        cmocka_unit_test(reproducible_follows_the_budget),
        cmocka_unit_test(local_run_cancels),
        cmocka_unit_test(table3_local_run_cancels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
