/* Iterated local search for tile patterns (optimizer.h, aa_optimize_perturbed). The L&A
 * descent stops at kinks of the max long before a good optimum of the large families (P(16,16,4)
 * from a Poisson seed: 0.199 after ~4 s, then no accepted step). Jittering the positions of the
 * local optimum by a small fraction of a pixel, resetting the weights to the filter's impulse
 * response and descending again moves to a neighbouring basin; keeping only improvements, 60 s of
 * such rounds reach 0.177 where 60 s of fresh seeds stay near 0.19. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "optimizer.h"
#include "optimizer_perturb.h"
#include "optimizer_run.h"

/* A standard normal deviate (Box-Muller; u1 in (0, 1]). */
static double normal_deviate(aa_rng *rng)
{
    double u1 = 1.0 - aa_rng_uniform(rng), u2 = aa_rng_uniform(rng);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

void aa_perturb_params_default(aa_perturb_params *pp)
{
    *pp = (aa_perturb_params){0, 0.01, 30, 0, 0, 0, false};
}

bool aa_family_perturbable(const aa_family *f)
{
    return f->tile > 1 && !f->border;
}

bool aa_pattern_tiled_without_border(const aa_pattern *p)
{
    return p->form == AA_FORM_TILE && p->tile > 1 && !p->border;
}

bool aa_perturbable(const aa_pattern *p)
{
    /* Border samples sit on edges and corners; moving them would change the family. */
    return p->form == AA_FORM_TILE && p->tile_count > 0 && !p->border;
}

/* x moved by d and kept `margin` inside the pixel it lands in (aa_pattern_from_tile wraps it
 * into the tile). A sample may leave its pixel: the descent keeps each sample inside its pixel
 * (crossing an edge changes the kernels that read it, a jump in E2), so only these moves change
 * how many samples each pixel holds. Letting them do so lowered the search's end points
 * (docs/optimizer.md). keep_pixel: the pixel is x's own. */
static double jittered_coordinate(double x, double d, double margin, bool keep_pixel)
{
    double pixel = floor(keep_pixel ? x : x + d);
    return fmin(fmax(x + d, pixel + margin), pixel + 1 - margin);
}

int opt_jittered_neighbour(const aa_pattern *p, double sigma, int redraw, bool keep_pixels,
                           const aa_filter *filter, aa_rng *rng, aa_pattern *out, aa_error *err)
{
    aa_point *pts = malloc(p->tile_count * sizeof *pts);
    if (!pts)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    const double margin = OPT_SITE_MARGIN;
    for (size_t i = 0; i < p->tile_count; i++) {
        double dx = sigma * normal_deviate(rng), dy = sigma * normal_deviate(rng);
        pts[i].x = jittered_coordinate(p->tile_samples[i].x, dx, margin, keep_pixels);
        pts[i].y = jittered_coordinate(p->tile_samples[i].y, dy, margin, keep_pixels);
    }
    /* Partial Fisher-Yates: the first `redraw` entries of a shuffled index list. */
    size_t n = p->tile_count, k = redraw > 0 ? ((size_t)redraw < n ? (size_t)redraw : n) : 0;
    size_t *order = k ? malloc(n * sizeof *order) : NULL;
    if (k && !order) {
        free(pts);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    for (size_t i = 0; i < k; i++) {
        if (i == 0)
            for (size_t j = 0; j < n; j++)
                order[j] = j;
        size_t j = i + (size_t)(aa_rng_uniform(rng) * (double)(n - i));
        if (j >= n)
            j = n - 1;
        size_t t = order[i];
        order[i] = order[j];
        order[j] = t;
        aa_point *q = &pts[order[i]];
        double px = floor(q->x), py = floor(q->y);
        q->x = px + margin + (1 - 2 * margin) * aa_rng_uniform(rng);
        q->y = py + margin + (1 - 2 * margin) * aa_rng_uniform(rng);
    }
    free(order);
    aa_tile_spec spec = {p->tile, p->kernel_size, p->border, p->tile_count,
                         pts,     NULL,           NULL,      filter};
    int rc = aa_pattern_from_tile(out, &spec, 0, err);
    free(pts);
    return rc;
}

int aa_optimize_perturbed(const aa_pattern *start, const aa_metric_params *metric,
                          const aa_optimize_params *local, const aa_perturb_params *pp, aa_rng *rng,
                          aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                          aa_optimize_result *result, aa_error *err)
{
    memset(best, 0, sizeof *best);
    if (!aa_perturbable(start))
        return aa_error_set(err, AA_EINVAL, "pattern",
                            "only tile patterns without border samples can be perturbed");
    if (!(pp->sigma > 0 && pp->sigma < 0.5) || pp->rounds < 0 || pp->stall < 1)
        return aa_error_set(err, AA_EINVAL, "perturb",
                            "sigma in (0, 0.5), rounds >= 0, stall >= 1");
    aa_evaluation ev;
    int rc = aa_evaluate(start, metric, &ev, err);
    if (rc)
        return rc;
    memset(result, 0, sizeof *result);
    result->initial_e2 = result->e2 = result->e2_before_snap = ev.e2;
    result->argmax_kernel = ev.argmax_kernel;
    result->argmax_angle_deg = ev.argmax_angle_deg;
    aa_evaluation_free(&ev);
    if ((rc = aa_pattern_copy(best, start)))
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    int since_better = 0;
    /* The rounds as one run, against the search's budgets. */
    opt_chained_progress chain = {progress, user, pp->max_seconds, pp->max_iterations, 0, 0, 0, 0};
    for (long round = 0; round < pp->rounds && since_better < pp->stall; round++) {
        aa_pattern trial, out;
        if ((rc = opt_jittered_neighbour(best, pp->sigma, pp->redraw, pp->keep_pixels,
                                         metric->filter, rng, &trial, err)))
            break;
        aa_optimize_params round_params = *local;
        if (pp->max_iterations > 0) {
            long left = pp->max_iterations - result->iterations;
            if (left <= 0) {
                aa_pattern_free(&trial);
                break;
            }
            if (round_params.max_iterations > left)
                round_params.max_iterations = left;
        }
        if (pp->max_seconds > 0) {
            double left = pp->max_seconds - result->seconds;
            if (left <= 0) {
                aa_pattern_free(&trial);
                break;
            }
            if (round_params.max_seconds <= 0 || round_params.max_seconds > left)
                round_params.max_seconds = left;
        }
        aa_optimize_result r;
        rc = aa_optimize(&trial, metric, &round_params,
                         progress ? opt_chained_progress_forward : NULL, &chain, &out, &r, err);
        aa_pattern_free(&trial);
        if (rc && rc != AA_ECANCELED)
            break;
        result->iterations += r.iterations;
        result->evaluations += r.evaluations;
        result->seconds += r.seconds;
        chain.seconds = result->seconds;
        chain.iterations = result->iterations;
        chain.evaluations = result->evaluations;
        if (out.kernels && r.e2 < result->e2) {
            aa_pattern_free(best);
            *best = out;
            result->e2 = result->e2_before_snap = r.e2;
            result->argmax_kernel = r.argmax_kernel;
            result->argmax_angle_deg = r.argmax_angle_deg;
            since_better = 0;
        } else {
            aa_pattern_free(&out);
            since_better++;
        }
        if (rc == AA_ECANCELED)
            break;
    }
    if (rc && rc != AA_ECANCELED) {
        aa_pattern_free(best);
        return rc;
    }
    return rc;
}
