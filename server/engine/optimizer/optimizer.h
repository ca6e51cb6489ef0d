/* The pattern optimizer: Laine & Aila (2005) section 5 and two step rules beyond it, with
 * multi-start and iterated local search.
 *
 * Step rules (aa_optimize_params.method; aa_auto_method picks one by measurement):
 *  - AA_METHOD_LAINE_AILA, the paper's. One step: evaluate W(theta) E1(theta) and its analytic
 *    gradient for every kernel and angle; terms with W E1 >= t E2 ("active") move with step c1,
 *    the rest with c0 (L&A: t = 0.99, c1 = 100 c0). Robustness beyond the paper (the max over
 *    kernels and angles has kinks where the summed active gradients stop descending): a step is
 *    accepted when E2 is below the largest of the last 10 accepted values and within 1% of the
 *    current one (nonmonotone acceptance, Grippo et al. 1986; the best pattern is kept
 *    separately, so results and traces are monotone); a rejected step halves c0, an accepted one
 *    grows it by 1.2x; after 3 rejections in a row the band of terms stepped with c1 widens
 *    (t -> 1 - 4^k (1 - t), k <= 6, t >= 0.5) and the step restarts from the last accepted size.
 *  - AA_METHOD_MINIMAX (optimizer_minimax.c): each step solves for the blend of near-maximal
 *    gradients that lowers all of them (a proximal QP over the simplex, simplex_qp.h) under a
 *    trust region. On the weights alone E2 is convex and this converges to the optimum.
 *  - AA_METHOD_SMOOTH (optimizer_smooth.c): L-BFGS on the Lp norm of the terms, p = 16 ... 65536,
 *    keeping the best true E2 seen; it crosses the kinks the other two stop at.
 * Common to all: position gradients of a tile sample are summed over every kernel that reads it
 * (tile_index), then the sample is kept on its site (corner: fixed, edge: along the edge,
 * interior: clamped inside its pixel); mirrored patterns move their source pixel and are rebuilt,
 * so the mirror structure holds by construction; weights move along the Sigma w = 1 projected
 * gradient and are renormalised. A run stops when the best E2 has not improved by rel_tolerance
 * over stall_iterations steps (smooth: when its last stage converges), at max_iterations, at
 * max_seconds, or when progress returns nonzero (it is called at most every 10 ms, between steps
 * and between kernels; one step of P(16,16,4) takes ~2-10 ms).
 * Deterministic: no clock-dependent decisions except the time budget. */
#ifndef AA_OPTIMIZER_H
#define AA_OPTIMIZER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "aa_core.h"
#include "aa_pattern.h"
#include "aa_metric.h"

typedef enum aa_optimize_mode {
    AA_OPTIMIZE_WEIGHTS, /* L&A Table 3 "Opt W" */
    AA_OPTIMIZE_POSITIONS,
    AA_OPTIMIZE_BOTH /* "Opt W+P" */
} aa_optimize_mode;

/* The step rule of a local run. */
typedef enum aa_optimize_method {
    AA_METHOD_LAINE_AILA, /* the paper's rule with the safeguards above */
    AA_METHOD_MINIMAX,    /* proximal minimax QP step with a trust region (optimizer_minimax.c) */
    AA_METHOD_SMOOTH      /* L-BFGS on the Lp norm, p -> large (optimizer_smooth.c) */
} aa_optimize_method;

const char *aa_optimize_method_name(aa_optimize_method m); /* "laine-aila", "minimax", "smooth" */
int aa_optimize_method_parse(const char *name, aa_optimize_method *out); /* AA_EINVAL if unknown */
/* The rule used when the caller leaves the choice to the engine ("auto"), by measurement
 * (README, Benchmarks): weights only -> minimax (the problem is convex in the weights and the
 * minimax step converges to its optimum, where the L&A rule stops ~1-2% above it); tiled
 * families without border samples (P(4,4,n), P(16,16,n); aa_family_perturbable) -> smooth
 * (P(16,16,4): 0.1730 against 0.1764 in 600 s); everything else -> laine-aila, which reaches the
 * published optima of the one-pixel families. */
aa_optimize_method aa_auto_method(bool tiled_without_border, aa_optimize_mode mode);

typedef struct aa_optimize_params {
    aa_optimize_mode mode;
    aa_optimize_method method; /* default AA_METHOD_LAINE_AILA */
    double threshold;          /* t, default 0.99 */
    double step;               /* c0, default 1e-4 (c1 = step * active_ratio) */
    double active_ratio;       /* c1 / c0, default 100 */
    long max_iterations;       /* per seed, default 20000 */
    double max_seconds;        /* wall budget for the whole call, default 10; <= 0: none */
    long stall_iterations;     /* default 500 */
    double rel_tolerance;      /* default 1e-6 */
    /* AA_METHOD_SMOOTH: the width (pixels) below which E1's crossing kinks are smoothed in the
     * first stage (p = 16); it halves with each doubling of p (aa_e1_smoothed_at_direction,
     * docs/optimizer.md). 0: the exact E1 in every stage. Default AA_SMOOTH_KINK_WIDTH. */
    double kink_width;
    /* Hardware grid: positions snapped to 1/2^grid_bits pixel after optimisation (and the
     * quantisation cost reported); d3d12_range also clamps offsets to [-8, 7]/16. */
    int grid_bits; /* 0: off; default 0 (4 = 1/16 pixel) */
    bool d3d12_range;
    aa_clock clock; /* default: CLOCK_MONOTONIC; multi-start uses local.clock for the call */
} aa_optimize_params;

#define AA_SMOOTH_KINK_WIDTH 0.3
void aa_optimize_params_default(aa_optimize_params *p);

/* Progress of a run: return nonzero to cancel (the call then returns AA_ECANCELED with the
 * best pattern so far in *best). */
typedef struct aa_optimize_progress {
    double seconds;   /* since the call started */
    long iterations;  /* steps so far, all seeds */
    long evaluations; /* E2 evaluations so far */
    double best_e2;
    double fraction;        /* 0..1 estimate */
    bool improved;          /* best_e2 improved since the previous call */
    const aa_pattern *best; /* valid during the callback only */
} aa_optimize_progress;
typedef int (*aa_optimize_progress_fn)(void *user, const aa_optimize_progress *progress);

typedef struct aa_optimize_result {
    double initial_e2;
    double e2;             /* of *best (after snapping when grid_bits > 0) */
    double e2_before_snap; /* == e2 when grid_bits == 0 */
    long iterations;
    long evaluations;
    double seconds;
    size_t argmax_kernel;
    double argmax_angle_deg;
} aa_optimize_result;

/* first := first followed by then: then's E2 and argmax, the work of both, first's initial_e2
 * (a refinement chained after the descent that produced its start). */
void aa_optimize_result_chain(aa_optimize_result *first, const aa_optimize_result *then);

/* Local optimisation from one seed pattern. *best receives a new pattern (free it). */
int aa_optimize(const aa_pattern *seed, const aa_metric_params *metric,
                const aa_optimize_params *params, aa_optimize_progress_fn progress, void *user,
                aa_pattern *best, aa_optimize_result *result, aa_error *err);

/* Iterated local search from a local optimum of a tile pattern without border samples
 * (aa_perturbable): up to `rounds` times, jitter every sample by N(0, sigma^2) pixels on the
 * tile's torus (a sample may move into a neighbouring pixel; the descent itself keeps samples in
 * their pixels), reset the weights to the filter's impulse response, descend with `local`, keep the
 * result if E2 is lower; stop after `stall` rounds in a row without improvement, when
 * max_seconds are spent (AA_OK), or when a round is cancelled (AA_ECANCELED, *best = the best so
 * far). result sums iterations, evaluations and seconds over the rounds; initial_e2 is start's.
 * Deterministic for a given rng state. */
typedef struct aa_perturb_params {
    long rounds;        /* 0: off; AA_PERTURB_UNTIL_STALL: until stall or a budget ends it */
    double sigma;       /* pixels, default 0.01 */
    int stall;          /* default 30 */
    double max_seconds; /* the whole search; <= 0: none (each round keeps local's budget) */
    /* Steps of the whole search (every round's descent), a clock-free budget; 0: none (each
     * round keeps local's max_iterations). */
    long max_iterations;
    /* Samples (distinct, chosen at random) also drawn afresh, uniformly in their own pixel, in
     * every round: a larger move than the jitter alone; default 0. */
    int redraw;
    /* Jitter each sample inside its own pixel, so every pixel keeps its number of samples (the
     * move before 2026-11-27, for comparison; default false: samples may change pixels). */
    bool keep_pixels;
} aa_perturb_params;
#define AA_PERTURB_UNTIL_STALL 1000000000L
/* rounds 0 (off), sigma 0.01, stall 30, no budgets of its own, no redraws, samples may change
 * pixels. */
void aa_perturb_params_default(aa_perturb_params *pp);
bool aa_perturbable(const aa_pattern *p);
/* The families whose optimizations use the search: tiled (T > 1) without border samples, i.e.
 * P(4,4,n) and P(16,16,n). The one-pixel families converge to the published optima without it
 * (bench_families), and it has not been measured there. */
bool aa_family_perturbable(const aa_family *f);
/* The same test on a pattern: a tile form with T > 1 and no border samples (what
 * aa_auto_method's tiled_without_border means). */
bool aa_pattern_tiled_without_border(const aa_pattern *p);
int aa_optimize_perturbed(const aa_pattern *start, const aa_metric_params *metric,
                          const aa_optimize_params *local, const aa_perturb_params *pp, aa_rng *rng,
                          aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                          aa_optimize_result *result, aa_error *err);

/* A descent from start with `local`, then, when it stops early (a kink of the max) and the
 * result can be perturbed (mode BOTH, aa_perturbable), iterated local search from its optimum
 * for the rest of the stage's budget: local->max_seconds (<= 0: none) and stage_iterations
 * steps over both (<= 0: none; the descent keeps local->max_iterations, the search runs until it
 * stalls). `search` gives the search's rounds, sigma, stall and redraws; its budgets are the
 * rest. progress sees one run: counters continue from the descent into the search, and the
 * fraction is the share of the stage's budgets spent, never stepping back. result chains both
 * runs; AA_ECANCELED leaves the best so far in *out. */
int aa_optimize_refined(const aa_pattern *start, const aa_metric_params *metric,
                        const aa_optimize_params *local, long stage_iterations,
                        const aa_perturb_params *search, aa_rng *rng,
                        aa_optimize_progress_fn progress, void *user, aa_pattern *out,
                        aa_optimize_result *result, aa_error *err);

/* Multi-start: seed_count local runs from random seeds of a family (or given patterns), spread
 * over worker threads (seed i goes to worker i % workers; each seed draws from its own PCG32
 * stream (rng_seed, i), so the seeds do not depend on the worker count). The best is the lowest
 * E2, ties to the lowest seed index. With iteration/stall limits only, the result is
 * deterministic for (rng_seed, workers) (in fact for rng_seed alone); a time budget stops seeds
 * at clock-dependent points. progress is called from worker threads, serialised by a mutex, at
 * most every 10 ms plus once at the end; nonzero cancels every worker (AA_ECANCELED, *best
 * holds the best so far when any seed has produced one). */

typedef struct aa_multistart_params {
    aa_optimize_params local; /* per seed (its max_seconds is capped by the call's budget) */
    size_t seed_count;
    /* Global index of the call's first seed (default 0): the call runs seeds first_seed ..
     * first_seed + seed_count - 1, each exactly as a call from 0 would (its stream, distribution,
     * configuration and perturbation stream follow the global index), so contiguous ranges
     * split over calls (shards of a job) reproduce one call. Given seeds[] are the range's own
     * (seeds[0] is seed first_seed). */
    size_t first_seed;
    uint64_t rng_seed;
    int workers;             /* 1..64 threads */
    double max_seconds;      /* whole call; <= 0: none */
    const aa_family *family; /* random seeds of this family, or NULL to use seeds[] */
    /* Distributions used in turn; NULL: Poisson disks for the tiled families without border
     * samples (aa_family_perturbable), all five otherwise. */
    const aa_seed_distribution *distributions;
    size_t distribution_count;
    const aa_pattern *seeds; /* given seeds (family == NULL): seed_count of them */
    /* Mirrored families: seed i takes configs[i % config_count]; NULL: all configurations of
     * the family's cost (aa_enumerate_mirrored). */
    const aa_mirrored_config *configs;
    size_t config_count;
    /* Mirrored families only, 0 = off: first run every configuration once for
     * screen_iterations steps (within a quarter of max_seconds), then spend the rest on the
     * screen_top configurations with the lowest E2 (per_seed then describes the second phase).
     * The screening always covers every configuration whatever first_seed is (it is
     * deterministic, so every shard of a split run screens alike); the focus phase runs the
     * seed range. */
    long screen_iterations;
    size_t screen_top;
    /* After each seed's descent, iterated local search (aa_optimize_perturbed) on its result
     * when the pattern allows it; perturb.rounds = 0 (the default) turns it off. Each seed's
     * rounds draw from their own stream, so the result stays deterministic per seed. Default:
     * aa_perturb_params_default with sigma 0.03 (measured on P(16,16,4), optimizer_multistart.c).
     */
    aa_perturb_params perturb;
    /* > 0: a seed's descent and its refinement together take at most this many steps (the
     * clock-free budget "seeds x max_iterations"); 0: the refinement has perturb's budgets. */
    long seed_iterations;
    /* Family seeds that are neither given nor mirrored, > 1: each seed is the lowest-E2 of this
     * many random patterns of its distribution (L&A Table 3's "best of 1000" start: P(16,16,4)
     * descends from it to far lower optima than from one draw). Candidate j of seed i draws from
     * its own stream, so the choice is deterministic per seed. 0 or 1: one draw (the default). */
    size_t seed_pool;
} aa_multistart_params;

void aa_multistart_params_default(aa_multistart_params *p);

typedef struct aa_multistart_seed {
    aa_seed_distribution distribution; /* distribution of a family seed */
    int status;                        /* AA_OK, or why this seed did not run to completion */
    double initial_e2;                 /* NaN if the seed did not run */
    double e2;
    long iterations;
} aa_multistart_seed;

typedef struct aa_multistart_result {
    double e2;
    size_t best_seed; /* global index; SIZE_MAX: the best came from the screening phase */
    size_t seeds_run;
    long iterations;
    long evaluations;
    double seconds;
    size_t argmax_kernel;
    double argmax_angle_deg;
    double e2_before_snap;
    aa_multistart_seed *per_seed; /* [seed_count], local: per_seed[i] is seed first_seed + i */
    size_t seed_count;
} aa_multistart_result;

int aa_multistart(const aa_multistart_params *params, const aa_metric_params *metric,
                  aa_optimize_progress_fn progress, void *user, aa_pattern *best,
                  aa_multistart_result *result, aa_error *err);
void aa_multistart_result_free(aa_multistart_result *r);

#endif
