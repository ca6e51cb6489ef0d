/* The sorted order of a kernel's projections, carried from one angle to the next (order.c).
 *
 * A workspace holds the projections p and the samples' input positions (index), in the order
 * of (p, index): ties are ordered by index, so the sorted order, and every sum taken over it,
 * does not depend on the order it was found from. The first angle of a kernel sorts from the
 * input order (aa_order_fresh). A neighbouring angle starts from the previous angle's order,
 * in which each entry is a few places from its new place (aa_order_resort):
 *  - the rank pass (x86-64 with AVX-512 or AVX2, chosen at run time): each entry's new place is
 *    its old place, plus the entries in the 16 after it that now sort before it, minus those in
 *    the 16 before it that now sort after it; vector comparisons, no branch per entry. It holds
 *    when no entry moves past more than 16 others, which the pass checks on its result (every
 *    place written once, in order); when the check fails it changes nothing and the kernel's
 *    remaining angles use the insertion pass.
 *  - the insertion pass: nearly linear, but about one mispredicted branch per moving entry.
 * Both give the same order, so the choice never changes a result. */
#ifndef AA_METRIC_ORDER_H
#define AA_METRIC_ORDER_H

#include <stdbool.h>
#include <stddef.h>

#include "metric.h"

/* Entries an entry may move past in the rank pass (its comparison window on either side). */
#define AA_ORDER_WINDOW 16
/* Below this many samples the insertion pass is used: its few moves cost less than the rank
 * pass (measured on random kernels: equal at 32 samples, rank 14 % faster at 48, 22 % at 64). */
#define AA_ORDER_RANK_MIN 40

/* Whether this CPU runs the pass (the insertion pass runs everywhere). */
bool aa_order_pass_supported(aa_order_pass pass);

/* Sorts ws->p, ws->index (n entries) from the input order: p from ws->in_p, index 0..n-1. Also
 * chooses the pass for the kernel's following angles (ws->order_pass and the CPU, n). */
void aa_order_fresh(aa_metric_workspace *ws, size_t n);

/* Sorts ws->p, ws->index from the previous angle's order (p recomputed in that order). */
void aa_order_resort(aa_metric_workspace *ws, size_t n);

/* One rank pass of the given kind (a rank pass the CPU supports): true when it sorted the
 * arrays, false when its window did not hold (arrays unchanged). For the tests. */
bool aa_order_rank_pass(aa_metric_workspace *ws, size_t n, aa_order_pass pass);

/* The insertion pass alone (for the tests). */
void aa_order_insertion_pass(aa_metric_workspace *ws, size_t n);

#endif
