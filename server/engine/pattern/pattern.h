/* Antialiasing patterns in the P(s, r, n) families of Laine & Aila (2005), section 3.
 *
 * Coordinates. A pattern repeats every T x T pixels ("the tile"). Tile coordinates put pixel
 * (i, j) at [i, i+1] x [j, j+1]; tile samples lie in [0, T)^2 and each distinct position is one
 * sample that is taken once (this is what defines the cost n = tile_count / T^2).
 * Output pixel (i, j) of the tile has its own reconstruction kernel (so s = T^2 for tile and
 * mirrored forms). A kernel reads the K x K pixel block whose lower-left pixel is
 * (i - (K-1)/2, j - (K-1)/2) (integer division), and reconstructs at the block centre: the
 * pixel centre for odd K, a pixel corner for even K (the output grid shifted by half a pixel,
 * L&A Fig. 3). With border ('+', r = K^2+), samples on the closed block boundary are read too.
 * Kernel samples are stored relative to that output point, as in the wire format.
 *
 * Forms:
 *  - explicit kernels: s kernels of (x, y, w). For s = 1 the samples are taken to repeat every
 *    pixel (T = 1). For s = T^2 the kernels are taken row-major over a T x T tile. Any other s
 *    is accepted for evaluation with tile = 0 (no known repetition; cost = samples / s).
 *  - mirrored: the samples of one pixel (relative to its centre, in [-0.5, 0.5]^2); neighbours
 *    use the pattern mirrored across the shared edge (Hasselgren et al. 2005, App. A): T = 2,
 *    K = 1, border on, s = 4, corner/edge/interior samples cost 0.25/0.5/1.
 *  - tile: T, K, border, tile samples, and per-kernel weights in the kernel's canonical order
 *    (samples of the block ordered by y, then x, ascending), or weights from the reference
 *    filter's impulse response h(x) h(y), normalised (L&A Table 3 "weights from the filter").
 *
 * Weights may be negative. They must sum to 1 per kernel (|sum - 1| <= 1e-9) unless
 * AA_PATTERN_NORMALIZE is given, in which case they are divided by their sum (a sum with
 * |sum| < 1e-12 is an error either way). */
#ifndef AA_PATTERN_H
#define AA_PATTERN_H

#include <stdbool.h>
#include <stddef.h>

#include "aa_core.h"
#include "filter.h"

#define AA_MAX_KERNEL_SAMPLES 4096 /* samples in one kernel */
#define AA_MAX_KERNELS 256         /* s */
#define AA_MAX_TILE 16             /* T */
#define AA_MAX_KERNEL_SIZE 8       /* K */
#define AA_MAX_COORD 1e6           /* |x|, |y| of a kernel sample */
#define AA_MAX_WEIGHT 1e6          /* |w| of a sample (before normalisation) */
#define AA_WEIGHT_SUM_TOLERANCE 1e-9
#define AA_POSITION_EPS 1e-9 /* positions closer than this are the same tile sample */

enum { AA_PATTERN_NORMALIZE = 1u << 0 };

typedef struct aa_sample {
    double x, y, w;
} aa_sample;

typedef struct aa_point {
    double x, y;
} aa_point;

typedef enum aa_pattern_form { AA_FORM_KERNELS, AA_FORM_MIRRORED, AA_FORM_TILE } aa_pattern_form;

/* Where a tile sample sits on the pixel grid; the optimizer keeps each sample on its site. */
typedef enum aa_site {
    AA_SITE_INTERIOR,
    AA_SITE_VERTICAL_EDGE,   /* x is an integer: slides along y */
    AA_SITE_HORIZONTAL_EDGE, /* y is an integer: slides along x */
    AA_SITE_CORNER           /* both integers: fixed */
} aa_site;

typedef struct aa_kernel {
    size_t count;
    aa_sample *samples;  /* relative to the output point */
    size_t *tile_index;  /* tile sample each one is (NULL when pattern->tile == 0) */
    double out_x, out_y; /* output point in tile coordinates */
} aa_kernel;

typedef struct aa_pattern {
    aa_pattern_form form;
    int tile;        /* T, 0 when unknown (explicit kernels with s not a square) */
    int kernel_size; /* K */
    bool border;     /* the '+' of r */
    size_t tile_count;
    aa_point *tile_samples; /* [tile_count], in [0, T)^2 */
    aa_site *tile_site;     /* [tile_count] */
    size_t kernel_count;    /* s */
    aa_kernel *kernels;     /* [s], row-major over the tile's pixels */
    double cost_spp;        /* n */
    char family[48];        /* e.g. "P(4,1+,1.25)" */
    size_t source_count;    /* mirrored form: the one pixel's samples (relative to centre) */
    aa_sample *source;
} aa_pattern;

typedef struct aa_tile_spec {
    int tile;        /* T >= 1 */
    int kernel_size; /* K >= 1 */
    bool border;
    size_t count;
    const aa_point *samples; /* tile coordinates, will be wrapped into [0, T)^2 */
    /* Per-kernel weights in canonical order; weights[k] has weight_counts[k] entries which must
     * equal the number of samples kernel k reads. NULL: from weight_filter (required then). */
    const double *const *weights;
    const size_t *weight_counts;
    const aa_filter *weight_filter;
} aa_tile_spec;

/* All constructors zero *p first; on error *p holds nothing to free (but freeing is safe).
 * Errors name fields relative to the pattern object: "kernels[2][1][0]", "mirrored[0][2]",
 * "tile.samples[3]", "tile.weights[1]", ... */
int aa_pattern_from_kernels(aa_pattern *p, const aa_sample *const *kernels, const size_t *counts,
                            size_t kernel_count, unsigned flags, aa_error *err);
int aa_pattern_from_mirrored(aa_pattern *p, const aa_sample *samples, size_t count, unsigned flags,
                             aa_error *err);
int aa_pattern_from_tile(aa_pattern *p, const aa_tile_spec *spec, unsigned flags, aa_error *err);
int aa_pattern_copy(aa_pattern *dst, const aa_pattern *src);
void aa_pattern_free(aa_pattern *p);

/* Total samples over all kernels (the size of gradient arrays). */
size_t aa_pattern_total_kernel_samples(const aa_pattern *p);
/* Site of a point in tile coordinates (within AA_POSITION_EPS of the grid). */
aa_site aa_site_of(double x, double y);
/* Writes the label "P(s,r,n)" for the given numbers. */
void aa_family_label(char *out, size_t cap, size_t s, int kernel_size, bool border, double n);

#endif
