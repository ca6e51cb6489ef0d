/* Banded multi-threaded reference (tile_parallel.h). */
#define _POSIX_C_SOURCE 200809L
#include "tile_parallel.h"

#include <stdatomic.h>
#include <string.h>

typedef struct band {
    const aa_scene *scene;
    aa_reference_params rp;
    double offset;
    aa_image *out;
    aa_rect rect;
    aa_reference_stats st;
    aa_error err;
    int rc;
    atomic_int *stop;
    const aa_reference_params *caller; /* band 0 forwards progress to it */
} band;

static int band_progress(void *user, double fraction)
{
    band *b = user;
    if (b->caller && b->caller->progress && b->caller->progress(b->caller->user, fraction))
        atomic_store(b->stop, 1);
    return atomic_load(b->stop);
}

static void band_main(void *arg)
{
    band *b = arg;
    b->rc = aa_render_reference(b->scene, &b->rp, b->offset, b->out, &b->rect, &b->st, &b->err);
    if (b->rc && b->rc != AA_ECANCELED)
        atomic_store(b->stop, 1);
}

int tile_reference_parallel(const aa_scene *s, const aa_reference_params *rp, double out_offset,
                            aa_image *out, int threads, aa_reference_stats *st, aa_error *err)
{
    if (threads > TILE_MAX_THREADS)
        threads = TILE_MAX_THREADS;
    if (threads > out->height / 8)
        threads = out->height / 8; /* bands of fewer rows mostly resample their borders */
    if (threads <= 1)
        return aa_render_reference(s, rp, out_offset, out, NULL, st, err);
    atomic_int stop = 0;
    band bands[TILE_MAX_THREADS];
    for (int k = 0; k < threads; k++) {
        band *b = &bands[k];
        memset(b, 0, sizeof *b);
        b->scene = s;
        b->rp = *rp;
        b->rp.progress = band_progress;
        b->rp.user = b;
        b->offset = out_offset;
        b->out = out;
        b->rect =
            (aa_rect){0, out->height * k / threads, out->width, out->height * (k + 1) / threads};
        b->stop = &stop;
        b->caller = k == 0 ? rp : NULL;
    }
    aa_fork_join(bands, sizeof *bands, threads, band_main);
    int rc = AA_OK;
    if (st)
        memset(st, 0, sizeof *st);
    for (int k = 0; k < threads; k++) {
        if (bands[k].rc && (rc == AA_OK || rc == AA_ECANCELED)) {
            rc = bands[k].rc;
            if (err)
                *err = bands[k].err;
        }
        if (st) {
            st->pixels += bands[k].st.pixels;
            st->pixels_supersampled += bands[k].st.pixels_supersampled;
            st->input_pixels += bands[k].st.input_pixels;
            st->samples += bands[k].st.samples;
        }
    }
    return rc;
}
