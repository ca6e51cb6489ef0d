/* Float grey images, error statistics and 8-bit conversions (image.h). */
#include "image.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int aa_image_init(aa_image *img, int width, int height, aa_error *err)
{
    memset(img, 0, sizeof *img);
    if (width < 1 || width > AA_IMAGE_MAX_SIDE)
        return aa_error_set(err, AA_EINVAL, "width", "width must be 1..%d", AA_IMAGE_MAX_SIDE);
    if (height < 1 || height > AA_IMAGE_MAX_SIDE)
        return aa_error_set(err, AA_EINVAL, "height", "height must be 1..%d", AA_IMAGE_MAX_SIDE);
    img->px = calloc((size_t)width * (size_t)height, sizeof *img->px);
    if (!img->px)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    img->width = width;
    img->height = height;
    return AA_OK;
}

void aa_image_free(aa_image *img)
{
    if (!img)
        return;
    free(img->px);
    memset(img, 0, sizeof *img);
}

aa_rect aa_image_rect(const aa_image *img)
{
    return (aa_rect){0, 0, img->width, img->height};
}

static int imax(int a, int b)
{
    return a > b ? a : b;
}

static int imin(int a, int b)
{
    return a < b ? a : b;
}

aa_rect aa_rect_intersect(aa_rect a, aa_rect b)
{
    return (aa_rect){imax(a.x0, b.x0), imax(a.y0, b.y0), imin(a.x1, b.x1), imin(a.y1, b.y1)};
}

aa_rect aa_rect_union(aa_rect a, aa_rect b)
{
    if (aa_rect_area(a) == 0)
        return b;
    if (aa_rect_area(b) == 0)
        return a;
    return (aa_rect){imin(a.x0, b.x0), imin(a.y0, b.y0), imax(a.x1, b.x1), imax(a.y1, b.y1)};
}

size_t aa_rect_area(aa_rect r)
{
    if (r.x1 <= r.x0 || r.y1 <= r.y0)
        return 0;
    return (size_t)(r.x1 - r.x0) * (size_t)(r.y1 - r.y0);
}

void aa_diff_init(aa_diff_stats *s)
{
    memset(s, 0, sizeof *s);
}

int aa_diff_add(aa_diff_stats *s, const aa_image *a, const aa_image *r)
{
    if (a->width != r->width || a->height != r->height)
        return AA_EINVAL;
    size_t n = (size_t)a->width * (size_t)a->height;
    for (size_t k = 0; k < n; k++) {
        double d = 255.0 * fabs((double)a->px[k] - (double)r->px[k]);
        s->sum_sq += d * d;
        if (d > s->max_dev)
            s->max_dev = d;
        long bin = lround(d);
        s->histogram[bin > 255 ? 255 : bin]++;
    }
    s->pixels += n;
    return AA_OK;
}

void aa_diff_finish(aa_diff_stats *s)
{
    double n = s->pixels ? (double)s->pixels : 1.0;
    s->rmse = sqrt(s->sum_sq / n);
    for (int i = 0; i < 256; i++)
        s->penalised[i] = (double)s->histogram[i] * i * i / n;
}

static uint8_t to_byte(double v)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 255;
    return (uint8_t)lround(v * 255.0);
}

void aa_image_to_gray8(const aa_image *img, uint8_t *out)
{
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t k = 0; k < n; k++)
        out[k] = to_byte(img->px[k]);
}

void aa_image_difference_gray8(const aa_image *a, const aa_image *r, double full_scale,
                               uint8_t *out)
{
    assert(a->width == r->width && a->height == r->height && full_scale > 0);
    size_t n = (size_t)a->width * (size_t)a->height;
    for (size_t k = 0; k < n; k++)
        out[k] = to_byte(1.0 - fabs((double)a->px[k] - (double)r->px[k]) / full_scale);
}

void aa_gray8_crop_magnify(const uint8_t *in, int width, aa_rect crop, int scale, uint8_t *out)
{
    /* The crop lies inside the image: proto_decode_crop refuses one that does not. */
    assert(scale >= 1 && crop.x0 >= 0 && crop.y0 >= 0 && crop.x0 <= crop.x1 && crop.y0 <= crop.y1 &&
           crop.x1 <= width);
    int cw = crop.x1 - crop.x0, ch = crop.y1 - crop.y0;
    size_t ow = (size_t)cw * (size_t)scale;
    for (int y = 0; y < ch * scale; y++) {
        const uint8_t *row = in + (size_t)(crop.y0 + y / scale) * (size_t)width + crop.x0;
        uint8_t *o = out + (size_t)y * ow;
        for (size_t x = 0; x < ow; x++)
            o[x] = row[x / (size_t)scale];
    }
}
