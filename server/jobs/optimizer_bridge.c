/* Engine optimizer progress -> shard_ctx (optimizer_bridge.h). */
#include "optimizer_bridge.h"

#include <math.h>

#include "codec.h"

opt_bridge opt_bridge_make(const shard_ctx *ctx, double base, double span)
{
    return (opt_bridge){ctx, base, span, 0, 0, 0, INFINITY, -1, false};
}

int opt_bridge_progress(void *user, const aa_optimize_progress *p)
{
    opt_bridge *b = user;
    json_t *best = NULL;
    if (p->best_e2 < b->best_e2) {
        b->best_e2 = p->best_e2;
        job_trace_point tp = {b->seconds_before + p->seconds, b->iterations_before + p->iterations,
                              b->evaluations_before + p->evaluations, b->best_e2};
        if (b->ctx->trace)
            b->ctx->trace(b->ctx->user, &tp);
        /* The pattern JSON is the expensive part: at most 10 a second. */
        if (p->best && p->seconds - b->last_best_post >= 0.1) {
            b->last_best_post = p->seconds;
            json_t *pj = proto_encode_pattern(p->best);
            if (pj)
                best = json_pack("{s:o,s:o}", "pattern", pj, "e2", proto_real(p->best_e2));
        }
    }
    if (b->ctx->progress && b->ctx->progress(b->ctx->user, b->base + b->span * p->fraction, best))
        b->stopped = true;
    json_decref(best);
    return b->stopped;
}

void opt_bridge_add(opt_bridge *b, long iterations, long evaluations, double seconds)
{
    b->iterations_before += iterations;
    b->evaluations_before += evaluations;
    b->seconds_before += seconds;
}

void opt_bridge_end(opt_bridge *b)
{
    job_trace_point tp = {b->seconds_before, b->iterations_before, b->evaluations_before,
                          b->best_e2};
    if (b->ctx->trace)
        b->ctx->trace(b->ctx->user, &tp);
}

bool opt_bridge_report(opt_bridge *b, double fraction)
{
    if (b->ctx->progress && b->ctx->progress(b->ctx->user, fraction, NULL))
        b->stopped = true;
    return b->stopped;
}
