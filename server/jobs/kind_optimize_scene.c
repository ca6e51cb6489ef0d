/* The optimize kind's scene descent (kind_optimize_scene.h). */
#include "kind_optimize_scene.h"

#include <math.h>
#include <string.h>

#include "aa_optimizer.h"
#include "aa_render.h"
#include "codec.h"

typedef struct scene_bridge {
    const shard_ctx *ctx;
    double max_seconds;
    long max_iterations;
    double last_post;
} scene_bridge;

static int scene_progress(void *user, const aa_scene_progress *p)
{
    scene_bridge *b = user;
    double f = b->max_seconds > 0 ? p->seconds / b->max_seconds
                                  : (double)p->iterations / (double)b->max_iterations;
    json_t *best = NULL;
    /* The pattern JSON is the expensive part: at most 10 a second. p->scene is the exact
     * prediction (the objective's exact callback, aa_predict_rmse_of). */
    if (p->best && p->seconds - b->last_post >= 0.1) {
        b->last_post = p->seconds;
        json_t *pj = proto_encode_pattern(p->best);
        if (pj)
            best = json_pack("{s:o,s:o,s:o,s:o}", "pattern", pj, "e2", proto_real(p->e2),
                             "predicted_rmse", proto_real(p->scene), "objective",
                             proto_real(p->objective));
    }
    bool stop =
        b->ctx->progress && b->ctx->progress(b->ctx->user, 0.5 + 0.5 * fmin(fmax(f, 0), 1), best);
    json_decref(best);
    return stop;
}

int kind_optimize_scene_refine(const proto_optimize_spec *op, const aa_metric_params *metric,
                               const shard_ctx *ctx, double seconds, proto_optimize_result *out,
                               aa_error *err)
{
    aa_scene scene;
    aa_edge_histogram h;
    int rc = aa_scene_init(&scene, &op->objective.scene, err);
    if (!rc)
        rc = aa_edge_histogram_of_scene(&scene, &h, err);
    if (rc)
        return rc;
    aa_scene_objective o = {.filter = &op->common.filter,
                            .pixels = (double)h.width * (double)h.height};
    aa_edge_histogram_folded(&h, o.length);
    /* Reported and compared: the prediction with pixel-locked edges summed exactly. */
    aa_predict_target target = {o.filter, &h};
    o.exact = aa_predict_rmse_of;
    o.exact_user = &target;
    aa_prediction opt_pred;
    if ((rc = aa_predict_rmse(&out->best, o.filter, &h, &opt_pred, err)))
        return rc;
    aa_scene_optimize_params sp = {.blend = op->objective.blend};
    aa_optimize_params_default(&sp.local);
    sp.local.mode = op->common.mode;
    sp.local.max_iterations = op->common.max_iterations ? op->common.max_iterations : 20000;
    sp.local.max_seconds = seconds;
    sp.local.clock = ctx->clock;
    /* F = 1 at the global-E2 optimum: both terms relative to it. */
    sp.scene_ref = opt_pred.rmse;
    sp.e2_ref = out->e2;
    scene_bridge b = {ctx, seconds, sp.local.max_iterations, -1};
    aa_pattern best;
    aa_scene_optimize_result r;
    rc = aa_optimize_scene(&out->best, metric, &o, &sp, scene_progress, &b, &best, &r, err);
    if (rc) {
        aa_pattern_free(&best);
        return rc;
    }
    aa_evaluation ev; /* for the argmax; r.scene is already the exact prediction */
    if ((rc = aa_evaluate(&best, metric, &ev, err))) {
        aa_pattern_free(&best);
        return rc;
    }
    out->scene = (proto_scene_objective_result){.spec = op->objective,
                                                .objective = r.objective,
                                                .predicted_rmse = r.scene,
                                                .e2 = ev.e2,
                                                .optimum_predicted_rmse = opt_pred.rmse,
                                                .optimum_e2 = out->e2};
    out->e2 = out->e2_before_snap = ev.e2;
    out->argmax_kernel = (int)ev.argmax_kernel;
    out->argmax_angle_deg = ev.argmax_angle_deg;
    aa_evaluation_free(&ev);
    aa_pattern_free(&out->best);
    out->best = best;
    out->iterations += r.iterations;
    out->evaluations += r.evaluations;
    out->seconds += r.seconds;
    return AA_OK;
}
