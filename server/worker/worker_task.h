/* TASK.json of aalab-worker: one shard of a job, written by the daemon's Slurm driver
 * (docs/cluster.md):
 * {"format":"aalab-task/1","job_id":N,"kind":"optimize","spec":{the kind's spec, without the
 *  envelope},"stage":s,"shard_index":i,"shard":<descriptor>,"prior":<merged state or null>,
 *  "output":"/abs/output-i.json","trace":"/abs/trace-i.json"} */
#ifndef AALAB_WORKER_TASK_H
#define AALAB_WORKER_TASK_H

#include <jansson.h>

#include "aa_core.h"
#include "job_kind.h"

typedef struct worker_task {
    json_t *root; /* owns the JSON below */
    long long job_id;
    const job_kind *kind; /* one with a split */
    void *params;         /* the decoded spec (kind->free_params) */
    int stage;
    long long shard_index;
    const json_t *shard;
    const json_t *prior; /* NULL for null */
    const char *output, *trace;
} worker_task;

/* Reads and validates path; on error err names the field (e.g. "spec.seeds") and nothing is
 * left to free. */
int worker_task_load(const char *path, worker_task *task, aa_error *err);
void worker_task_free(worker_task *task);

#endif
