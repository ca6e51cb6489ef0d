/* The rows of the table of kinds (one per kind file, kind_<id>.c, listed in kind_list.h), the
 * macros the kind files build their functions with, and the functions of the kinds that tests
 * and other kind files use. See job_kind.h for what each function does. */
#ifndef AALAB_KINDS_H
#define AALAB_KINDS_H

#include <stdlib.h>

#include "job_kind.h"

/* The row of each kind, defined in its kind file. */
#define KIND(id) extern const job_kind job_kind_##id;
#include "kind_list.h"
#undef KIND

/* The five functions of a kind's row. A new kind's file declares its own
 * (JOB_KIND_FUNCTIONS(kind_<id>); above their definitions); the list below is of the kinds whose
 * functions the tests call directly (tests/jobs). */
#define JOB_KIND_FUNCTIONS(prefix)                                                                 \
    int prefix##_decode(const json_t *spec, void **params, aa_error *err);                         \
    void prefix##_free(void *params);                                                              \
    int prefix##_run(void *params, job_ctx *ctx, void **result, aa_error *err);                    \
    json_t *prefix##_encode_result(const void *result);                                            \
    void prefix##_free_result(void *result)

JOB_KIND_FUNCTIONS(kind_optimize);
JOB_KIND_FUNCTIONS(kind_family_sweep);
JOB_KIND_FUNCTIONS(kind_random_stats);
JOB_KIND_FUNCTIONS(kind_table3);
JOB_KIND_FUNCTIONS(kind_compare);
JOB_KIND_FUNCTIONS(kind_animation);
JOB_KIND_FUNCTIONS(kind_temporal_render);
JOB_KIND_FUNCTIONS(kind_reference_convergence);
JOB_KIND_FUNCTIONS(kind_sleep);
JOB_KIND_FUNCTIONS(kind_temporal_optimize);

/* decode and free of a kind whose spec is a proto struct `type` with a proto decoder and free:
 * the spec struct is the kind's params. */
#define JOB_KIND_SPEC_PARAMS(prefix, type, decode_fn, free_fn)                                     \
    int prefix##_decode(const json_t *spec, void **params, aa_error *err)                          \
    {                                                                                              \
        *params = NULL;                                                                            \
        type *s = calloc(1, sizeof *s);                                                            \
        if (!s)                                                                                    \
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");                              \
        int rc = decode_fn(spec, s, err);                                                          \
        if (rc) {                                                                                  \
            free(s);                                                                               \
            return rc;                                                                             \
        }                                                                                          \
        *params = s;                                                                               \
        return AA_OK;                                                                              \
    }                                                                                              \
    void prefix##_free(void *params)                                                               \
    {                                                                                              \
        if (params)                                                                                \
            free_fn(params);                                                                       \
        free(params);                                                                              \
    }

/* encode_result and free_result of a kind whose result is a malloc'd proto struct with a proto
 * encoder and free (the half JOB_KIND_RESULT and JOB_KIND_SPLIT_RESULT share). */
#define JOB_KIND_RESULT_CODEC(prefix, encode_fn, free_fn)                                          \
    json_t *prefix##_encode_result(const void *result)                                             \
    {                                                                                              \
        return encode_fn(result);                                                                  \
    }                                                                                              \
    void prefix##_free_result(void *result)                                                        \
    {                                                                                              \
        if (result)                                                                                \
            free_fn(result);                                                                       \
        free(result);                                                                              \
    }

/* run, encode_result and free_result of a kind whose result is a proto struct `type` with a proto
 * encoder and free; run_fn(params, ctx, type *out, err) fills a zeroed struct, and
 * prefix##_run hands it over on success. */
#define JOB_KIND_RESULT(prefix, type, run_fn, encode_fn, free_fn)                                  \
    int prefix##_run(void *params, job_ctx *ctx, void **result, aa_error *err)                     \
    {                                                                                              \
        *result = NULL;                                                                            \
        type *r = calloc(1, sizeof *r);                                                            \
        if (!r)                                                                                    \
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");                              \
        int rc = run_fn(params, ctx, r, err);                                                      \
        if (rc) {                                                                                  \
            prefix##_free_result(r);                                                               \
            return rc;                                                                             \
        }                                                                                          \
        *result = r;                                                                               \
        return AA_OK;                                                                              \
    }                                                                                              \
    JOB_KIND_RESULT_CODEC(prefix, encode_fn, free_fn)

/* run, encode_result and free_result of a kind that splits into shards (job_split.h): it runs
 * locally through job_split_run_local, and its result is the proto struct its split's finish
 * makes (encode_fn, free_fn). */
#define JOB_KIND_SPLIT_RESULT(prefix, split, encode_fn, free_fn)                                   \
    int prefix##_run(void *params, job_ctx *ctx, void **result, aa_error *err)                     \
    {                                                                                              \
        return job_split_run_local(&split, params, ctx, result, err);                              \
    }                                                                                              \
    JOB_KIND_RESULT_CODEC(prefix, encode_fn, free_fn)

/* A kind's row of the table (kind_list.h), from the names every kind file gives its functions
 * (prefix##_decode, _free, _run, _encode_result, _free_result); the rest of the row (at least
 * .name and .summary) follows as designated initializers. */
#define JOB_KIND_ROW(id, ...)                                                                      \
    const job_kind job_kind_##id = {.decode = kind_##id##_decode,                                  \
                                    .free_params = kind_##id##_free,                               \
                                    .run = kind_##id##_run,                                        \
                                    .encode_result = kind_##id##_encode_result,                    \
                                    .free_result = kind_##id##_free_result,                        \
                                    __VA_ARGS__}

/* The members of a row whose kind optimises a family's patterns: the family its spec names, its
 * time limit and its best pattern. */
#define JOB_KIND_FAMILY_MEMBERS(id)                                                                \
    .spec_family = kind_##id##_family, .max_seconds = kind_##id##_max_seconds,                     \
    .best_of = kind_##id##_best_of

/* How the optimizer kinds split into shards (job_split.h). */
struct job_split;
extern const struct job_split kind_optimize_split;
extern const struct job_split kind_family_sweep_split;
extern const struct job_split kind_random_stats_split;
extern const struct job_split kind_table3_split;

const char *kind_optimize_family(const void *params);
const char *kind_family_sweep_family(const void *params);
const char *kind_random_stats_family(const void *params);
const char *kind_table3_family(const void *params);

double kind_optimize_max_seconds(const void *params);
double kind_family_sweep_max_seconds(const void *params);
double kind_random_stats_max_seconds(const void *params);
double kind_table3_max_seconds(const void *params);

json_t *kind_optimize_best_of(const json_t *result, double *e2);
json_t *kind_family_sweep_best_of(const json_t *result, double *e2);
json_t *kind_random_stats_best_of(const json_t *result, double *e2);
json_t *kind_table3_best_of(const json_t *result, double *e2);
json_t *kind_sleep_best_of(const json_t *result, double *e2);
/* The temporal-optimize kind (kind_temporal_optimize.c): no split, one thread. */
const char *kind_temporal_optimize_family(const void *params);
double kind_temporal_optimize_max_seconds(const void *params);
json_t *kind_temporal_optimize_best_of(const json_t *result, double *e2);
/* The sleep kind's split (kind_sleep_split.c): the test kind the Slurm executor tests drive. */
extern const struct job_split kind_sleep_split;

#endif
