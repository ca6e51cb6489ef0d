/* The trace of a Slurm job from its shards' trace files: best so far over all shards, by wall
 * time since the job's submission to Slurm; iterations and evaluations are the sums over the
 * shards of each shard's latest counts at that time. A point is kept where the best improves,
 * as the local trace does. */
#ifndef AALAB_CLUSTER_TRACE_H
#define AALAB_CLUSTER_TRACE_H

#include <stddef.h>

#include <jansson.h>

/* traces[i]: a trace file's JSON ({"started_unix","points":[...]}) or NULL (none yet; also
 * malformed ones are skipped). A new array of {"seconds","iterations","evaluations","best_e2"};
 * NULL when out of memory. */
json_t *cluster_trace_merge(json_t *const *traces, size_t n, double submitted_unix);

#endif
