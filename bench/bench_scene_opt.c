/* Issue 18 point 4: a pattern optimized for a scene (objective_scene.h) against the best
 * global-E2 pattern of the same family and cost, rendered on that scene.
 *
 * For each scene: the global-E2 search (aa_multistart, as bench_families runs it) gives pattern
 * G; the scene search (aa_optimize_scene, blend 0, from G and from `--seeds` random seeds of the
 * family) gives pattern S, the lowest scene term. Both are rendered on the scene (256², the
 * renderer; reference supersampled at AALAB_BENCH_SPP, default 1024) and the measured RMSE
 * compared. A "pair" is two half-planes rendered separately, their squared errors pooled (RMSE
 * over both images) and their edge histograms summed:
 *  - UI near-axis: edges at 2° and 92° (axis-aligned edges at spread sub-pixel offsets);
 *  - 30° grid: edges at 30° and 120°;
 *  - the Siemens star (every angle: the two should tie).
 * Prints per scene: family, predicted RMSE (the scene objective, aa_predict_rmse) and global E2
 * of each, rendered RMSE of each, and the ratio rendered(S) / rendered(G). Also the blend
 * α = 0.5 pattern's figures. Budgets: by default steps only, so the figures are deterministic
 * (the E2 optimum of a family is not unique: patterns of equal E2 differ widely at a given angle,
 * and a time budget picks among them by the clock): --e2-seeds (64) seeds of 4000 steps for the
 * E2 search, --seeds (40) random seeds of 4000 steps for the scene search; --e2-seconds /
 * --scene-seconds switch to time budgets. --family (default P(1,1,4)); --only UI|grid30|star. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"
#include "aa_render.h"

typedef struct bench_case {
    const char *label;
    size_t count;
    aa_scene_params sp[2];
} bench_case;

static aa_scene_params half_plane(double angle)
{
    aa_scene_params p = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    p.angle_deg = angle;
    p.offset = 0.37;
    return p;
}

/* Summed histograms (for the prediction) and folded lengths (for the objective). */
static int histogram_of(const bench_case *bc, aa_edge_histogram *sum, aa_scene_objective *o,
                        aa_error *err)
{
    memset(sum, 0, sizeof *sum);
    memset(o, 0, sizeof *o);
    for (size_t i = 0; i < bc->count; i++) {
        aa_scene s;
        aa_edge_histogram h;
        int rc = aa_scene_init(&s, &bc->sp[i], err);
        if (rc || (rc = aa_edge_histogram_of_scene(&s, &h, err)))
            return rc;
        double folded[AA_EDGE_BINS];
        aa_edge_histogram_folded(&h, folded);
        for (int d = 0; d < AA_EDGE_BINS; d++) {
            o->length[d] += folded[d];
            sum->length[d] += h.length[d];
        }
        for (size_t l = 0; l < h.locked_count && sum->locked_count < AA_EDGE_MAX_LOCKED; l++)
            sum->locked[sum->locked_count++] = h.locked[l];
        sum->total += h.total;
        sum->subpixel_area += h.subpixel_area;
        o->pixels += (double)h.width * h.height;
        /* The prediction's N over the pair: two images stacked. */
        sum->width = h.width;
        sum->height += h.height;
    }
    return AA_OK;
}

/* Rendered RMSE of p over the case's scenes (squared errors pooled). */
static int rendered(const bench_case *bc, const aa_pattern *p, int spp, aa_image *refs,
                    bool *have_refs, double *rmse, aa_error *err)
{
    aa_diff_stats d;
    aa_diff_init(&d);
    double off = aa_output_offset(p->kernel_size);
    for (size_t i = 0; i < bc->count; i++) {
        aa_scene s;
        int rc = aa_scene_init(&s, &bc->sp[i], err);
        if (rc)
            return rc;
        aa_image *ref = &refs[2 * i + (off == 0.5 ? 0 : 1)];
        if (!have_refs[ref - refs]) {
            aa_reference_params rp = aa_reference_params_default();
            rp.spp = spp;
            if ((rc = aa_image_init(ref, s.p.width, s.p.height, err)) ||
                (rc = aa_render_reference(&s, &rp, off, ref, NULL, NULL, err)))
                return rc;
            have_refs[ref - refs] = true;
        }
        aa_image img;
        if ((rc = aa_image_init(&img, s.p.width, s.p.height, err)))
            return rc;
        rc = aa_render_pattern(&s, p, true, &img, NULL, NULL, err);
        if (!rc)
            rc = aa_diff_add(&d, &img, ref);
        aa_image_free(&img);
        if (rc)
            return rc;
    }
    aa_diff_finish(&d);
    *rmse = d.rmse;
    return AA_OK;
}

typedef struct figures {
    double predicted, e2, rendered;
} figures;

static int figures_of(const bench_case *bc, const aa_pattern *p, const aa_edge_histogram *h,
                      const aa_metric_params *metric, int spp, aa_image *refs, bool *have,
                      figures *out, aa_error *err)
{
    aa_prediction pred;
    aa_evaluation ev;
    int rc = aa_predict_rmse(p, metric->filter, h, &pred, err);
    if (rc || (rc = aa_evaluate(p, metric, &ev, err)))
        return rc;
    out->predicted = pred.rmse;
    out->e2 = ev.e2;
    aa_evaluation_free(&ev);
    return rendered(bc, p, spp, refs, have, &out->rendered, err);
}

/* The scene search: from the E2 optimum and from random seeds, keep the lowest objective. */
static int scene_search(const aa_family *fam, const aa_pattern *start,
                        const aa_metric_params *metric, const aa_scene_objective *o, double blend,
                        double seconds, int seeds, aa_pattern *best, aa_scene_optimize_result *br,
                        aa_error *err)
{
    aa_scene_optimize_params sp = {.blend = blend};
    aa_optimize_params_default(&sp.local);
    sp.local.mode = AA_OPTIMIZE_BOTH;
    sp.local.max_iterations = 4000;
    sp.local.stall_iterations = 300;
    sp.local.max_seconds = seconds > 0 ? seconds / (seeds + 1) : 0;
    double s0, e0, f0;
    int rc = aa_scene_objective_blend(start, metric, o, blend, 0, 0, &f0, &s0, &e0, err);
    if (rc)
        return rc;
    /* Both terms relative to the E2 optimum: F = 1 there. */
    sp.scene_ref = s0;
    sp.e2_ref = e0;
    memset(best, 0, sizeof *best);
    bool have = false;
    for (int i = 0; i <= seeds && !rc; i++) {
        aa_pattern seed, out;
        if (i == 0) {
            rc = aa_pattern_copy(&seed, start) ? AA_ENOMEM : AA_OK;
        } else {
            aa_rng rng;
            aa_rng_seed(&rng, 1000 + (uint64_t)i, 5);
            rc = aa_family_seed(fam,
                                (aa_seed_distribution)(i % 2 ? AA_SEED_JITTERED : AA_SEED_UNIFORM),
                                metric->filter, &rng, &seed, err);
        }
        if (rc)
            break;
        aa_scene_optimize_result r;
        rc = aa_optimize_scene(&seed, metric, o, &sp, NULL, NULL, &out, &r, err);
        aa_pattern_free(&seed);
        if (rc)
            break;
        if (!have || r.objective < br->objective) {
            if (have)
                aa_pattern_free(best);
            *best = out;
            *br = r;
            have = true;
        } else {
            aa_pattern_free(&out);
        }
    }
    return rc;
}

int main(int argc, char **argv)
{
    double e2_seconds = 0, scene_seconds = 0; /* 0: iteration budgets only (deterministic) */
    int seeds = 40, e2_seeds = 64, spp = 1024;
    const char *family = "P(1,1,4)", *only = NULL;
    if (getenv("AALAB_BENCH_SPP"))
        spp = atoi(getenv("AALAB_BENCH_SPP"));
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--e2-seconds") && i + 1 < argc)
            e2_seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--scene-seconds") && i + 1 < argc)
            scene_seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--seeds") && i + 1 < argc)
            seeds = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--e2-seeds") && i + 1 < argc)
            e2_seeds = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--family") && i + 1 < argc)
            family = argv[++i];
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else {
            fprintf(stderr,
                    "usage: %s [--family F] [--e2-seeds N] [--seeds N] [--e2-seconds S] "
                    "[--scene-seconds S] [--only UI|grid30|star]\n",
                    argv[0]);
            return 2;
        }
    }
    aa_filter filter;
    aa_acuity acuity;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    aa_metric_params metric = {&filter, &acuity, NULL, 0, 0};
    aa_family fam;
    aa_error err = {0};
    if (aa_family_parse(family, &fam, &err)) {
        fprintf(stderr, "--family: %s\n", err.message);
        return 2;
    }
    bench_case cases[3] = {
        {"UI", 2, {half_plane(2), half_plane(92)}},
        {"grid30", 2, {half_plane(30), half_plane(120)}},
        {"star", 1, {aa_scene_params_default(AA_SCENE_SIEMENS_STAR)}},
    };
    /* The global-E2 optimum of the family, once (it does not depend on the scene). */
    aa_multistart_params mp;
    aa_multistart_params_default(&mp);
    mp.family = &fam;
    mp.workers = 1;
    mp.rng_seed = 1;
    mp.max_seconds = e2_seconds;
    mp.seed_count = e2_seconds > 0 ? 100000 : (size_t)e2_seeds;
    mp.local.method = aa_auto_method(aa_family_perturbable(&fam), mp.local.mode);
    mp.local.max_iterations = 4000;
    mp.local.stall_iterations = 300;
    mp.screen_iterations = 150;
    mp.screen_top = 8;
    if (aa_family_perturbable(&fam))
        mp.perturb.rounds = AA_PERTURB_UNTIL_STALL;
    aa_pattern global;
    aa_multistart_result mr;
    int rc = aa_multistart(&mp, &metric, NULL, NULL, &global, &mr, &err);
    if (rc && rc != AA_ECANCELED) {
        fprintf(stderr, "E2 search: %s\n", err.message);
        return 1;
    }
    printf("bench_scene_opt: family %s, 256^2, reference %d spp; global-E2 search (1 worker, %s) "
           "-> E2 %.4f over %zu seeds in %.1f s; scene search from it and %d random seeds "
           "(blend 0, and blend 0.5), %s\n",
           family, spp, e2_seconds > 0 ? "time budget" : "4000 steps per seed, no time budget",
           mr.e2, mr.seeds_run, mr.seconds, seeds,
           scene_seconds > 0 ? "time budget" : "4000 steps per seed, no time budget");
    aa_multistart_result_free(&mr);
    printf("%-7s %-9s %9s %9s %9s %9s %9s %9s %8s   %s\n", "scene", "pattern", "objective",
           "pred_rmse", "E2", "rendered", "r/pred", "vs_E2opt", "seconds", "");
    for (size_t c = 0; c < 3; c++) {
        const bench_case *bc = &cases[c];
        if (only && strcmp(only, bc->label))
            continue;
        aa_edge_histogram h;
        aa_scene_objective o;
        aa_image refs[4];
        bool have[4] = {false, false, false, false};
        memset(refs, 0, sizeof refs);
        if ((rc = histogram_of(bc, &h, &o, &err)))
            break;
        o.filter = &filter;
        aa_predict_target target = {&filter, &h};
        o.exact = aa_predict_rmse_of;
        o.exact_user = &target;
        figures g;
        if ((rc = figures_of(bc, &global, &h, &metric, spp, refs, have, &g, &err)))
            break;
        printf("%-7s %-9s %9.4f %9.4f %9.4f %9.4f %9.3f %9.3f %8s\n", bc->label, "E2-opt", 1.0,
               g.predicted, g.e2, g.rendered, g.rendered / g.predicted, 1.0, "-");
        const double blends[2] = {0, 0.5};
        for (int b = 0; b < 2 && !rc; b++) {
            aa_pattern sbest;
            aa_scene_optimize_result sr = {0};
            double t0 = aa_seconds_now();
            if ((rc = scene_search(&fam, &global, &metric, &o, blends[b], scene_seconds, seeds,
                                   &sbest, &sr, &err)))
                break;
            double t = aa_seconds_now() - t0;
            figures s;
            rc = figures_of(bc, &sbest, &h, &metric, spp, refs, have, &s, &err);
            aa_pattern_free(&sbest);
            if (rc)
                break;
            char name[16];
            snprintf(name, sizeof name, "scene a%.1f", blends[b]);
            printf("%-7s %-9s %9.4f %9.4f %9.4f %9.4f %9.3f %9.3f %8.1f\n", bc->label, name,
                   sr.objective, s.predicted, s.e2, s.rendered, s.rendered / s.predicted,
                   s.rendered / g.rendered, t);
        }
        for (int i = 0; i < 4; i++)
            if (have[i])
                aa_image_free(&refs[i]);
    }
    aa_pattern_free(&global);
    if (rc) {
        fprintf(stderr, "bench_scene_opt: %s\n", err.message);
        return 1;
    }
    return 0;
}
