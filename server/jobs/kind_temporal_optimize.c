/* Job kind "temporal-optimize": the N offsets of a TAA jitter sequence optimised for the
 * worst-phase E2 (optionally + lambda F2) with the weights fixed by the blend, by the engine's
 * aa_temporal_optimize (docs/temporal.md section 7), from a family "T(N)" or a given sequence.
 * Seed k is one start of the optimizer with its own random stream (seed 0 is the given sequence),
 * so seeds run in batches, one thread each where the pool's workers are idle, and the result,
 * merged in seed order, is the same for any batch size: a max_iterations run is reproducible bit
 * for bit. Progress, the best so far and the E2-against-time trace are posted after every batch;
 * the engine's progress callback also runs within the job thread's seed (and the job thread keeps
 * reporting while the batch's other seeds finish), so a cancel stops the job promptly. The
 * result's E2, mean over phases and F2 are POST /v1/evaluate's of the best sequence. Spec and
 * result: proto/job_temporal_optimize.h. */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

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

/* One seed of a batch (run_seed): seed k of the job is one start of the engine's optimizer
 * with its own random stream, so a batch's seeds are independent and the result does not
 * depend on how many run at once. */
typedef struct seed_task {
    const proto_temporal_optimize_spec *spec;
    const aa_metric_params *metric;
    job_ctx *ctx; /* item 0 only (the job's thread): progress and cancellation */
    double fraction_before, fraction_span;
    atomic_int *stop, *done;
    int batch;
    long seed;
    aa_clock clock;
    aa_point *offsets; /* [N] */
    aa_temporal_opt_result res;
    aa_temporal_opt_progress end; /* the seed's own figures */
    int rc;
    aa_error err;
} seed_task;

static uint64_t seed_stream(uint64_t rng_seed, uint64_t k)
{
    /* splitmix64 of the pair: neighbouring seeds get unrelated streams. */
    uint64_t z = rng_seed * 0x9E3779B97F4A7C15u + k + 1;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

static int seed_progress(void *user, const aa_temporal_opt_progress *p)
{
    seed_task *t = user;
    if (p->start >= 0)
        t->end = *p;
    if (t->ctx &&
        job_ctx_progress(t->ctx, t->fraction_before + t->fraction_span * p->fraction, NULL))
        atomic_store(t->stop, 1);
    return atomic_load(t->stop);
}

static void run_seed(void *item)
{
    seed_task *t = item;
    const proto_temporal_optimize_spec *s = t->spec;
    aa_temporal_opt_params p = {.count = s->temporal.count,
                                .blend = s->temporal.blend,
                                .range = s->temporal.jitter_range,
                                .frame = s->temporal.has_frame ? &s->temporal.frame : NULL,
                                .resolve = s->temporal.has_resolve ? &s->temporal.resolve : NULL,
                                .metric = t->metric,
                                .start =
                                    t->seed == 0 && !s->have_family ? s->temporal.jitter : NULL,
                                .max_starts = 1,
                                .descent_steps = (int)s->max_iterations,
                                .grid_step = s->grid_bits ? ldexp(1, -s->grid_bits) : 0,
                                .flicker_weight = s->flicker_weight,
                                .flicker_cap = s->flicker_cap,
                                .seed = seed_stream(s->rng_seed, (uint64_t)t->seed),
                                .swap_sweeps = s->order_search ? 0 : -1,
                                .clock = t->clock,
                                .progress = seed_progress,
                                .progress_user = t};
    t->rc = aa_temporal_optimize(&p, t->offsets, &t->res, &t->err);
    atomic_fetch_add(t->done, 1);
    /* The job's thread keeps reporting (and noticing a cancel) while the others finish. */
    while (t->ctx && atomic_load(t->done) < t->batch) {
        if (job_ctx_progress(t->ctx, t->fraction_before, NULL))
            atomic_store(t->stop, 1);
        struct timespec d = {0, 20 * 1000 * 1000};
        nanosleep(&d, NULL);
    }
}

#define MAX_BATCH 8

/* The best so far as {"pattern", "e2"} for the job list. */
static json_t *best_so_far(const proto_temporal *setting, const aa_point *best, double e2)
{
    proto_temporal t = *setting;
    t.jitter = (aa_point *)best;
    t.preset = t.source = NULL;
    json_t *pattern = proto_encode_temporal(&t);
    return pattern ? json_pack("{s:o,s:o}", "pattern", pattern, "e2", proto_real(e2)) : NULL;
}

/* Appends the seed's row to the result's table. */
static int add_row(proto_temporal_optimize_result *r, size_t *cap, const seed_task *t)
{
    if (r->per_seed_count == *cap) {
        size_t n = *cap ? 2 * *cap : 64;
        proto_temporal_seed *a = realloc(r->per_seed, n * sizeof *a);
        if (!a)
            return AA_ENOMEM;
        r->per_seed = a;
        *cap = n;
    }
    r->per_seed[r->per_seed_count++] = (proto_temporal_seed){t->seed,
                                                             t->end.start_from == 0 ? 0 : 1,
                                                             t->end.start_initial_score,
                                                             t->end.start_score,
                                                             t->end.start_e2,
                                                             t->end.start_f2};
    return AA_OK;
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
    size_t N = s->temporal.count;
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
    seed_task tasks[MAX_BATCH];
    aa_point *offsets = malloc(MAX_BATCH * N * sizeof *offsets);
    if (!offsets)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    aa_clock clock = job_ctx_clock(ctx);
    double t0 = aa_clock_seconds(&clock), best_score = INFINITY, best_e2 = INFINITY;
    atomic_int stop = 0;
    size_t cap = 0;
    long next = 0;
    while (!rc && next < s->seeds) {
        double elapsed = aa_clock_seconds(&clock) - t0;
        if (s->max_seconds > 0 && next > 0 && elapsed >= s->max_seconds)
            break;
        /* Seeds in batches, one thread each where workers are idle (job_ctx_workers). */
        long w = job_ctx_workers(ctx);
        w = w < 1 ? 1 : w > MAX_BATCH ? MAX_BATCH : w;
        w = w > s->seeds - next ? s->seeds - next : w;
        double done = (double)next / (double)s->seeds;
        double by_time = s->max_seconds > 0 ? elapsed / s->max_seconds : 0;
        atomic_int finished = 0;
        for (long k = 0; k < w; k++)
            tasks[k] = (seed_task){.spec = s,
                                   .metric = &mp,
                                   .ctx = k == 0 ? ctx : NULL,
                                   .fraction_before = fmax(done, by_time),
                                   .fraction_span = (double)w / (double)s->seeds,
                                   .stop = &stop,
                                   .done = &finished,
                                   .batch = (int)w,
                                   .seed = next + k,
                                   .clock = clock,
                                   .offsets = offsets + k * N};
        aa_fork_join(tasks, sizeof *tasks, (int)w, run_seed);
        if (atomic_load(&stop)) {
            rc = AA_ECANCELED;
            break;
        }
        /* Merged in seed order (a tie keeps the lower seed): any batch size, one result. */
        json_t *best = NULL;
        for (long k = 0; k < w && !rc; k++) {
            seed_task *t = &tasks[k];
            if (t->rc) {
                *err = t->err;
                rc = t->rc;
                break;
            }
            r->evaluations += t->res.evaluations;
            if (add_row(r, &cap, t))
                rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
            if (t->res.score < best_score) {
                best_score = t->res.score;
                best_e2 = t->res.e2;
                memcpy(r->best.jitter, t->offsets, N * sizeof *t->offsets);
                json_decref(best);
                best = best_so_far(&s->temporal, r->best.jitter, best_e2);
            }
        }
        next += w;
        r->seeds_run = next;
        elapsed = aa_clock_seconds(&clock) - t0;
        job_trace_point pt = {elapsed, next, r->evaluations, best_e2};
        job_ctx_trace(ctx, &pt);
        double fraction = fmax((double)next / (double)s->seeds,
                               s->max_seconds > 0 ? elapsed / s->max_seconds : 0);
        if (!rc && job_ctx_progress(ctx, fmin(1, fraction), best))
            rc = AA_ECANCELED;
        json_decref(best);
    }
    free(offsets);
    if (rc)
        return rc;
    r->score = best_score;
    r->flicker_weight = s->flicker_weight;
    r->flicker_cap = s->flicker_cap;
    r->grid_bits = s->grid_bits;
    r->seconds = aa_clock_seconds(&clock) - t0;
    r->run = proto_run_info_make("local", 1, s->reproducible, &s->acuity);
    return evaluate_best(s, r, err);
}

JOB_KIND_RESULT(kind_temporal_optimize, proto_temporal_optimize_result, temporal_optimize_run,
                proto_encode_temporal_optimize_result, proto_temporal_optimize_result_free)

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(temporal_optimize, .name = "temporal-optimize",
             .summary =
                 "Multi-start optimisation of a TAA jitter sequence (a family T(N), or a given "
                 "temporal pattern) for the smallest worst-phase E2, optionally plus lambda F2.",
             JOB_KIND_FAMILY_MEMBERS(temporal_optimize));
