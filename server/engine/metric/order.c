/* The sorted order of a kernel's projections from angle to angle; see order.h. */
#include "order.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define AA_ORDER_X86 1
#include <immintrin.h>
#endif

/* Sorted order: by p, ties by input index. */
static inline bool before(double pa, uint32_t ia, double pb, uint32_t ib)
{
    return pa < pb || (pa == pb && ia < ib);
}

/* Entry i moved back to its place in the sorted entries before it. */
static inline void insert_entry(double *p, uint32_t *ix, size_t i)
{
    double pi = p[i];
    uint32_t ii = ix[i];
    size_t j = i;
    while (j > 0 && before(pi, ii, p[j - 1], ix[j - 1])) {
        p[j] = p[j - 1];
        ix[j] = ix[j - 1];
        j--;
    }
    p[j] = pi;
    ix[j] = ii;
}

/* Insertion pass over ws's keys (p, index): nearly linear when they are almost sorted, as after
 * the previous angle of the same kernel. An entry moves only if it sorts before the largest
 * entry ahead of it (when its turn comes, the prefix ahead holds the same entries, sorted), so a
 * first loop lists the entries whose p is at most the largest p ahead, without a branch per
 * entry: on neighbouring angles of a pattern's kernel about half of the entries move, and a
 * branch per entry mispredicts about every other time. Then each listed entry is inserted (an
 * entry that ties that p stays if its index is larger). The list goes to the second half of
 * ws->index. */
void aa_order_insertion_pass(aa_metric_workspace *ws, size_t n)
{
    double *p = ws->p, mp = p[0];
    uint32_t *ix = ws->index, *moves = ws->index + ws->capacity;
    size_t count = 0;
    for (size_t i = 1; i < n; i++) {
        double pi = p[i];
        moves[count] = (uint32_t)i;
        count += (size_t)(pi <= mp);
        mp = pi > mp ? pi : mp;
    }
    for (size_t m = 0; m < count; m++)
        insert_entry(p, ix, moves[m]);
}

/* Stable bottom-up merge sort of (p, index) from input order (ties stay in index order), for a
 * first sort of many samples; index's second half and tail are the scratch. */
static void merge_sort_keys(aa_metric_workspace *ws, size_t n)
{
    double *p = ws->p, *pt = ws->tail;
    uint32_t *ix = ws->index, *it = ws->index + ws->capacity;
    for (size_t width = 1; width < n; width *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * width) {
            size_t mid = lo + width < n ? lo + width : n,
                   hi = lo + 2 * width < n ? lo + 2 * width : n;
            size_t i = lo, j = mid, k = lo;
            while (i < mid && j < hi) {
                if (p[j] < p[i]) {
                    pt[k] = p[j];
                    it[k++] = ix[j++];
                } else {
                    pt[k] = p[i];
                    it[k++] = ix[i++];
                }
            }
            while (i < mid) {
                pt[k] = p[i];
                it[k++] = ix[i++];
            }
            while (j < hi) {
                pt[k] = p[j];
                it[k++] = ix[j++];
            }
        }
        memcpy(p, pt, n * sizeof *p);
        memcpy(ix, it, n * sizeof *ix);
    }
}

bool aa_order_pass_supported(aa_order_pass pass)
{
    switch (pass) {
    case AA_ORDER_INSERTION:
        return true;
#ifdef AA_ORDER_X86
    case AA_ORDER_RANK_AVX2:
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
    case AA_ORDER_RANK_AVX512:
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("popcnt");
#endif
    default:
        return false;
    }
}

/* The pass for a kernel of n samples under the workspace's choice. */
static aa_order_pass choose_pass(aa_order_pass wanted, size_t n)
{
    if (n < AA_ORDER_RANK_MIN || wanted == AA_ORDER_INSERTION)
        return AA_ORDER_INSERTION;
    if (wanted != AA_ORDER_AUTO)
        return aa_order_pass_supported(wanted) ? wanted : AA_ORDER_INSERTION;
    if (aa_order_pass_supported(AA_ORDER_RANK_AVX512))
        return AA_ORDER_RANK_AVX512;
    if (aa_order_pass_supported(AA_ORDER_RANK_AVX2))
        return AA_ORDER_RANK_AVX2;
    return AA_ORDER_INSERTION;
}

void aa_order_fresh(aa_metric_workspace *ws, size_t n)
{
    double *p = ws->p;
    uint32_t *ix = ws->index;
    for (size_t i = 0; i < n; i++) {
        p[i] = ws->in_p[i];
        ix[i] = (uint32_t)i;
    }
    if (n > 32) {
        merge_sort_keys(ws, n);
    } else {
        for (size_t i = 1; i < n; i++)
            insert_entry(p, ix, i);
    }
    ws->kernel_pass = AA_ORDER_AUTO; /* chosen at the kernel's first re-sort */
}

#ifdef AA_ORDER_X86
/* The rank pass in three steps. Setup: p copied between pads of -inf (before) and +inf (after),
 * so every window lies inside the buffer and the pads never count (no p is below -inf or above
 * +inf); the output places (tail) filled with NaN. The ranks: each entry stored at its place in
 * tail and the second half of index. Check: every place written (a NaN left fails every
 * comparison) and the places in (p, index) order; only then copied back. Tied entries keep
 * their old order here; where that is not their index order, the check fails and the insertion
 * pass orders them. */
static const double *rank_setup(aa_metric_workspace *ws, size_t n)
{
    double *pp = ws->padded + AA_ORDER_WINDOW;
    for (size_t t = 0; t < AA_ORDER_WINDOW; t++) {
        pp[-1 - (ptrdiff_t)t] = -INFINITY;
        pp[n + t] = INFINITY;
    }
    memcpy(pp, ws->p, n * sizeof *pp);
    for (size_t k = 0; k < n; k++)
        ws->tail[k] = NAN;
    return pp;
}

/* The check in one lane, with ties (the vector checks pass strictly increasing p only), and
 * the copy back. */
static bool rank_check(aa_metric_workspace *ws, size_t n, bool strictly_increasing)
{
    const double *op = ws->tail;
    const uint32_t *oi = ws->index + ws->capacity;
    bool ok = strictly_increasing;
    if (!ok) {
        ok = op[n - 1] == op[n - 1];
        for (size_t k = 0; k + 1 < n; k++)
            ok &= (op[k] < op[k + 1]) | ((op[k] == op[k + 1]) & (oi[k] < oi[k + 1]));
    }
    if (ok) {
        memcpy(ws->p, op, n * sizeof *op);
        memcpy(ws->index, oi, n * sizeof *oi);
    }
    return ok;
}

/* Entry i of the old order stored at its place: ahead and behind are the masks of the entries
 * in the window before it that now sort after it and of those after it that now sort before it. */
static inline void rank_store(aa_metric_workspace *ws, const double *pp, size_t i, unsigned ahead,
                              unsigned behind)
{
    size_t place = i + (size_t)__builtin_popcount(behind) - (size_t)__builtin_popcount(ahead);
    ws->tail[place] = pp[i];
    ws->index[ws->capacity + place] = ws->index[i];
}

/* Eight lanes: the 16 entries before i (ahead) and the 16 after it (behind), two comparisons
 * each. */
__attribute__((target("avx512f,popcnt"))) static bool rank_places_avx512(aa_metric_workspace *ws,
                                                                         const double *pp, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        __m512d key = _mm512_set1_pd(pp[i]);
        unsigned ahead =
            (unsigned)_mm512_cmp_pd_mask(_mm512_loadu_pd(pp + i - 16), key, _CMP_GT_OQ) |
            (unsigned)_mm512_cmp_pd_mask(_mm512_loadu_pd(pp + i - 8), key, _CMP_GT_OQ) << 8;
        unsigned behind =
            (unsigned)_mm512_cmp_pd_mask(_mm512_loadu_pd(pp + i + 1), key, _CMP_LT_OQ) |
            (unsigned)_mm512_cmp_pd_mask(_mm512_loadu_pd(pp + i + 9), key, _CMP_LT_OQ) << 8;
        rank_store(ws, pp, i, ahead, behind);
    }
    /* whether op[k] < op[k + 1] for every k (false at a NaN) */
    const double *op = ws->tail;
    __mmask8 all = 0xff;
    size_t k = 0;
    for (; k + 9 <= n; k += 8)
        all &= _mm512_cmp_pd_mask(_mm512_loadu_pd(op + k), _mm512_loadu_pd(op + k + 1), _CMP_LT_OQ);
    bool increasing = all == 0xff;
    for (; k + 1 < n; k++)
        increasing &= op[k] < op[k + 1];
    return increasing && op[n - 1] == op[n - 1];
}

/* Four lanes, four comparisons on each side. */
__attribute__((target("avx2,popcnt"))) static bool rank_places_avx2(aa_metric_workspace *ws,
                                                                    const double *pp, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        __m256d key = _mm256_set1_pd(pp[i]);
        unsigned ahead = 0, behind = 0;
        for (int q = 0; q < 4; q++) {
            __m256d a = _mm256_loadu_pd(pp + i - 16 + 4 * q),
                    b = _mm256_loadu_pd(pp + i + 1 + 4 * q);
            ahead |= (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(a, key, _CMP_GT_OQ)) << (4 * q);
            behind |= (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(b, key, _CMP_LT_OQ)) << (4 * q);
        }
        rank_store(ws, pp, i, ahead, behind);
    }
    const double *op = ws->tail;
    __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    size_t k = 0;
    for (; k + 5 <= n; k += 4)
        all = _mm256_and_pd(
            all, _mm256_cmp_pd(_mm256_loadu_pd(op + k), _mm256_loadu_pd(op + k + 1), _CMP_LT_OQ));
    bool increasing = _mm256_movemask_pd(all) == 0xf;
    for (; k + 1 < n; k++)
        increasing &= op[k] < op[k + 1];
    return increasing && op[n - 1] == op[n - 1];
}
#endif

/* A rank pass of a kind this CPU runs, on n >= 2 entries (checked once per kernel, by
 * choose_pass, not at every angle). */
static bool rank_pass(aa_metric_workspace *ws, size_t n, aa_order_pass pass)
{
#ifdef AA_ORDER_X86
    if (pass == AA_ORDER_RANK_AVX512)
        return rank_check(ws, n, rank_places_avx512(ws, rank_setup(ws, n), n));
    if (pass == AA_ORDER_RANK_AVX2)
        return rank_check(ws, n, rank_places_avx2(ws, rank_setup(ws, n), n));
#else
    (void)ws;
    (void)n;
    (void)pass;
#endif
    return false;
}

bool aa_order_rank_pass(aa_metric_workspace *ws, size_t n, aa_order_pass pass)
{
    return n >= 2 && pass != AA_ORDER_INSERTION && aa_order_pass_supported(pass) &&
           rank_pass(ws, n, pass);
}

void aa_order_resort(aa_metric_workspace *ws, size_t n)
{
    if (ws->kernel_pass == AA_ORDER_AUTO)
        ws->kernel_pass = choose_pass(ws->order_pass, n);
    if (ws->kernel_pass != AA_ORDER_INSERTION) {
        if (rank_pass(ws, n, ws->kernel_pass)) {
            ws->rank_passes++;
            return;
        }
        ws->kernel_pass = AA_ORDER_INSERTION; /* not again for this kernel */
    }
    aa_order_insertion_pass(ws, n);
    ws->insertion_passes++;
}
