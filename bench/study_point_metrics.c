/* Does blue noise or low discrepancy predict E2? For random patterns of each seed distribution
 * (uniform, jittered, N-rooks, Poisson disk, Lloyd) in P(1,1,4), P(1,1,8) and P(16,16,4), with
 * weights from the default filter (Mitchell B = C = 1/3) and the default acuity table: E2 and the
 * point-set figures of the tile (docs/analysis.md), then the Spearman rank correlation of E2 with
 * each figure over the patterns of one distribution, and over all distributions pooled. A
 * measurement, not tuned: the patterns are aa_family_seed's, drawn from stream (seed, i).
 *   study_point_metrics [--count N per distribution (default 1000)] [--seed S (default 1)]
 *                       [--families "P(1,1,4),P(1,1,8),P(16,16,4)"]
 * Two threads split the patterns; about 2 minutes at the defaults on the 2-core machine. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"

enum { F_CD, F_WD, F_MD, F_L2STAR, F_STAR, F_MIN_DIST, F_MEAN_NN, F_LOW_POWER, F_NYQUIST, FIGURES };
static const char *const figure_names[FIGURES] = {
    "CD",        "WD",    "MD", "L2-star", "Linf-star", "min d/d_hex", "mean nn/d_hex",
    "low power", "nu_eff"};
#define DISTS 5
static const aa_seed_distribution dists[DISTS] = {AA_SEED_UNIFORM, AA_SEED_JITTERED, AA_SEED_NROOKS,
                                                  AA_SEED_POISSON, AA_SEED_LLOYD};

typedef struct work {
    const aa_family *family;
    const aa_metric_params *metric;
    const aa_filter *filter;
    aa_seed_distribution distribution;
    uint64_t seed;
    size_t first, count;
    double *e2;           /* [count] */
    double *fig[FIGURES]; /* [count] each */
    int failed;
} work;

/* Mean periodogram power over 0 < |k| <= sqrt(n)/2: the low-frequency energy blue noise lacks. */
static double low_power(const aa_spectrum *s, size_t n)
{
    double limit = sqrt((double)n) / 2, sum = 0;
    size_t count = 0;
    for (int b = 1; b <= s->radius && b <= limit; b++) {
        sum += s->radial[b] * (double)s->annulus_count[b];
        count += s->annulus_count[b];
    }
    return count ? sum / (double)count : NAN;
}

static void *run(void *arg)
{
    work *w = arg;
    for (size_t i = 0; i < w->count; i++) {
        aa_rng rng;
        aa_rng_seed(&rng, w->seed, w->first + i);
        aa_pattern p;
        aa_error err = {0};
        aa_evaluation ev;
        aa_point *pts = NULL;
        size_t n = 0;
        if (aa_family_seed(w->family, w->distribution, w->filter, &rng, &p, &err) ||
            aa_evaluate(&p, w->metric, &ev, &err) || aa_pattern_unit_points(&p, &pts, &n, &err)) {
            fprintf(stderr, "study_point_metrics: %s\n", err.message);
            w->failed = 1;
            return NULL;
        }
        w->e2[i] = ev.e2;
        aa_evaluation_free(&ev);
        aa_discrepancy d;
        aa_spacing sp;
        aa_spectrum s;
        double star;
        int radius = (int)ceil(sqrt((double)n)) + 1;
        if (aa_point_set_discrepancy(pts, n, &d, &err) ||
            aa_point_set_star_discrepancy(pts, n, &star, &err) ||
            aa_point_set_spacing(pts, n, &sp, &err) ||
            aa_point_set_spectrum(pts, n, radius, &s, &err)) {
            fprintf(stderr, "study_point_metrics: %s\n", err.message);
            w->failed = 1;
            free(pts);
            aa_pattern_free(&p);
            return NULL;
        }
        double v[FIGURES] = {d.centered,
                             d.wrap_around,
                             d.mixture,
                             d.l2_star,
                             star,
                             sp.min_distance_normalized,
                             sp.mean_nn_distance_normalized,
                             low_power(&s, n),
                             s.effective_nyquist / sqrt((double)n)};
        for (int f = 0; f < FIGURES; f++)
            w->fig[f][i] = v[f];
        aa_spectrum_free(&s);
        free(pts);
        aa_pattern_free(&p);
    }
    return NULL;
}

/* Spearman's rho (aa_spearman_of, the one random-stats and table3 report; pairs with a NaN
 * dropped). */
static double spearman(const double *a, const double *b, size_t n)
{
    aa_spearman_result r;
    return aa_spearman_of(a, b, n, &r) ? NAN : r.rho;
}

int main(int argc, char **argv)
{
    size_t count = 1000;
    uint64_t seed = 1;
    char families[256] = "P(1,1,4),P(1,1,8),P(16,16,4)";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--count"))
            count = (size_t)strtoul(argv[i + 1], NULL, 10);
        else if (!strcmp(argv[i], "--seed"))
            seed = strtoull(argv[i + 1], NULL, 10);
        else if (!strcmp(argv[i], "--families"))
            snprintf(families, sizeof families, "%s", argv[i + 1]);
    }
    if (count < 3) {
        fprintf(stderr, "study_point_metrics: --count >= 3\n");
        return 2;
    }
    aa_filter filter;
    aa_filter_default(&filter);
    aa_acuity acuity;
    aa_acuity_naiman(&acuity);
    aa_metric_params metric = {&filter, &acuity, NULL, 0, 0};
    printf("study_point_metrics: %zu random patterns per distribution, seed %llu, Mitchell "
           "weights, default acuity; Spearman rho of E2 with each point-set figure\n",
           count, (unsigned long long)seed);
    size_t all_n = DISTS * count;
    double *all_e2 = malloc(all_n * sizeof *all_e2), *all_fig[FIGURES];
    for (int f = 0; f < FIGURES; f++)
        all_fig[f] = malloc(all_n * sizeof *all_fig[f]);
    /* Split the list at the commas outside parentheses. */
    for (char *p = families; *p;) {
        char *name = p;
        int depth = 0;
        while (*p && (depth || *p != ',')) {
            depth += (*p == '(') - (*p == ')');
            p++;
        }
        if (*p)
            *p++ = 0;
        aa_family fam;
        aa_error err = {0};
        if (aa_family_parse(name, &fam, &err)) {
            fprintf(stderr, "study_point_metrics: %s\n", err.message);
            return 2;
        }
        printf("\n%s\n%-10s %8s", name, "dist", "E2 mean");
        for (int f = 0; f < FIGURES; f++)
            printf(" %13s", figure_names[f]);
        printf("\n");
        for (int d = 0; d <= DISTS; d++) {
            double *e2, *fig[FIGURES];
            size_t n;
            if (d < DISTS) {
                work w[2];
                pthread_t t[2];
                for (int k = 0; k < 2; k++) {
                    size_t first = k ? count / 2 : 0, c = k ? count - count / 2 : count / 2;
                    w[k] = (work){.family = &fam,
                                  .metric = &metric,
                                  .filter = &filter,
                                  .distribution = dists[d],
                                  .seed = seed * 1000 + (uint64_t)d,
                                  .first = first,
                                  .count = c,
                                  .e2 = all_e2 + (size_t)d * count + first};
                    for (int f = 0; f < FIGURES; f++)
                        w[k].fig[f] = all_fig[f] + (size_t)d * count + first;
                    pthread_create(&t[k], NULL, run, &w[k]);
                }
                for (int k = 0; k < 2; k++)
                    pthread_join(t[k], NULL);
                if (w[0].failed || w[1].failed)
                    return 1;
                e2 = all_e2 + (size_t)d * count;
                for (int f = 0; f < FIGURES; f++)
                    fig[f] = all_fig[f] + (size_t)d * count;
                n = count;
            } else {
                e2 = all_e2;
                for (int f = 0; f < FIGURES; f++)
                    fig[f] = all_fig[f];
                n = all_n;
            }
            double mean = 0;
            for (size_t i = 0; i < n; i++)
                mean += e2[i] / (double)n;
            printf("%-10s %8.4f", d < DISTS ? aa_seed_distribution_name(dists[d]) : "pooled", mean);
            for (int f = 0; f < FIGURES; f++)
                printf(" %13.3f", spearman(e2, fig[f], n));
            printf("\n");
            fflush(stdout);
        }
    }
    return 0;
}
