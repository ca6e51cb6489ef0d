/* The functions of every job kind, one group per kind file (kind_<name>.c); job_kinds.c lists
 * them in the table of kinds. See job_kind.h for what each function does. */
#ifndef AALAB_KINDS_H
#define AALAB_KINDS_H

#include <stdlib.h>

#include "job_kind.h"

#define JOB_KIND_FUNCTIONS(prefix)                                                                 \
    int prefix##_decode(const json_t *spec, void **params, aa_error *err);                         \
    void prefix##_free(void *params);                                                              \
    int prefix##_run(void *params, job_ctx *ctx, json_t **result, aa_error *err)

JOB_KIND_FUNCTIONS(kind_optimize);
JOB_KIND_FUNCTIONS(kind_family_sweep);
JOB_KIND_FUNCTIONS(kind_random_stats);
JOB_KIND_FUNCTIONS(kind_compare);
JOB_KIND_FUNCTIONS(kind_animation);
JOB_KIND_FUNCTIONS(kind_reference_convergence);
JOB_KIND_FUNCTIONS(kind_sleep);

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

const char *kind_optimize_family(const void *params);
const char *kind_family_sweep_family(const void *params);
const char *kind_random_stats_family(const void *params);

json_t *kind_optimize_best_of(const json_t *result, double *e2);
json_t *kind_family_sweep_best_of(const json_t *result, double *e2);
json_t *kind_random_stats_best_of(const json_t *result, double *e2);
json_t *kind_sleep_best_of(const json_t *result, double *e2);

#endif
