/* Job kind "sleep": {"kind":"sleep","seconds":S,"fail":bool?,"pattern":P?} waits S seconds
 * (0..3600) in 10 ms steps, reporting progress and a synthetic trace, and stops promptly when
 * cancelled. Harmless; exercises the worker pool, persistence and cancellation end to end.
 * With "fail":true it ends with an error instead of a result; with a pattern, that pattern
 * (validated and re-encoded) is its best-so-far and result, so export and {"job": ID}
 * references can be tested without the optimizer. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "codec.h"
#include "kinds.h"

typedef struct sleep_params {
    double seconds;
    bool fail;
    json_t *pattern; /* encoded, or NULL */
} sleep_params;

static const char *const spec_keys[] = {"seconds", "fail", "pattern", NULL};

int kind_sleep_decode(const json_t *spec, void **params, aa_error *err)
{
    int rc0 = proto_check_keys(spec, spec_keys, err, "");
    if (rc0)
        return rc0;
    json_t *v = json_object_get(spec, "seconds");
    if (!v)
        return aa_error_set(err, AA_EINVAL, "seconds", "seconds is required");
    if (!json_is_number(v))
        return aa_error_set(err, AA_EINVAL, "seconds", "must be a number");
    double s = json_number_value(v);
    if (!(s >= 0 && s <= 3600))
        return aa_error_set(err, AA_ERANGE, "seconds", "must be in 0..3600");
    v = json_object_get(spec, "fail");
    if (v && !json_is_boolean(v))
        return aa_error_set(err, AA_EINVAL, "fail", "must be true or false");
    json_t *encoded = NULL;
    const json_t *pj = json_object_get(spec, "pattern");
    if (pj) {
        aa_pattern pat;
        int rc = proto_decode_pattern(pj, 0, &pat, "pattern", err);
        if (rc)
            return rc;
        encoded = proto_encode_pattern(&pat);
        aa_pattern_free(&pat);
        if (!encoded)
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    sleep_params *p = malloc(sizeof *p);
    if (!p) {
        json_decref(encoded);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    p->seconds = s;
    p->fail = v && json_is_true(v);
    p->pattern = encoded;
    *params = p;
    return AA_OK;
}

JOB_KIND_JSON_RESULT(kind_sleep)

int kind_sleep_run(void *params, job_ctx *ctx, void **result, aa_error *err)
{
    const sleep_params *p = params;
    /* The job's clock: time paused for another user's job does not count as sleeping. */
    aa_clock clock = job_ctx_clock(ctx);
    double t0 = aa_clock_seconds(&clock);
    long steps = 0;
    for (;;) {
        double t = aa_clock_seconds(&clock) - t0;
        double frac = p->seconds > 0 ? fmin(1.0, t / p->seconds) : 1.0;
        json_t *best = json_pack("{s:f}", "elapsed", t);
        if (p->pattern)
            json_object_set(best, "pattern", p->pattern);
        bool stop = job_ctx_progress(ctx, frac, best);
        json_decref(best);
        job_trace_point pt = {t, steps, steps, 1.0 / (1.0 + (double)steps)};
        job_ctx_trace(ctx, &pt);
        if (stop)
            return AA_ECANCELED;
        if (t >= p->seconds)
            break;
        struct timespec d = {0, 10 * 1000 * 1000};
        nanosleep(&d, NULL);
        steps++;
    }
    if (p->fail)
        return aa_error_set(err, AA_EINVAL, "fail", "failed on request");
    *result = json_pack("{s:f,s:I}", "slept_seconds", aa_clock_seconds(&clock) - t0, "steps",
                        (json_int_t)steps);
    if (p->pattern)
        json_object_set(*result, "pattern", p->pattern);
    return AA_OK;
}

void kind_sleep_free(void *params)
{
    sleep_params *p = params;
    if (p)
        json_decref(p->pattern);
    free(p);
}

json_t *kind_sleep_best_of(const json_t *result, double *e2)
{
    *e2 = NAN;
    aa_pattern p;
    aa_error err = {0};
    const json_t *pj = json_object_get(result, "pattern");
    if (!pj || proto_decode_pattern(pj, 0, &p, "pattern", &err))
        return NULL;
    json_t *out = proto_encode_pattern(&p);
    aa_pattern_free(&p);
    return out;
}
