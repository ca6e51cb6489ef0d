/* L&A Table 3 (P(16,16,4), 4 spp) over K rng_seeds with both Naiman tables in one run, beside the
 * paper's values: for each seed, table and distribution (Poisson disk, jittered grid), 1000
 * random patterns (Min, Avg, Max), exact Opt W of the best, Opt W+P of the best with a budget
 * (aa_table3_cell_run, the protocol table3 jobs run). Every cell of a seed (tables x
 * distributions) runs on a thread of its own; on 2 idle cores a seed's two distributions side by
 * side take the larger of their CPU times, which the table prints per cell.
 * Reported: mean +- sd over the seeds of every column, the paper's value and the ratio
 * mean / paper, and the issue-17 targets for version 2 (naiman): Min / Avg / Max within one sd
 * of the paper, Opt W within +4 %, Opt W+P mean <= 0.165 (Poisson) and <= 0.173 (jittered).
 * Budgets are CPU seconds of the thread running the cell (CLOCK_THREAD_CPUTIME_ID), so the
 * figures do not depend on what else loads the machine; --wall-clock uses the wall clock.
 * Per cell it prints the CPU seconds (and their parts), per seed and table the time the seed
 * takes on 2 idle cores with its two distributions side by side (the larger of their CPU times,
 * as a table3 job's shard runs them), and over the seeds that time's mean and maximum against
 * the issue-17 target of <= 2 minutes per seed.
 * Flags: --seeds N (8), --wp-seconds S (60), --count N (1000), --quick (2 seeds, 200 patterns,
 * 10 s), --tables naiman,naiman-envelope, --wall-clock, --first-seed K (seeds K .. K+N-1),
 * --random-only (the 1000 random patterns only: Min / Avg / Max in about a CPU second per
 * cell), --poisson-radius R (px; default aa_poisson_default_radius). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "aa_metric.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"

#define MAX_SEEDS 64
#define DISTS 2
#define MAX_TABLES 3
static const aa_seed_distribution dists[DISTS] = {AA_SEED_POISSON, AA_SEED_JITTERED};
static const double wp_target[DISTS] = {0.165, 0.173};
#define SEED_SECONDS_TARGET 120.0 /* <= 2 minutes per seed on 2 cores (version 2) */

/* A seed's wall time on 2 idle cores with its two distributions side by side: the larger of
 * their CPU times. */
static double side_by_side(double cpu[DISTS][MAX_SEEDS], int s)
{
    return cpu[0][s] > cpu[1][s] ? cpu[0][s] : cpu[1][s];
}

/* The calling thread's CPU time: each cell's budget counts its own work only. */
static double thread_cpu_seconds(void *user)
{
    (void)user;
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct job {
    const aa_family *family;
    aa_seed_distribution distribution;
    const aa_metric_params *metric;
    const aa_table3_params *params;
    uint64_t seed;
    aa_table3_cell cell;
    int rc;
    char error[512];
    double cpu_seconds; /* the cell's thread CPU time */
    bool random_only;   /* the random patterns only (Min / Avg / Max) */
} job;

static void run_job(void *item)
{
    job *j = item;
    aa_error err = {0};
    double t0 = thread_cpu_seconds(NULL);
    if (j->random_only) {
        memset(&j->cell, 0, sizeof j->cell);
        j->cell.opt_w = j->cell.opt_wp = NAN;
        j->rc = aa_random_patterns_range_radius(
            j->family, j->distribution, j->params->poisson_radius, j->metric, j->seed, 0,
            j->params->count, NULL, NULL, NULL, &j->cell.best_random, &j->cell.best_index,
            &j->cell.random, &err);
    } else {
        j->rc = aa_table3_cell_run(j->family, j->distribution, j->metric, j->params, j->seed, NULL,
                                   NULL, &j->cell, &err);
    }
    j->cpu_seconds = thread_cpu_seconds(NULL) - t0;
    if (j->rc)
        snprintf(j->error, sizeof j->error, "%s: %s", err.field, err.message);
}

enum { C_MIN, C_AVG, C_MAX, C_W, C_WP, COLS };
static const char *const col_names[COLS] = {"Min", "Avg", "Max", "Opt W", "Opt W+P"};

static double paper_value(const aa_table3_paper *p, int c)
{
    const double v[COLS] = {p->min, p->avg, p->max, p->opt_w, p->opt_wp};
    return v[c];
}

int main(int argc, char **argv)
{
    int seeds = 8, first_seed = 1;
    bool random_only = false;
    aa_table3_params tp;
    aa_table3_params_default(&tp);
    char tables[128] = "naiman,naiman-envelope";
    tp.clock.fn = thread_cpu_seconds;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            seeds = 2;
            tp.count = 200;
            tp.opt_wp_seconds = 10;
        } else if (!strcmp(argv[i], "--random-only")) {
            random_only = true;
        } else if (!strcmp(argv[i], "--poisson-radius") && i + 1 < argc) {
            tp.poisson_radius = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--wall-clock")) {
            tp.clock.fn = NULL;
        } else if (!strcmp(argv[i], "--first-seed") && i + 1 < argc) {
            first_seed = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--seeds") && i + 1 < argc) {
            seeds = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--wp-seconds") && i + 1 < argc) {
            tp.opt_wp_seconds = atof(argv[++i]);
        } else if (!strcmp(argv[i], "--count") && i + 1 < argc) {
            tp.count = (size_t)atol(argv[++i]);
        } else if (!strcmp(argv[i], "--tables") && i + 1 < argc) {
            snprintf(tables, sizeof tables, "%s", argv[++i]);
        } else {
            fprintf(stderr,
                    "usage: %s [--quick] [--seeds N] [--wp-seconds S] [--count N] "
                    "[--tables A,B] [--wall-clock] [--first-seed K] [--random-only] "
                    "[--poisson-radius R]\n",
                    argv[0]);
            return 2;
        }
    }
    if (seeds < 1 || seeds > MAX_SEEDS || tp.count < 1) {
        fprintf(stderr, "bench_table3: 1..%d seeds, count >= 1\n", MAX_SEEDS);
        return 2;
    }
    aa_filter filter;
    aa_filter_default(&filter);
    aa_family fam;
    aa_error err = {0};
    if (aa_family_parse("P(16,16,4)", &fam, &err))
        return 1;
    printf("bench_table3: L&A Table 3, P(16,16,4), %d seeds, %zu random patterns each, Opt W+P "
           "%.0f %s s, Poisson disk: dart throwing on the torus at r = %.4f px\n",
           seeds, tp.count, tp.opt_wp_seconds, tp.clock.fn ? "CPU" : "wall",
           tp.poisson_radius > 0 ? tp.poisson_radius : aa_poisson_default_radius(4));
    aa_acuity acuity[MAX_TABLES];
    int table_count = 0;
    for (char *save = NULL, *name = strtok_r(tables, ",", &save); name;
         name = strtok_r(NULL, ",", &save)) {
        if (table_count == MAX_TABLES || aa_acuity_by_name(&acuity[table_count], name, &err)) {
            fprintf(stderr, "bench_table3: %s\n",
                    table_count == MAX_TABLES ? "too many tables" : err.message);
            return 2;
        }
        table_count++;
    }
    aa_metric_params metric[MAX_TABLES];
    for (int t = 0; t < table_count; t++)
        metric[t] = (aa_metric_params){&filter, &acuity[t], NULL, 0, 0};
    static double v[MAX_TABLES][DISTS][COLS][MAX_SEEDS];
    static double cpu[MAX_TABLES][DISTS][MAX_SEEDS];
    double wall_sum = 0;
    printf("every cell of a seed (%d tables x %d distributions) runs on a thread of its own; "
           "budgets count each thread's CPU time\n",
           table_count, DISTS);
    printf("per row: the cell's CPU seconds (cell s) and its parts (random patterns, Opt W, "
           "Opt W+P)\n");
    printf("\n%-16s %-5s %-9s %8s %8s %8s %8s %8s %7s %7s %7s %7s\n", "acuity", "seed", "dist",
           "Min", "Avg", "Max", "Opt W", "Opt W+P", "cell s", "rand s", "W s", "W+P s");
    for (int s = 0; s < seeds; s++) {
        job jobs[MAX_TABLES * DISTS];
        int n = 0;
        for (int t = 0; t < table_count; t++)
            for (int d = 0; d < DISTS; d++, n++) {
                memset(&jobs[n], 0, sizeof jobs[n]);
                jobs[n] = (job){.family = &fam,
                                .distribution = dists[d],
                                .metric = &metric[t],
                                .params = &tp,
                                .seed = (uint64_t)(first_seed + s),
                                .random_only = random_only};
            }
        double t0 = aa_monotonic_seconds();
        aa_fork_join(jobs, sizeof jobs[0], n, run_job);
        double wall = aa_monotonic_seconds() - t0;
        wall_sum += wall;
        for (int t = 0, i = 0; t < table_count; t++)
            for (int d = 0; d < DISTS; d++, i++) {
                const aa_table3_cell *c = &jobs[i].cell;
                if (jobs[i].rc) {
                    fprintf(stderr, "bench_table3: seed %d: %s\n", first_seed + s, jobs[i].error);
                    return 1;
                }
                const double row[COLS] = {c->random.min, c->random.avg, c->random.max, c->opt_w,
                                          c->opt_wp};
                for (int k = 0; k < COLS; k++)
                    v[t][d][k][s] = row[k];
                cpu[t][d][s] = jobs[i].cpu_seconds;
                printf("%-16s %-5d %-9s %8.4f %8.4f %8.4f %8.4f %8.4f %7.1f %7.1f %7.1f %7.1f\n",
                       acuity[t].name, first_seed + s, aa_seed_distribution_name(dists[d]), row[0],
                       row[1], row[2], row[3], row[4], jobs[i].cpu_seconds,
                       jobs[i].cpu_seconds - c->opt_w_run.seconds - c->opt_wp_run.seconds,
                       c->opt_w_run.seconds, c->opt_wp_run.seconds);
                aa_table3_cell_free(&jobs[i].cell);
            }
        for (int t = 0; t < table_count; t++)
            printf("seed %d, %s: on 2 idle cores, its %d distributions side by side take %.1f s "
                   "(the larger cell CPU time: %s %.1f s, %s %.1f s)\n",
                   first_seed + s, acuity[t].name, DISTS, side_by_side(cpu[t], s),
                   aa_seed_distribution_name(dists[0]), cpu[t][0][s],
                   aa_seed_distribution_name(dists[1]), cpu[t][1][s]);
        printf("seed %d: %.1f s wall for all %d cells (machine shared)\n", first_seed + s, wall, n);
        fflush(stdout);
    }
    for (int t = 0; t < table_count; t++) {
        bool v2 = acuity[t].version == 2 && !strcmp(acuity[t].name, "naiman");
        printf("\nacuity %s (version %d), mean +- sd over %d seeds\n", acuity[t].name,
               acuity[t].version, seeds);
        printf("%-9s %-8s %17s %8s %7s  %s\n", "dist", "column", "mean +- sd", "paper", "ratio",
               v2 ? "target (version 2)" : "");
        for (int d = 0; d < DISTS; d++) {
            const aa_table3_paper *p = aa_table3_paper_row(dists[d]);
            for (int k = 0; k < (random_only ? C_W : COLS); k++) {
                double mean, sd;
                aa_mean_sd(v[t][d][k], (size_t)seeds, &mean, &sd);
                double pv = paper_value(p, k);
                char target[64];
                bool ok;
                if (k <= C_MAX) {
                    ok = fabs(mean - pv) <= sd;
                    snprintf(target, sizeof target, "|mean - paper| <= sd");
                } else if (k == C_W) {
                    ok = mean <= pv * 1.04;
                    snprintf(target, sizeof target, "<= paper + 4 %% (%.4f)", pv * 1.04);
                } else {
                    ok = mean <= wp_target[d];
                    snprintf(target, sizeof target, "<= %.3f", wp_target[d]);
                }
                printf("%-9s %-8s %8.4f +- %6.4f %8.3f %7.3f  %s%s%s\n",
                       aa_seed_distribution_name(dists[d]), col_names[k], mean, sd, pv, mean / pv,
                       v2 ? target : "", v2 ? ": " : "", v2 ? (ok ? "met" : "MISSED") : "");
            }
            double cm, cs;
            aa_mean_sd(cpu[t][d], (size_t)seeds, &cm, &cs);
            printf("%-9s CPU seconds per seed: %.1f +- %.1f\n", aa_seed_distribution_name(dists[d]),
                   cm, cs);
        }
        /* The issue-17 time target: a seed on 2 cores, its two distributions side by side (as
         * a table3 job's shard runs them), takes the larger of their CPU times. */
        double per_seed[MAX_SEEDS], worst = 0;
        for (int s = 0; s < seeds; s++) {
            per_seed[s] = side_by_side(cpu[t], s);
            worst = per_seed[s] > worst ? per_seed[s] : worst;
        }
        double sm, ss;
        aa_mean_sd(per_seed, (size_t)seeds, &sm, &ss);
        printf(
            "a seed on 2 cores (distributions side by side): %.1f +- %.1f s, at most %.1f s%s%s\n",
            sm, ss, worst, v2 ? "; target <= 120 s per seed: " : "",
            v2 ? (worst <= SEED_SECONDS_TARGET ? "met" : "MISSED") : "");
    }
    printf("\nper seed on 2 idle cores (its two distributions side by side) the wall time is the "
           "larger CPU time of the two; measured wall per seed here, all cells at once on a "
           "shared machine: %.1f s\n",
           wall_sum / seeds);
    return 0; /* a missed target is reported, not an error */
}
