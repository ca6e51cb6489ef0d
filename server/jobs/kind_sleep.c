/* Job kind "sleep" (test only): waits the spec's seconds (0..3600) in 10 ms steps, reporting
 * progress and a synthetic trace, and stops promptly when cancelled. Harmless; exercises the
 * worker pool, persistence and cancellation end to end. With "fail":true it ends with an error
 * instead of a result; with a pattern, that pattern (validated and re-encoded) is its
 * best-so-far and result, so export and {"job": ID} references can be tested without the
 * optimizer. Spec and result: proto/job_sleep.h. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "codec.h"
#include "job_sleep.h"
#include "kinds.h"

JOB_KIND_SPEC_PARAMS(kind_sleep, proto_sleep_spec, proto_decode_sleep_spec, proto_sleep_spec_free)

static int sleep_run(void *params, job_ctx *ctx, proto_sleep_result *out, aa_error *err)
{
    const proto_sleep_spec *p = params;
    json_t *pattern = p->have_pattern ? proto_encode_pattern(&p->pattern) : NULL;
    if (p->have_pattern && !pattern)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    /* The job's clock: time paused for another user's job does not count as sleeping. */
    aa_clock clock = job_ctx_clock(ctx);
    double t0 = aa_clock_seconds(&clock);
    long steps = 0;
    int rc = AA_OK;
    for (;;) {
        double t = aa_clock_seconds(&clock) - t0;
        double frac = p->seconds > 0 ? fmin(1.0, t / p->seconds) : 1.0;
        json_t *best = json_pack("{s:f}", "elapsed", t);
        if (pattern)
            json_object_set(best, "pattern", pattern);
        bool stop = job_ctx_progress(ctx, frac, best);
        json_decref(best);
        job_trace_point pt = {t, steps, steps, 1.0 / (1.0 + (double)steps)};
        job_ctx_trace(ctx, &pt);
        if (stop) {
            rc = AA_ECANCELED;
            break;
        }
        if (t >= p->seconds)
            break;
        struct timespec d = {0, 10 * 1000 * 1000};
        nanosleep(&d, NULL);
        steps++;
    }
    json_decref(pattern);
    if (rc)
        return rc;
    if (p->fail)
        return aa_error_set(err, AA_EINVAL, "fail", "failed on request");
    out->slept_seconds = aa_clock_seconds(&clock) - t0;
    out->steps = steps;
    if (p->have_pattern) {
        if (aa_pattern_copy(&out->pattern, &p->pattern))
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        out->have_pattern = true;
    }
    return AA_OK;
}

JOB_KIND_RESULT(kind_sleep, proto_sleep_result, sleep_run, proto_encode_sleep_result,
                proto_sleep_result_free)

json_t *kind_sleep_best_of(const json_t *result, double *e2)
{
    *e2 = NAN;
    proto_sleep_result r;
    aa_error err = {0};
    if (proto_decode_sleep_result(result, &r, &err))
        return NULL;
    json_t *out = r.have_pattern ? proto_encode_pattern(&r.pattern) : NULL;
    proto_sleep_result_free(&r);
    return out;
}

/* The kind's row of the table of kinds (kind_list.h). */
JOB_KIND_ROW(sleep, .name = "sleep",
             .summary =
                 "Test kind: waits a given time, reporting progress, and returns an optional "
                 "pattern.",
             .test_only = true, .best_of = kind_sleep_best_of, .split = &kind_sleep_split);
