/* The optimize kind's scene objective on the wire (issue 18 point 4; engine:
 * server/engine/optimizer/objective_scene.h).
 * Spec: "objective": {"scene": name | {...} (the forms of POST /v1/render and /v1/predict),
 *                     "size": [w, h]?, "blend": α in [0, 1] (default 0)}.
 * Result: "scene_objective": {"scene", "blend", "objective", "predicted_rmse", "e2",
 *   "e2_optimum": {"predicted_rmse", "e2"}} — the best pattern's blended objective F, its edge
 * model RMSE on the scene (aa_predict_rmse) and its E2, beside the same figures of the job's best
 * global-E2 pattern (F's references: F = 1 there). */
#ifndef AALAB_PROTO_JOB_SCENE_OBJECTIVE_H
#define AALAB_PROTO_JOB_SCENE_OBJECTIVE_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_render.h"

typedef struct proto_scene_objective {
    bool enabled; /* "objective" given */
    aa_scene_params scene;
    double blend;
} proto_scene_objective;

/* Reads spec["objective"] (absent: enabled false). Errors name "objective",
 * "objective.scene...", "objective.size" or "objective.blend". */
int proto_decode_scene_objective(const json_t *spec, proto_scene_objective *out, aa_error *err);

typedef struct proto_scene_objective_result {
    proto_scene_objective spec;
    double objective, predicted_rmse, e2;
    double optimum_predicted_rmse, optimum_e2; /* of the best global-E2 pattern */
} proto_scene_objective_result;

json_t *proto_encode_scene_objective_result(const proto_scene_objective_result *r);
int proto_decode_scene_objective_result(const json_t *j, proto_scene_objective_result *out,
                                        aa_error *err);

#endif
