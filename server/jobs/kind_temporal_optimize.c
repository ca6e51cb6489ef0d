/* Job kind "temporal-optimize": the N offsets of a TAA jitter sequence optimised for the
 * worst-phase E2 (optionally + lambda F2) with the weights fixed by the blend, by the engine's
 * aa_temporal_optimize (docs/temporal.md section 7), from a family "T(N)" or a given sequence.
 * Progress, the best so far and the E2-against-time trace are posted after every seed; the
 * engine's progress callback also runs within seeds, so a cancel stops the job promptly. The
 * result's E2, mean over phases and F2 are POST /v1/evaluate's of the best sequence. One thread:
 * the seeds share a random stream (and hops start from the best so far), which keeps a
 * max_iterations run reproducible bit for bit. Spec and result: proto/job_temporal_optimize.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aa_temporal.h"
#include "codec.h"
#include "codec_temporal.h"
#include "job_temporal_optimize.h"
#include "kinds.h"

JOB_KIND_SPEC_PARAMS(kind_temporal_optimize, proto_temporal_optimize_spec,
                     proto_decode_temporal_optimize_spec, proto_temporal_optimize_spec_free)

double kind_temporal_optimize_max_seconds(const void *params)
{
    return ((const proto_temporal_optimize_spec *)params)->max_seconds;
}

const char *kind_temporal_optimize_family(const void *params)
{
    return ((const proto_temporal_optimize_spec *)params)->family;
}

json_t *kind_temporal_optimize_best_of(const json_t *result, double *e2)
{
    proto_temporal best;
    aa_error err = {0};
    *e2 = NAN;
    if (proto_decode_temporal_optimize_result(result, &best, e2, &err)) {
        proto_temporal_free(&best);
        return NULL;
    }
    json_t *out = proto_encode_temporal(&best);
    proto_temporal_free(&best);
    return out;
}

typedef struct run_state {
    job_ctx *ctx;
    const proto_temporal_optimize_spec *spec;
    proto_temporal_optimize_result *out;
    size_t cap;
    double posted_best;
    int rc; /* AA_ENOMEM while collecting */
} run_state;

/* The best so far as {"pattern", "e2"} for the job list. */
static json_t *best_so_far(const run_state *st, const aa_temporal_opt_progress *p)
{
    proto_temporal t = st->spec->temporal;
    t.jitter = (aa_point *)p->best;
    t.preset = t.source = NULL;
    json_t *pattern = proto_encode_temporal(&t);
    json_t *o =
        pattern ? json_pack("{s:o,s:o}", "pattern", pattern, "e2", proto_real(p->best_e2)) : NULL;
    return o;
}

static int on_progress(void *user, const aa_temporal_opt_progress *p)
{
    run_state *st = user;
    json_t *best = NULL;
    if (p->start >= 0) {
        proto_temporal_optimize_result *r = st->out;
        if (r->per_seed_count == st->cap) {
            size_t cap = st->cap ? 2 * st->cap : 64;
            proto_temporal_seed *a = realloc(r->per_seed, cap * sizeof *a);
            if (!a) {
                st->rc = AA_ENOMEM;
                return 1;
            }
            r->per_seed = a;
            st->cap = cap;
        }
        r->per_seed[r->per_seed_count++] =
            (proto_temporal_seed){p->start,       p->start_kind, p->start_initial_score,
                                  p->start_score, p->start_e2,   p->start_f2};
        if (p->best && p->best_score < st->posted_best) {
            st->posted_best = p->best_score;
            best = best_so_far(st, p);
        }
        job_trace_point pt = {p->seconds, p->starts, p->evaluations, p->best_e2};
        job_ctx_trace(st->ctx, &pt);
    }
    bool stop = job_ctx_progress(st->ctx, p->fraction, best);
    json_decref(best);
    return stop;
}

/* POST /v1/evaluate's figures of the best sequence. */
static int evaluate_best(const proto_temporal_optimize_spec *s, proto_temporal_optimize_result *r,
                         aa_error *err)
{
    aa_temporal t;
    aa_temporal_spec ts = proto_temporal_spec(&r->best);
    int rc = aa_temporal_build(&t, &ts, err);
    if (rc)
        return rc;
    aa_metric_params mp = proto_temporal_optimize_metric(s);
    aa_temporal_evaluation ev;
    rc = aa_temporal_evaluate(&t, &mp, r->best.cut_frames, &ev, err);
    if (!rc) {
        r->e2 = ev.e2;
        r->mean_phase_e2 = ev.mean_phase_e2;
        r->f2 = ev.f2;
        r->frames_to_settle = ev.frames_to_settle;
        r->phase_e2 = malloc(ev.phase_count * sizeof *r->phase_e2);
        if (r->phase_e2)
            memcpy(r->phase_e2, ev.phase_e2, ev.phase_count * sizeof *r->phase_e2);
        else
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        aa_temporal_evaluation_free(&ev);
    }
    aa_temporal_free(&t);
    return rc;
}

static int temporal_optimize_run(void *params, job_ctx *ctx, proto_temporal_optimize_result *r,
                                 aa_error *err)
{
    const proto_temporal_optimize_spec *s = params;
    aa_metric_params mp = proto_temporal_optimize_metric(s);
    r->start_e2 = NAN;
    memcpy(r->family, s->family, sizeof r->family);
    if (!s->have_family) {
        aa_temporal_spec ts = proto_temporal_spec(&s->temporal);
        int rc = aa_temporal_e2(ts.jitter, ts.count, ts.blend, ts.frame, ts.resolve, &mp,
                                &r->start_e2, err);
        if (rc)
            return rc;
    }
    int rc = proto_temporal_copy(&s->temporal, &r->best, err);
    if (rc)
        return rc;
    r->best.preset = r->best.source = NULL;
    run_state st = {.ctx = ctx, .spec = s, .out = r, .posted_best = INFINITY};
    aa_temporal_opt_params p = {.count = s->temporal.count,
                                .blend = s->temporal.blend,
                                .range = s->temporal.jitter_range,
                                .frame = s->temporal.has_frame ? &s->temporal.frame : NULL,
                                .resolve = s->temporal.has_resolve ? &s->temporal.resolve : NULL,
                                .metric = &mp,
                                .start = s->have_family ? NULL : s->temporal.jitter,
                                .max_starts = s->seeds,
                                .max_seconds = s->max_seconds,
                                .descent_steps = (int)s->max_iterations,
                                .grid_step = s->grid_bits ? ldexp(1, -s->grid_bits) : 0,
                                .flicker_weight = s->flicker_weight,
                                .flicker_cap = s->flicker_cap,
                                .seed = s->rng_seed,
                                .swap_sweeps = s->order_search ? 0 : -1,
                                .clock = job_ctx_clock(ctx),
                                .progress = on_progress,
                                .progress_user = &st};
    aa_temporal_opt_result res;
    rc = aa_temporal_optimize(&p, r->best.jitter, &res, err);
    if (rc == AA_ECANCELED && st.rc)
        rc = aa_error_set(err, st.rc, "", "out of memory");
    if (rc)
        return rc;
    r->score = res.score;
    r->flicker_weight = s->flicker_weight;
    r->flicker_cap = s->flicker_cap;
    r->grid_bits = s->grid_bits;
    r->seeds_run = res.starts;
    r->evaluations = res.evaluations;
    r->seconds = res.seconds;
    r->run = proto_run_info_make("local", 1, s->reproducible, &s->acuity);
    return evaluate_best(s, r, err);
}

JOB_KIND_RESULT(kind_temporal_optimize, proto_temporal_optimize_result, temporal_optimize_run,
                proto_encode_temporal_optimize_result, proto_temporal_optimize_result_free)
