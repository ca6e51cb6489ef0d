/* Reference cost grows with edge length, not area: the Siemens star's sparse reference at 256^2
 * and 512^2 (ratio expected ~2x, not 4x), the fraction of pixels left out, and the speed-up
 * over supersampling every pixel, all measured in this run. Set AALAB_BENCH_DENSE_512=1 to
 * also time the dense baseline at 512^2 (about 4x the 256^2 one). */
#include <stdio.h>
#include <stdlib.h>

#include "aa_pattern.h"
#include "aa_render.h"

typedef struct timing {
    double seconds;
    aa_reference_stats st;
} timing;

static int reference_time(int size, bool skip, timing *t)
{
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_SIEMENS_STAR);
    sp.width = sp.height = size;
    aa_scene s;
    aa_image img;
    aa_error err = {0};
    if (aa_scene_init(&s, &sp, &err) || aa_image_init(&img, size, size, &err)) {
        fprintf(stderr, "bench_render: %s\n", err.message);
        return 1;
    }
    aa_reference_params rp = aa_reference_params_default();
    rp.skip = skip;
    double t0 = aa_seconds_now();
    int rc = aa_render_reference(&s, &rp, 0.5, &img, NULL, &t->st, &err);
    t->seconds = aa_seconds_now() - t0;
    aa_image_free(&img);
    if (rc)
        fprintf(stderr, "bench_render: %s\n", err.message);
    return rc != 0;
}

static void print_sparse(int size, const timing *t)
{
    double px = (double)size * size;
    printf("  %4d^2 sparse: %8.3f s  supersampled %7zu of %7.0f pixels (skipped %5.1f%%), "
           "%zu input pixels sampled, %.3g samples\n",
           size, t->seconds, t->st.pixels_supersampled, px,
           100.0 * (1.0 - (double)t->st.pixels_supersampled / px), t->st.input_pixels,
           (double)t->st.samples);
}

int main(void)
{
    timing s256, s512, d256, d512;
    printf("bench_render: Siemens star (16 wedges), reference Mitchell-Netravali (1/3,1/3), "
           "1024 jittered spp\n");
    if (reference_time(256, true, &s256) || reference_time(512, true, &s512))
        return 1;
    print_sparse(256, &s256);
    print_sparse(512, &s512);
    printf("  time ratio 512^2 / 256^2: %.2fx (area ratio 4x; edge-length ratio 2x)\n",
           s512.seconds / s256.seconds);
    if (reference_time(256, false, &d256))
        return 1;
    printf("   256^2 dense (supersample every pixel): %8.3f s, %.3g samples\n", d256.seconds,
           (double)d256.st.samples);
    printf("  speed-up of sparse over dense at 256^2: %.2fx\n", d256.seconds / s256.seconds);
    const char *env = getenv("AALAB_BENCH_DENSE_512");
    if (env && *env == '1') {
        if (reference_time(512, false, &d512))
            return 1;
        printf("   512^2 dense: %8.3f s; speed-up of sparse over dense at 512^2: %.2fx\n",
               d512.seconds, d512.seconds / s512.seconds);
    }

    /* Pattern render cost beside the reference, same scene (FLIPQUAD, 512^2). */
    aa_pattern p;
    aa_render_params rp = aa_render_params_default(AA_SCENE_SIEMENS_STAR);
    rp.scene.width = rp.scene.height = 512;
    aa_render_result r;
    if (aa_pattern_from_preset(&p, aa_preset_find("flipquad"), NULL) ||
        aa_render_tile(&rp, &p, &r, NULL))
        return 1;
    printf("  flipquad 512^2: pattern %.4f s (%zu pixels sampled, %zu coverage samples), "
           "reference %.3f s, ratio %.0fx; RMSE %.3f, max dev %.1f, E2 %.3f\n",
           r.pattern_seconds, r.raster.pixels_sampled, r.raster.samples_evaluated,
           r.reference_seconds, r.reference_seconds / r.pattern_seconds, r.diff.rmse,
           r.diff.max_dev, r.e2);
    /* The same rule for the pattern render: sparse against sampling every pixel. */
    aa_scene scene;
    if (aa_scene_init(&scene, &rp.scene, NULL))
        return 1;
    double t0 = aa_seconds_now();
    int reps = 20;
    for (int k = 0; k < reps; k++)
        aa_render_pattern(&scene, &p, false, &r.pattern, NULL, NULL, NULL);
    double dense = (aa_seconds_now() - t0) / reps;
    t0 = aa_seconds_now();
    for (int k = 0; k < reps; k++)
        aa_render_pattern(&scene, &p, true, &r.pattern, NULL, NULL, NULL);
    double sparse = (aa_seconds_now() - t0) / reps;
    printf("  flipquad 512^2 pattern render: sparse %.4f s, every pixel %.4f s, speed-up %.2fx\n",
           sparse, dense, dense / sparse);
    aa_render_result_free(&r);
    aa_pattern_free(&p);
    return 0;
}
