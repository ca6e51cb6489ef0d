/* Pieces the job result codecs share: E2 values that may be null (NaN), patterns, method
 * names, and the "best"/"e2" pair every optimizer result carries. */
#ifndef AALAB_PROTO_JOB_RESULT_UTIL_H
#define AALAB_PROTO_JOB_RESULT_UTIL_H

#include <jansson.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"

/* A number, or null for NaN (proto_real writes non-finite values as null). */
int proto_result_real(const json_t *obj, const char *key, double *out, aa_error *err);
int proto_result_integer(const json_t *obj, const char *key, long long *out, aa_error *err);
/* An encoded pattern at obj[key] (must be present unless optional; null counts as absent when
 * optional). *present tells whether one was decoded. */
int proto_result_pattern(const json_t *obj, const char *key, bool optional, aa_pattern *out,
                         bool *present, aa_error *err);
int proto_result_method(const json_t *obj, const char *key, aa_optimize_method *out, aa_error *err);

/* How an optimizer job ran (optimize, family-sweep, random-stats results): "executor" ("local"
 * or "slurm"), "shards" (the most shards a stage had) and "reproducible" (the budget did not
 * depend on the clock, so the result is the same for any number of shards or workers). */
typedef struct proto_run_info {
    char executor[8]; /* "" encodes as "local" */
    long shards;      /* 0 encodes as 1 */
    bool reproducible;
    /* The acuity table the job used ("acuity": {"name","version"} or {"name":"custom"}); name ""
     * (results stored before it was recorded) encodes nothing. */
    char acuity_name[24];
    int acuity_version; /* 0: custom */
} proto_run_info;
/* The run info of a finished job: executor, shards, reproducible, the acuity table (may be NULL).
 */
proto_run_info proto_run_info_make(const char *executor, size_t shards, bool reproducible,
                                   const aa_acuity *acuity);
/* Adds the keys to o (false when out of memory). */
bool proto_run_info_encode(json_t *o, const proto_run_info *ri);
/* The keys of a result; results stored before they existed lack them: local, 1 shard, not
 * reproducible, no acuity. */
int proto_run_info_decode(const json_t *obj, proto_run_info *out, aa_error *err);

#endif
