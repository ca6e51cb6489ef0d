/* The iterated local search's move (optimizer_perturb.h, private): jittered samples move on the
 * tile's torus and may change pixels, always landing inside a pixel, never on its edges; with
 * keep_pixels they stay in their own. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "aa_core.h"
#include "aa_optimizer.h"
#include "aa_pattern.h"
#include "optimizer_perturb.h"

/* A uniform P(16,16,4) pattern with sample 0 OPT_SITE_MARGIN inside the tile's right edge (x =
 * 4) and sample 1 that far inside the left edge of its pixel's right neighbour. */
static void pattern_with_samples_at_edges(const aa_filter *filter, aa_pattern *out)
{
    aa_family fam;
    aa_pattern u;
    aa_rng rng;
    aa_rng_seed(&rng, 15, 1);
    assert_int_equal(aa_family_parse("P(16,16,4)", &fam, NULL), AA_OK);
    assert_int_equal(aa_family_seed(&fam, AA_SEED_UNIFORM, filter, &rng, &u, NULL), AA_OK);
    aa_point pts[64];
    assert_int_equal(u.tile_count, 64);
    for (size_t i = 0; i < u.tile_count; i++)
        pts[i] = (aa_point){u.tile_samples[i].x, u.tile_samples[i].y};
    /* Find a sample in the right column and one in a pixel with a left neighbour. */
    size_t right = 64, inner = 64;
    for (size_t i = 0; i < 64; i++) {
        if (floor(pts[i].x) == 3 && right == 64)
            right = i;
        else if (floor(pts[i].x) == 1 && inner == 64)
            inner = i;
    }
    assert_true(right < 64 && inner < 64);
    /* Samples 0 and 1 of the built pattern (tile_samples keep the given order). */
    aa_point ordered[64];
    size_t n = 0;
    ordered[n++] = (aa_point){4 - OPT_SITE_MARGIN, pts[right].y};
    ordered[n++] = (aa_point){1 + OPT_SITE_MARGIN, pts[inner].y};
    for (size_t i = 0; i < 64; i++)
        if (i != right && i != inner)
            ordered[n++] = pts[i];
    aa_tile_spec spec = {4, 4, false, 64, ordered, NULL, NULL, filter};
    assert_int_equal(aa_pattern_from_tile(out, &spec, 0, NULL), AA_OK);
    assert_true(aa_perturbable(out));
    aa_pattern_free(&u);
}

/* draws neighbours of p; counts how often samples 0 and 1 left their pixels */
static void draw_neighbours(const aa_pattern *p, bool keep_pixels, const aa_filter *filter,
                            int draws, int *wrapped, int *crossed)
{
    aa_rng rng;
    aa_rng_seed(&rng, 15, 2);
    *wrapped = *crossed = 0;
    for (int d = 0; d < draws; d++) {
        aa_pattern q;
        assert_int_equal(
            opt_jittered_neighbour(p, 0.02, d % 2, keep_pixels, filter, &rng, &q, NULL), AA_OK);
        assert_int_equal(q.tile_count, p->tile_count);
        assert_string_equal(q.family, p->family);
        assert_true(aa_perturbable(&q));
        for (size_t i = 0; i < q.tile_count; i++) {
            const double c[2] = {q.tile_samples[i].x, q.tile_samples[i].y};
            for (int k = 0; k < 2; k++) {
                double f = c[k] - floor(c[k]);
                assert_true(c[k] >= 0 && c[k] < 4);
                /* inside its pixel: at least the margin (up to rounding) from either edge */
                assert_true(f >= 0.999 * OPT_SITE_MARGIN && f <= 1 - 0.999 * OPT_SITE_MARGIN);
            }
        }
        /* sample 0 sat against x = 4: a move to the right wraps round to x = 0+ */
        *wrapped += q.tile_samples[0].x < 1;
        /* sample 1 sat against x = 1 of pixel column 1: a move left takes it into column 0 */
        *crossed += q.tile_samples[1].x < 1;
        aa_pattern_free(&q);
    }
}

static void jitter_crosses_pixel_edges_and_wraps(void **state)
{
    (void)state;
    aa_filter filter;
    aa_filter_default(&filter);
    aa_pattern p;
    pattern_with_samples_at_edges(&filter, &p);
    assert_true(p.tile_samples[0].x == 4 - OPT_SITE_MARGIN);
    assert_true(p.tile_samples[1].x == 1 + OPT_SITE_MARGIN);
    int wrapped, crossed, draws = 200;
    draw_neighbours(&p, false, &filter, draws, &wrapped, &crossed);
    /* Each is a fair coin per draw (200 draws: 100 +- 7); clamping in place would give 0. */
    assert_true(wrapped > draws / 4 && wrapped < 3 * draws / 4);
    assert_true(crossed > draws / 4 && crossed < 3 * draws / 4);
    /* keep_pixels: the earlier move, every sample stays in its pixel */
    draw_neighbours(&p, true, &filter, draws, &wrapped, &crossed);
    assert_int_equal(wrapped, 0);
    assert_int_equal(crossed, 0);
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(jitter_crosses_pixel_edges_and_wraps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
