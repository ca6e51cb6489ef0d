/* The edge model: a scene's rendered RMSE predicted from its edge histogram and the pattern's
 * unweighted E1, with no fitted parameter and no rendering (issue 18).
 *
 * Along a straight edge whose offsets against the sample grid are spread evenly, the summed
 * squared pixel error per unit length is the integral of (ghat - g)² over the edge offset, i.e.
 * E1(θ)² by definition (metric.h), averaged over the kernels the edge meets. Hence
 *   sum_sq ≈ Σ_d length[d] · mean_k E1_k(θ_d)²    (θ_d = d degrees, the bin centre)
 *   rmse   ≈ 255 · sqrt(sum_sq / N),               N = width · height.
 * E1 is unweighted (W ≡ 1) and computed with the reference filter of the render.
 *
 * Pixel-locked edges (straight, with a small integer normal direction, edge_histogram.h) meet
 * the pixel grid at a lattice of offsets only: for them the integral becomes the sum over one
 * period of that lattice along the edge (which also cycles through the tile's kernels),
 * evaluated exactly. Their part is
 * reported in locked_sq. Detail below the pixel scale is not covered: its area share is
 * reported, its error is not estimated. */
#ifndef AA_PREDICT_H
#define AA_PREDICT_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"
#include "aa_pattern.h"
#include "edge_histogram.h"

typedef struct aa_prediction {
    double rmse;                 /* 0..255 scale */
    double sum_sq;               /* predicted sum over pixels of (pattern - reference)², 0..1 */
    double bin_sq[AA_EDGE_BINS]; /* per-bin part of sum_sq (locked edges in their bins) */
    double e1_rms[AA_EDGE_BINS]; /* sqrt(mean_k E1_k(θ_d)²), 0 where the scene has no edge */
    double locked_sq;            /* part of sum_sq from pixel-locked edges */
    double segment_sq;           /* part of sum_sq summed over segments (AA_PREDICT_SEGMENT_SUMS) */
    double subpixel_area_share;  /* share of the image below the pixel scale: not covered */
    size_t pixels;               /* N */
} aa_prediction;

/* Model flags for the _with variants (docs/predict.md, "Against the reference the render
 * computes"); 0 is the model, what aa_predict_rmse and aa_predict_e1_rms compute:
 *  - AA_PREDICT_REFERENCE_PROFILE: E1 measured against g_θ, the step response the renderer's
 *    separable reference really has across an edge at the bin's angle (edge_profile.h), not
 *    against the filter's 1-D g (equal at 0° and 90°);
 *  - AA_PREDICT_SEGMENT_SUMS: the histogram's straight segments (segment[], the half-plane's
 *    line and the triangles' sides) summed exactly over their pixels, against g_θ, instead of
 *    L·E1²: the pixels' real offsets along a finite edge, which near a rational slope (27° is
 *    2:1 + 0.4°) are not spread evenly over the lattice gaps.
 * Locked edges are always summed against the true reference. */
#define AA_PREDICT_REFERENCE_PROFILE 1u
#define AA_PREDICT_SEGMENT_SUMS 2u
#define AA_PREDICT_EXACT_REFERENCE (AA_PREDICT_REFERENCE_PROFILE | AA_PREDICT_SEGMENT_SUMS)

/* f: the reference filter (NULL: the default). E1 against g (AA_PREDICT_PROFILE_FILTER).
 * Errors: AA_EINVAL (empty pattern),
 * AA_ENOMEM. */
int aa_predict_rmse(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                    aa_prediction *out, aa_error *err);

/* aa_predict_rmse with the model flags above. */
int aa_predict_rmse_with(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                         unsigned model, aa_prediction *out, aa_error *err);

/* The g_θ tables a model other than 0 needs for one filter and histogram (h; NULL: bins only),
 * at the bins where want[d] (NULL: where h has length, locked bins included; every bin when h is
 * NULL too), and one per kept segment: built once (about 1 ms per distinct profile, 46 at
 * most), read-only afterwards, shared by any number of patterns and threads. Errors: AA_ENOMEM. */
typedef struct aa_predict_tables aa_predict_tables;
int aa_predict_tables_new(const aa_filter *f, const aa_edge_histogram *h, const bool *want,
                          aa_predict_tables **out, aa_error *err);
void aa_predict_tables_free(aa_predict_tables *t);
/* How many g_θ tables aa_predict_tables_new(f, h, want) builds (for callers that cap work). */
size_t aa_predict_tables_count(const aa_edge_histogram *h, const bool *want);

/* aa_predict_rmse_with with tables from aa_predict_tables_new(f, h, NULL) (NULL: built and freed
 * in this call). AA_EINVAL ("tables") when they lack a bin the histogram needs. */
int aa_predict_rmse_tables(const aa_pattern *p, const aa_filter *f, const aa_edge_histogram *h,
                           unsigned model, const aa_predict_tables *tables, aa_prediction *out,
                           aa_error *err);

/* sqrt(mean over kernels of E1_k(θ_d)²), unweighted, with filter f (NULL: the default), at the
 * bin centres d where want[d], or at every bin when want is NULL; 0 elsewhere. The values
 * aa_predict_rmse uses (its e1_rms), for drawing the pattern's side of the model at every angle.
 * Errors: AA_EINVAL (empty pattern). */
int aa_predict_e1_rms(const aa_pattern *p, const aa_filter *f, const bool *want,
                      double e1_rms[AA_EDGE_BINS], aa_error *err);
int aa_predict_e1_rms_with(const aa_pattern *p, const aa_filter *f, const bool *want,
                           unsigned model, double e1_rms[AA_EDGE_BINS], aa_error *err);
/* aa_predict_e1_rms_with with shared tables (aa_predict_tables_new with the same filter and a
 * want covering this one; NULL: built and freed in this call). AA_EINVAL ("tables") when they
 * lack a bin. */
int aa_predict_e1_rms_tables(const aa_pattern *p, const aa_filter *f, const bool *want,
                             unsigned model, const aa_predict_tables *tables,
                             double e1_rms[AA_EDGE_BINS], aa_error *err);

/* A scene to predict on, for callbacks: aa_predict_rmse_of(user = an aa_predict_target, ...) has
 * the signature of aa_scene_objective.exact (objective_scene.h) and writes the prediction's rmse.
 */
typedef struct aa_predict_target {
    const aa_filter *filter;
    const aa_edge_histogram *histogram;
} aa_predict_target;
int aa_predict_rmse_of(void *user, const aa_pattern *p, double *rmse, aa_error *err);

/* Spearman's rank correlation of a[] and b[] (ties get their mean rank); NaN when n < 2 or
 * either side is constant. O(n²): meant for a handful of patterns. */
double aa_spearman(const double *a, const double *b, size_t n);

#endif
