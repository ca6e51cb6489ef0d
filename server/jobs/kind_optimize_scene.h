/* The optimize kind's scene objective (issue 18 point 4): after the global-E2 search, a descent
 * on the blended scene objective (objective_scene.h) from its best pattern. A job with a scene
 * objective runs as one shard: F's references are the whole job's E2 optimum. */
#ifndef AALAB_KIND_OPTIMIZE_SCENE_H
#define AALAB_KIND_OPTIMIZE_SCENE_H

#include "aa_metric.h"
#include "job_optimize.h"
#include "job_split.h"

/* out holds the global-E2 search's result; on success its best, e2 and argmax become the scene
 * descent's and out->scene its figures; iterations, evaluations and seconds add up. The descent
 * reports progress on [0.5, 1] and the best so far with its predicted RMSE and objective.
 * seconds: its time budget (<= 0: none). AA_ECANCELED leaves out as the search left it. */
int kind_optimize_scene_refine(const proto_optimize_spec *op, const aa_metric_params *metric,
                               const shard_ctx *ctx, double seconds, proto_optimize_result *out,
                               aa_error *err);

#endif
