/* POST /v1/predict: the edge model's RMSE for one or more patterns on a scene, without
 * rendering (proto/codec_predict.h, server/engine/render/predict.h). Runs on the compute pool in
 * the caller's evaluate share, like POST /v1/evaluate (api_classify). Its work is bounded: the
 * scene's edge histogram (at most about 0.75 s for a 4096² checkerboard, 8 ms at 256², measured
 * on the 2-core build machine) plus kernel samples × angles with edges (plus all 180 with
 * e1_by_angle) × patterns, plus with "model" the g_θ tables (once per request, shared by the
 * patterns) and the segment sums per pattern, which is capped below. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "codec_predict.h"
#include "handlers.h"

/* The same budget as a synchronous evaluate: kernel samples x angles (E1 at one angle costs
 * about 70 ns per kernel sample, measured on the 2-core build machine). */
#define PREDICT_MAX_WORK (1L << 23)
/* The models' extra costs in those units, measured the same way: a g_θ table up to about 1 ms
 * (0.4-2 ms for a scene's 2-6 tables); a segment sum scans its bounding box at about 1 ns per pixel
 * and evaluates its pixels within a few px of the line at about 4 ns per kernel sample. */
#define PREDICT_TABLE_WORK 16384.0
#define PREDICT_SCAN_PER_WORK 64.0
#define PREDICT_BAND_PX 16.0

/* One pattern's segment sums: each segment's bounding box (plus its band) scanned, and the band's
 * pixels evaluated with up to every kernel sample. */
static double segments_work(const aa_edge_histogram *h, size_t samples)
{
    double work = 0;
    for (size_t k = 0; k < h->segment_count; k++) {
        const aa_edge_segment *g = &h->segment[k];
        double w = fmin(fabs(g->x1 - g->x0) + 1 + PREDICT_BAND_PX, h->width);
        double hh = fmin(fabs(g->y1 - g->y0) + 1 + PREDICT_BAND_PX, h->height);
        double len = hypot(g->x1 - g->x0, g->y1 - g->y0);
        work += w * hh / PREDICT_SCAN_PER_WORK + len * (double)samples;
    }
    return work;
}

static int check_work(const proto_predict_request *rq, const aa_edge_histogram *h, const bool *want,
                      aa_error *err)
{
    size_t angles = 0;
    for (int d = 0; d < AA_EDGE_BINS; d++)
        angles += h->length[d] > 0 || d == 0 || d == 90;
    if (rq->e1_by_angle)
        angles += AA_EDGE_BINS;
    double work = rq->model ? (double)aa_predict_tables_count(h, want) * PREDICT_TABLE_WORK : 0;
    for (size_t i = 0; i < rq->pattern_count; i++) {
        size_t samples = aa_pattern_total_kernel_samples(&rq->patterns[i]);
        work += (double)samples * (double)angles;
        if (rq->model & AA_PREDICT_SEGMENT_SUMS)
            work += segments_work(h, samples);
    }
    if (work <= (double)PREDICT_MAX_WORK)
        return AA_OK;
    return aa_error_set(err, AA_ERANGE, rq->single ? "pattern" : "patterns",
                        "%.0f units of work (kernel samples x angles, plus the %s model's tables "
                        "and sums) is more than a prediction does (%ld); send fewer or smaller "
                        "patterns",
                        work, proto_predict_model_name(rq->model), PREDICT_MAX_WORK);
}

void handle_predict(api_context *ctx, const api_request *req, api_response *resp)
{
    aa_error err = {0};
    json_t *body = api_request_body(ctx, req, resp, &err, NULL);
    if (!body)
        return;
    int rc = err.code;
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
    /* The model's g_θ tables, once per request and read-only across the patterns: the scene's
     * bins and segments, and every bin when E1 is wanted at every angle. */
    bool want[AA_EDGE_BINS];
    for (int d = 0; !rc && d < AA_EDGE_BINS; d++)
        want[d] = rq.e1_by_angle || h->length[d] > 0;
    if (!rc)
        rc = check_work(&rq, h, want, &err);
    aa_predict_tables *tables = NULL;
    if (!rc && rq.model)
        rc = aa_predict_tables_new(rq.reference.params.filter, h, want, &tables, &err);
    for (size_t i = 0; !rc && i < rq.pattern_count; i++) {
        char field[32];
        proto_predict_pattern_field(&rq, i, field, sizeof field);
        rc = aa_predict_rmse_tables(&rq.patterns[i], rq.reference.params.filter, h, rq.model,
                                    tables, &pred[i], &err);
        if (!rc && e1_by_angle)
            rc = aa_predict_e1_rms_tables(&rq.patterns[i], rq.reference.params.filter, NULL,
                                          rq.model, tables, e1_by_angle[i], &err);
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
    aa_predict_tables_free(tables);
    free(h);
    free(pred);
    free(e1_by_angle);
    proto_predict_request_free(&rq);
}
