/* cluster_trace.h: every shard's points on one clock, sorted, swept once. */
#include "cluster_trace.h"

#include <math.h>
#include <stdlib.h>

typedef struct event {
    double t;
    size_t shard;
    long long iterations, evaluations;
    double best;
} event;

static int by_time(const void *a, const void *b)
{
    const event *x = a, *y = b;
    return x->t < y->t ? -1 : x->t > y->t ? 1 : (x->shard > y->shard) - (x->shard < y->shard);
}

json_t *cluster_trace_merge(json_t *const *traces, size_t n, double submitted_unix)
{
    size_t total = 0;
    for (size_t i = 0; i < n; i++)
        total += json_array_size(json_object_get(traces[i], "points"));
    event *ev = total ? malloc(total * sizeof *ev) : NULL;
    long long *iters = calloc(n ? n : 1, sizeof *iters);
    long long *evals = calloc(n ? n : 1, sizeof *evals);
    json_t *out = json_array();
    if ((total && !ev) || !iters || !evals || !out)
        goto fail;
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        json_t *started = json_object_get(traces[i], "started_unix");
        if (!json_is_number(started))
            continue;
        double offset = json_number_value(started) - submitted_unix;
        size_t k;
        json_t *p;
        json_array_foreach(json_object_get(traces[i], "points"), k, p)
        {
            json_t *s = json_object_get(p, "seconds"), *b = json_object_get(p, "best_e2");
            if (!json_is_number(s))
                continue;
            ev[m++] = (event){.t = offset + json_number_value(s),
                              .shard = i,
                              .iterations = json_integer_value(json_object_get(p, "iterations")),
                              .evaluations = json_integer_value(json_object_get(p, "evaluations")),
                              .best = json_is_number(b) ? json_number_value(b) : INFINITY};
        }
    }
    if (m)
        qsort(ev, m, sizeof *ev, by_time);
    double best = INFINITY;
    long long sum_i = 0, sum_e = 0;
    for (size_t k = 0; k < m; k++) {
        const event *e = &ev[k];
        sum_i += e->iterations - iters[e->shard];
        sum_e += e->evaluations - evals[e->shard];
        iters[e->shard] = e->iterations;
        evals[e->shard] = e->evaluations;
        if (!(e->best < best))
            continue;
        best = e->best;
        json_t *pt =
            json_pack("{s:f,s:I,s:I,s:f}", "seconds", e->t < 0 ? 0 : e->t, "iterations",
                      (json_int_t)sum_i, "evaluations", (json_int_t)sum_e, "best_e2", best);
        if (!pt || json_array_append_new(out, pt))
            goto fail;
    }
    free(ev);
    free(iters);
    free(evals);
    return out;
fail:
    free(ev);
    free(iters);
    free(evals);
    json_decref(out);
    return NULL;
}
