/* Engine optimizer progress -> job_ctx (optimizer_bridge.h). */
#include "optimizer_bridge.h"

#include "codec.h"

int opt_job_progress(void *user, const aa_optimize_progress *p)
{
    opt_job_bridge *b = user;
    json_t *best = NULL;
    bool better = p->best_e2 < b->best_e2;
    if (better) {
        b->best_e2 = p->best_e2;
        job_trace_point tp = {b->seconds_before + p->seconds, b->iterations_before + p->iterations,
                              b->evaluations_before + p->evaluations, b->best_e2};
        job_ctx_trace(b->ctx, &tp);
        /* The pattern JSON is the expensive part: at most 10 a second. */
        if (p->best && p->seconds - b->last_best_post >= 0.1) {
            b->last_best_post = p->seconds;
            json_t *pj = proto_encode_pattern(p->best);
            if (pj)
                best = json_pack("{s:o,s:o}", "pattern", pj, "e2", proto_real(p->best_e2));
        }
    }
    bool stop = job_ctx_progress(b->ctx, b->base + b->span * p->fraction, best);
    json_decref(best);
    return stop || job_ctx_cancelled(b->ctx);
}
