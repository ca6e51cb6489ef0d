/* Internal to the optimizer: what one local run needs besides the free variables (angles,
 * acuity weights, per-term values, gradient scratch, the clock, progress and cancel polling),
 * shared by the step rules (optimizer.c: Laine & Aila; optimizer_minimax.c: the minimax QP
 * step; optimizer_smooth.c: the smoothed max). Not part of the public API. */
#ifndef AA_OPTIMIZER_RUN_H
#define AA_OPTIMIZER_RUN_H

#include <stdbool.h>

#include "aa_metric.h"
#include "optimizer.h"
#include "optimizer_state.h"

/* Progress reporting of one run: at most every 10 ms unless forced. */
typedef struct opt_progress_state {
    aa_optimize_progress_fn fn;
    void *user;
    double start, last_call;
    double last_fraction; /* a cancel poll (no estimate of its own) reports this again */
    bool improved;
    const aa_clock *clock;
} opt_progress_state;

/* Several runs seen as one by the caller's progress (the rounds of an iterated local search, a
 * descent and then its search): each report gets the earlier runs' seconds, iterations and
 * evaluations added (the caller updates them between runs), and its fraction is the share of
 * the budgets spent, never stepping back (a run's own fraction restarts at 0 and ends at 1). */
typedef struct opt_chained_progress {
    aa_optimize_progress_fn fn;
    void *user;
    double budget_seconds;  /* <= 0: none */
    long budget_iterations; /* <= 0: none */
    double seconds;         /* the earlier runs' */
    long iterations, evaluations;
    double fraction; /* the last reported; without budgets 0 until the runs end */
} opt_chained_progress;

/* An aa_optimize_progress_fn; user is an opt_chained_progress. */
int opt_chained_progress_forward(void *user, const aa_optimize_progress *p);

struct opt_loop;

typedef struct opt_run {
    const aa_metric_params *metric;
    const aa_optimize_params *params;
    size_t angle_count;
    double *theta;         /* radians */
    double *dir_c, *dir_s; /* aa_metric_direction of each theta */
    double *weight;        /* W(theta) */
    double *value;         /* W E1 per kernel x angle, kernel-major, of the last eval */
    /* The smoothed rule's stages set kink_width > 0 (0 otherwise). Evaluations fill smoothed
     * with W E1 of the kink-smoothed E1 (aa_e1_smoothed_at_direction; the same as value at
     * width 0), and term gradients are its gradients; value stays exact (the best pattern, the
     * trace). */
    double kink_width;
    double *smoothed;
    double *cur_value;             /* the same of the loop's cur (opt_loop_accept keeps it) */
    double *gx, *gy, *gw;          /* per-kernel gradient scratch (max kernel size) */
    double *dir_x, *dir_y, *dir_w; /* descent direction on the free variables */
    aa_metric_workspace ws;
    long evaluations;
    /* The loop this run belongs to, polled between kernels so a cancel is seen within a
     * fraction of a step (a step of P(16,16,4) can take 50+ ms on a loaded machine). */
    struct opt_loop *loop;
} opt_run;

/* One local run in progress, as the step rules see it: they move cur (trial is scratch), keep
 * the best state in top and its E2 in best_e2, count steps in it, and return when a stopping
 * rule holds (AA_OK), on error, or with AA_ECANCELED when the progress callback cancels. */
typedef struct opt_loop {
    opt_run run;
    opt_state cur, trial, top;
    opt_progress_state ps;
    double start;   /* aa_clock_seconds(&params->clock) when the run began */
    double e2;      /* of cur */
    double best_e2; /* of top */
    long it;
    long mark_it; /* opt_loop_stalled: the step and best E2 of the last real improvement */
    double mark_e2;
    aa_error *err;
} opt_loop;

/* Call between steps: AA_OK to go on, 1 if the time budget or max_iterations is spent,
 * AA_ECANCELED if the progress callback cancels. */
int opt_loop_tick(opt_loop *L);
/* Whether best_e2 has not fallen by rel_tolerance for stall_iterations steps. */
bool opt_loop_stalled(opt_loop *L);
/* cur := trial, whose E2 is te2 and whose values are in run.value (the last evaluation); cur
 * becomes the best when it is (for the result and the trace). */
void opt_loop_accept(opt_loop *L, double te2);
/* Records st (of E2 e2) as the new best when it is lower and a valid pattern: no two samples of
 * a kernel at the same position (clamping two points into the same corner of their boxes would
 * make one; the pattern constructors refuse such patterns). Returns whether it was taken. */
bool opt_loop_offer_best(opt_loop *L, const opt_state *st, double e2);

/* The step rules. */
int opt_descend_laine_aila(opt_loop *L);
int opt_descend_minimax(opt_loop *L);
int opt_descend_smooth(opt_loop *L);

int opt_run_init(opt_run *r, const opt_state *st, const aa_metric_params *metric,
                 const aa_optimize_params *params, aa_error *err);
void opt_run_free(opt_run *r);
/* E2 of the state's current kernels (opt_state_apply first); fills r->value and r->smoothed.
 * AA_ECANCELED when the progress callback asks to stop. */
int opt_run_eval_e2(opt_run *r, opt_state *st, double *e2);
/* Calls the progress callback (rate-limited unless force) with a snapshot of best. */
int opt_report(opt_progress_state *ps, const opt_state *best, double best_e2, long it, long evals,
               double fraction, bool force);
int opt_poll_cancel(const opt_run *r);
/* trial := base - step * (r->dir_x, r->dir_y, r->dir_w), projected onto the sites and
 * renormalised, applied to trial's kernels. */
void opt_run_take_step(const opt_run *r, opt_state *trial, const opt_state *base, double step);
/* Where opt_run_add_term_gradient adds a term's gradient: point m's x and y at
 * x[m - point_base] and y[m - point_base], weight slot s at w[s - weight_base]. Coordinates
 * fixed by their site (lo == hi) get nothing, nor those flagged in frozen_x / frozen_y (NULL:
 * none). */
typedef struct opt_gradient_target {
    double *x, *y, *w;
    size_t point_base, weight_base;
    const unsigned char *frozen_x, *frozen_y;
} opt_gradient_target;
/* Adds factor * grad E1 of kernel k at angle a (factor carries W(theta) and the rule's scale)
 * to the free variables of the mode: mirror signs applied, samples shared by kernels summed.
 * With r->kink_width > 0, the gradient of the kink-smoothed E1. */
int opt_run_add_term_gradient(opt_run *r, const opt_state *st, size_t k, size_t a, double factor,
                              const opt_gradient_target *to);
/* dst's variables := src's (same shape), applied to dst's kernels. */
void opt_state_copy_vars(opt_state *dst, const opt_state *src);

#endif
