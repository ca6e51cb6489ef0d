/* Tile render and incremental animation (render.h). */
#include "render.h"

#include <math.h>
#include <string.h>
#include <time.h>

#include "aa_metric.h"

aa_render_params aa_render_params_default(aa_scene_shape shape)
{
    aa_render_params p;
    memset(&p, 0, sizeof p);
    p.scene = aa_scene_params_default(shape);
    p.reference = aa_reference_params_default();
    p.acuity = NULL;
    p.skip = true;
    return p;
}

double aa_seconds_now(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

int aa_pattern_e2(const aa_pattern *p, const aa_filter *f, const aa_acuity *a, double *e2,
                  aa_error *err)
{
    aa_filter fd;
    aa_acuity ad;
    if (!f) {
        aa_filter_default(&fd);
        f = &fd;
    }
    if (!a) {
        aa_acuity_naiman(&ad);
        a = &ad;
    }
    aa_metric_params mp = {f, a, NULL, 0, 0};
    aa_evaluation ev;
    memset(&ev, 0, sizeof ev);
    int rc = aa_evaluate(p, &mp, &ev, err);
    if (!rc)
        *e2 = ev.e2;
    aa_evaluation_free(&ev);
    return rc;
}

void aa_render_result_free(aa_render_result *r)
{
    if (!r)
        return;
    aa_image_free(&r->pattern);
    aa_image_free(&r->reference);
}

int aa_render_tile(const aa_render_params *rp, const aa_pattern *p, aa_render_result *out,
                   aa_error *err)
{
    memset(out, 0, sizeof *out);
    aa_scene scene;
    int rc = aa_scene_init(&scene, &rp->scene, err);
    if (!rc)
        rc = aa_pattern_e2(p, rp->reference.filter, rp->acuity, &out->e2, err);
    if (!rc)
        rc = aa_image_init(&out->pattern, rp->scene.width, rp->scene.height, err);
    if (!rc)
        rc = aa_image_init(&out->reference, rp->scene.width, rp->scene.height, err);
    if (!rc) {
        double t0 = aa_seconds_now();
        rc = aa_render_pattern(&scene, p, rp->skip, &out->pattern, NULL, &out->raster, err);
        out->pattern_seconds = aa_seconds_now() - t0;
    }
    if (!rc) {
        double t0 = aa_seconds_now();
        rc = aa_render_reference(&scene, &rp->reference, aa_output_offset(p->kernel_size),
                                 &out->reference, NULL, &out->ref, err);
        out->reference_seconds = aa_seconds_now() - t0;
    }
    if (!rc) {
        aa_diff_init(&out->diff);
        aa_diff_add(&out->diff, &out->pattern, &out->reference);
        aa_diff_finish(&out->diff);
    }
    if (rc)
        aa_render_result_free(out);
    return rc;
}

int aa_animation_init(aa_animation *a, const aa_render_params *rp, const aa_pattern *p,
                      aa_error *err)
{
    memset(a, 0, sizeof *a);
    a->params = *rp;
    a->pattern = p;
    aa_scene probe;
    int rc = aa_scene_init(&probe, &rp->scene, err);
    if (!rc)
        rc = aa_image_init(&a->pattern_img, rp->scene.width, rp->scene.height, err);
    if (!rc)
        rc = aa_image_init(&a->reference_img, rp->scene.width, rp->scene.height, err);
    if (rc)
        aa_animation_free(a);
    return rc;
}

void aa_animation_free(aa_animation *a)
{
    aa_image_free(&a->pattern_img);
    aa_image_free(&a->reference_img);
}

/* Pixels whose footprint (half-width reach around the output point) meets box. */
static aa_rect footprint_rect(const double box[4], double off, double reach)
{
    aa_rect r = {(int)floor(box[0] - reach - off) - 1, (int)floor(box[1] - reach - off) - 1,
                 (int)ceil(box[2] + reach - off) + 2, (int)ceil(box[3] + reach - off) + 2};
    return r;
}

int aa_animation_frame(aa_animation *a, aa_animation_frame_stats *st, aa_error *err)
{
    memset(st, 0, sizeof *st);
    aa_scene_params sp = a->params.scene;
    if (a->next_frame >= sp.frames)
        return aa_error_set(err, AA_EINVAL, "frame", "the animation has %d frames", sp.frames);
    sp.frame = a->next_frame;
    aa_scene scene;
    int rc = aa_scene_init(&scene, &sp, err);
    if (rc)
        return rc;
    double box[4];
    bool bounded = aa_scene_bounds(&scene, box);
    double off = aa_output_offset(a->pattern->kernel_size);
    double reach = (a->params.reference.filter ? a->params.reference.filter->radius : 2.0);
    for (size_t k = 0; k < a->pattern->kernel_count; k++)
        for (size_t n = 0; n < a->pattern->kernels[k].count; n++)
            reach = fmax(reach, fmax(fabs(a->pattern->kernels[k].samples[n].x),
                                     fabs(a->pattern->kernels[k].samples[n].y)));
    aa_rect region = aa_image_rect(&a->pattern_img);
    if (a->next_frame > 0 && bounded && a->prev_bounded) {
        /* Outside both frames' content every footprint sees only background: unchanged. */
        aa_rect now = footprint_rect(box, off, reach);
        aa_rect before = footprint_rect(a->prev_box, off, reach);
        region = aa_rect_intersect(region, aa_rect_union(now, before));
    }
    st->frame = sp.frame;
    st->pixels_recomputed = aa_rect_area(region);
    double t0 = aa_seconds_now();
    rc = aa_render_pattern(&scene, a->pattern, a->params.skip, &a->pattern_img, &region,
                           &st->raster, err);
    st->pattern_seconds = aa_seconds_now() - t0;
    if (rc)
        return rc;
    t0 = aa_seconds_now();
    rc = aa_render_reference(&scene, &a->params.reference, off, &a->reference_img, &region,
                             &st->ref, err);
    st->reference_seconds = aa_seconds_now() - t0;
    if (rc)
        return rc;
    aa_diff_init(&st->diff);
    aa_diff_add(&st->diff, &a->pattern_img, &a->reference_img);
    aa_diff_finish(&st->diff);
    a->prev_bounded = bounded;
    memcpy(a->prev_box, box, sizeof box);
    a->next_frame++;
    return AA_OK;
}
