/* Runs a splittable kind (job_split.h) the way the executors do, in-process: every stage planned
 * with max_shards, every shard run with a quiet shard_ctx, each output passed through JSON text
 * (as the files between aalab-worker and the daemon carry it), merged, finished. Shared by the
 * kind tests (tests/jobs) and the worker tests (tests/worker). */
#ifndef AALAB_SPLIT_HARNESS_H
#define AALAB_SPLIT_HARNESS_H

#include <stddef.h>

#include <jansson.h>

#include "job_kind.h"
#include "job_split.h"

/* The kind's params decoded from a spec's JSON text; NULL if the text or the spec is invalid. */
void *split_harness_decode(const job_kind *kind, const char *spec_text);
/* The kind's encoded result ("slurm", shards = most shards of a stage); NULL on failure. */
json_t *split_harness_run(const job_kind *kind, void *params, size_t max_shards, int workers);
/* JSON text of v (compact, 17 significant digits), for exact comparisons; free() it. */
char *split_harness_text(const json_t *v);
/* The JSON value through text and back, as a file carries it. */
json_t *split_harness_reparse(const json_t *v);

#endif
