/* The dual of a proximal minimax step: maximise over the unit simplex
 *     phi(lambda) = f . lambda - (delta / 2) lambda' Q lambda,    lambda >= 0, sum lambda = 1,
 * Q symmetric positive semidefinite (a Gram matrix of term gradients), by pairwise Frank-Wolfe
 * with exact line search (Lacoste-Julien & Jaggi 2015: linear convergence on polytopes). Each
 * iteration moves mass from the worst support vertex to the best vertex and costs O(m), since
 * Q lambda is kept up to date. Stops when the Frank-Wolfe duality gap
 *     max_i grad_i - lambda . grad,  grad = f - delta Q lambda,
 * is at most tol (it bounds phi* - phi), or after max_iterations. */
#ifndef AA_SIMPLEX_QP_H
#define AA_SIMPLEX_QP_H

#include <stddef.h>

typedef struct aa_simplex_qp_result {
    double objective; /* phi(lambda) */
    double gap;       /* Frank-Wolfe duality gap at the end (>= phi* - phi) */
    long iterations;
} aa_simplex_qp_result;

/* Q: m x m row-major. lambda: [m], on entry a point of the simplex (warm start) or all zero
 * (start at the vertex of the largest f); on exit the solution. q: [m] scratch, on exit
 * Q lambda. Returns 0, or -1 if m == 0 or delta <= 0. */
int aa_simplex_qp_solve(size_t m, const double *Q, const double *f, double delta, double *lambda,
                        double *q, double tol, long max_iterations, aa_simplex_qp_result *result);

#endif
