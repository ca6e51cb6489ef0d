/* Float grey images and the error statistics the renderer reports (pure: no I/O).
 *
 * Pixel (i, j) is px[j * width + i]; j grows downwards (row 0 is the top row of a PNG).
 * Values are linear intensities, nominally 0..1; filtered images (negative lobes, negative
 * pattern weights) may stray slightly outside and are kept unclamped for the statistics. */
#ifndef AA_IMAGE_H
#define AA_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "aa_core.h"

#define AA_IMAGE_MAX_SIDE 4096

typedef struct aa_image {
    int width, height;
    float *px;
} aa_image;

/* A half-open pixel rectangle [x0, x1) x [y0, y1). */
typedef struct aa_rect {
    int x0, y0, x1, y1;
} aa_rect;

/* Allocates a zeroed image. Errors: AA_EINVAL (size out of 1..AA_IMAGE_MAX_SIDE), AA_ENOMEM. */
int aa_image_init(aa_image *img, int width, int height, aa_error *err);
void aa_image_free(aa_image *img);
aa_rect aa_image_rect(const aa_image *img);
/* Intersection; an empty result has x0 >= x1 or y0 >= y1. */
aa_rect aa_rect_intersect(aa_rect a, aa_rect b);
aa_rect aa_rect_union(aa_rect a, aa_rect b);
size_t aa_rect_area(aa_rect r);

/* Error of an approximation against a reference, on the 0..255 scale (Hasselgren et al. 2005,
 * sec. 6.1). The deviation of a pixel is d = 255 |a - r|; rmse and max_dev use d unrounded;
 * histogram[i] counts pixels with round(d) == i (i clamped to 255), and penalised[i] is
 * histogram[i] * i^2 / n, whose sum approximates the MSE (their Fig. 6-7). Accumulate over
 * several images (animation frames) with aa_diff_add, then aa_diff_finish. */
typedef struct aa_diff_stats {
    size_t pixels;
    double sum_sq; /* sum of d^2 */
    double rmse;
    double max_dev;
    size_t histogram[256];
    double penalised[256];
} aa_diff_stats;

void aa_diff_init(aa_diff_stats *s);
/* a and b must have the same size (else AA_EINVAL). */
int aa_diff_add(aa_diff_stats *s, const aa_image *approx, const aa_image *reference);
void aa_diff_finish(aa_diff_stats *s);

/* 8-bit conversions for PNG encoding (out has width*height bytes, row-major, top row first). */
void aa_image_to_gray8(const aa_image *img, uint8_t *out);
/* L&A Fig. 8: white = no error, black = |a - r| >= full_scale (0.1 = 10% absolute error). */
void aa_image_difference_gray8(const aa_image *a, const aa_image *r, double full_scale,
                               uint8_t *out);
/* Nearest-neighbour magnification of the crop rect of an 8-bit image: out has
 * (crop width * scale) x (crop height * scale) bytes. The crop must lie inside the image. */
void aa_gray8_crop_magnify(const uint8_t *in, int width, aa_rect crop, int scale, uint8_t *out);

#endif
