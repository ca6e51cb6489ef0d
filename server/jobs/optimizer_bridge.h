/* Shared by the optimizer job kinds (optimize, family-sweep, random-stats): the bridge from the
 * engine's progress callback to job_ctx (progress, best-so-far, error-against-run-time trace,
 * cancellation). */
#ifndef AALAB_OPTIMIZER_BRIDGE_H
#define AALAB_OPTIMIZER_BRIDGE_H

#include <jansson.h>

#include "job_kind.h"
#include "aa_optimizer.h"

/* Engine progress -> job_ctx. base/span map the run's 0..1 onto the job's progress. */
typedef struct opt_job_bridge {
    job_ctx *ctx;
    double base, span;
    long iterations_before, evaluations_before;
    double seconds_before;
    double best_e2; /* over the whole job */
    double last_best_post;
} opt_job_bridge;
int opt_job_progress(void *user, const aa_optimize_progress *p);

#endif
