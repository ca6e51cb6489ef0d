/* POST /v1/predict: the edge model's RMSE for one or more patterns on a scene, without
 * rendering (proto/codec_predict.h, server/engine/render/predict.h). Runs on the compute pool in
 * the caller's evaluate share, like POST /v1/evaluate (api_classify). Its work is bounded: the
 * scene's edge histogram (at most about 0.75 s for a 4096² checkerboard, 8 ms at 256², measured
 * on the 2-core build machine) plus kernel samples × angles with edges (plus all 180 with
 * e1_by_angle) × patterns, which is capped below. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_predict.h"
#include "handlers.h"

/* The same budget as a synchronous evaluate: kernel samples x angles. */
#define PREDICT_MAX_WORK (1L << 23)

static int check_work(const proto_predict_request *rq, const aa_edge_histogram *h, aa_error *err)
{
    size_t angles = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++)
        angles += h->length[d] > 0 || d == 0 || d == 90;
    if (rq->e1_by_angle)
        angles += AA_EDGE_BINS;
    double work = 0;
    for (size_t i = 0; i < rq->pattern_count; i++)
        work += (double)aa_pattern_total_kernel_samples(&rq->patterns[i]) * (double)angles;
    if (work <= (double)PREDICT_MAX_WORK)
        return AA_OK;
    return aa_error_set(err, AA_ERANGE, rq->single ? "pattern" : "patterns",
                        "%.0f kernel samples x angles is more than a prediction does (%ld); send "
                        "fewer or smaller patterns",
                        work, PREDICT_MAX_WORK);
}

void handle_predict(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *body = api_parse_body(req, resp);
    if (!body)
        return;
    aa_error err = {0};
    int rc = api_resolve_pattern_refs(ctx, &req->caller, body, &err);
    proto_predict_request rq;
    memset(&rq, 0, sizeof rq);
    if (!rc)
        rc = proto_decode_predict_request(body, &rq, &err);
    json_decref(body);
    aa_scene scene;
    aa_edge_histogram *h = NULL;
    aa_prediction *pred = NULL;
    double(*e1_by_angle)[AA_EDGE_BINS] = NULL;
    if (!rc)
        rc = aa_scene_init(&scene, &rq.scene, &err);
    if (!rc) {
        h = malloc(sizeof *h);
        pred = calloc(rq.pattern_count, sizeof *pred);
        if (rq.e1_by_angle)
            e1_by_angle = calloc(rq.pattern_count, sizeof *e1_by_angle);
        if (!h || !pred || (rq.e1_by_angle && !e1_by_angle))
            rc = aa_error_set(&err, AA_ENOMEM, "", "out of memory");
    }
    if (!rc)
        rc = aa_edge_histogram_of_scene(&scene, h, &err);
    if (!rc)
        rc = check_work(&rq, h, &err);
    for (size_t i = 0; !rc && i < rq.pattern_count; i++) {
        char field[32];
        proto_predict_pattern_field(&rq, i, field, sizeof field);
        rc = aa_predict_rmse(&rq.patterns[i], rq.reference.params.filter, h, &pred[i], &err);
        if (!rc && e1_by_angle)
            rc = aa_predict_e1_rms(&rq.patterns[i], rq.reference.params.filter, NULL,
                                   e1_by_angle[i], &err);
        if (rc) {
            snprintf(err.field, sizeof err.field, "%s", field);
        } else if (!isfinite(pred[i].rmse)) {
            /* E1 is finite only when every kernel's weights sum to 1 (docs/metric.md). */
            rc = aa_error_set(&err, AA_ERANGE, field,
                              "the error integral is infinite or overflows for this pattern "
                              "(every kernel's weights must sum to 1)");
        }
    }
    if (rc) {
        api_reply_aa_error(resp, &err);
    } else {
        json_t *out = proto_encode_predictions(&rq, h, pred, e1_by_angle);
        if (out) {
            api_reply_json(resp, 200, out);
        } else {
            aa_error_set(&err, AA_ENOMEM, "", "out of memory");
            api_reply_aa_error(resp, &err);
        }
    }
    free(h);
    free(pred);
    free(e1_by_angle);
    proto_predict_request_free(&rq);
}
