/* Shared by the optimizer job kinds (optimize, family-sweep, random-stats): the bridge from the
 * engine's progress callback to the shard context a shard runs under (progress, best so far,
 * error-against-run-time trace, cancellation), whether the shard runs in the daemon or in
 * aalab-worker. */
#ifndef AALAB_OPTIMIZER_BRIDGE_H
#define AALAB_OPTIMIZER_BRIDGE_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_optimizer.h"
#include "job_split.h"

/* Engine progress -> shard_ctx. base/span map a run's 0..1 onto the shard's progress; the
 * *_before counts carry a shard's earlier runs (several configurations, refinement) so its
 * trace is one continuous line. */
typedef struct opt_bridge {
    const shard_ctx *ctx;
    double base, span;
    long iterations_before, evaluations_before;
    double seconds_before;
    double best_e2; /* over the whole shard */
    double last_best_post;
    bool stopped; /* ctx said stop */
} opt_bridge;

/* A bridge for ctx covering the shard's progress [base, base + span]. */
opt_bridge opt_bridge_make(const shard_ctx *ctx, double base, double span);
/* The engine callback (user: the opt_bridge). */
int opt_bridge_progress(void *user, const aa_optimize_progress *p);
/* Adds a finished run's work to the counts the next run's points start from. */
void opt_bridge_add(opt_bridge *b, long iterations, long evaluations, double seconds);
/* The shard's last trace point: its total work and best E2 when it ends (the executors
 * continue the next shard's trace from it). */
void opt_bridge_end(opt_bridge *b);
/* Reports fraction (and no new best) to the shard; true when it must stop. */
bool opt_bridge_report(opt_bridge *b, double fraction);

#endif
