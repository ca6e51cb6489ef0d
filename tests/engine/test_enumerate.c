/* Mirrored P(4,1+,n) placement enumeration against an independent count: Burnside's lemma over
 * the 8 symmetries of the square, with the symmetries applied to actual site coordinates
 * (corner points and edge midpoints) rather than to index permutations. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "aa_pattern.h"

/* Slots 0..3 corners, 4..7 edges, in enumerate.h's order. */
static const double slot_x[8] = {-0.5, 0.5, 0.5, -0.5, 0, 0.5, 0, -0.5};
static const double slot_y[8] = {-0.5, -0.5, 0.5, 0.5, -0.5, 0, 0.5, 0};

static void symmetry(int g, double x, double y, double *ox, double *oy)
{
    /* g = 0..7: the 8 matrices with entries in {-1, 0, 1} that map the square to itself. */
    static const int m[8][4] = {{1, 0, 0, 1},  {0, -1, 1, 0}, {-1, 0, 0, -1}, {0, 1, -1, 0},
                                {-1, 0, 0, 1}, {1, 0, 0, -1}, {0, 1, 1, 0},   {0, -1, -1, 0}};
    *ox = m[g][0] * x + m[g][1] * y;
    *oy = m[g][2] * x + m[g][3] * y;
}

static int slot_image(int g, int s)
{
    double x, y;
    symmetry(g, slot_x[s], slot_y[s], &x, &y);
    for (int t = 0; t < 8; t++)
        if (fabs(slot_x[t] - x) < 1e-12 && fabs(slot_y[t] - y) < 1e-12)
            return t;
    return -1;
}

static size_t burnside(int quarters)
{
    size_t fixed_total = 0;
    int emax = quarters / 2;
    for (int g = 0; g < 8; g++) {
        int img[8];
        for (int s = 0; s < 8; s++)
            img[s] = slot_image(g, s);
        int v[8];
        for (int mask = 0; mask < 16; mask++)
            for (v[4] = 0; v[4] <= emax; v[4]++)
                for (v[5] = 0; v[5] <= emax; v[5]++)
                    for (v[6] = 0; v[6] <= emax; v[6]++)
                        for (v[7] = 0; v[7] <= emax; v[7]++) {
                            int q = 0;
                            for (int c = 0; c < 4; c++) {
                                v[c] = (mask >> c) & 1;
                                q += v[c];
                            }
                            q += 2 * (v[4] + v[5] + v[6] + v[7]);
                            if (q > quarters || (quarters - q) % 4)
                                continue; /* the interior count fills the rest */
                            int fixed = 1;
                            for (int s = 0; s < 8; s++)
                                fixed &= v[img[s]] == v[s];
                            fixed_total += (size_t)fixed;
                        }
    }
    return fixed_total / 8;
}

static void counts_match_burnside(void **state)
{
    (void)state;
    for (int q = 1; q <= 16; q++) {
        aa_mirrored_config *list;
        size_t n;
        assert_int_equal(aa_enumerate_mirrored(q / 4.0, &list, &n, NULL), AA_OK);
        assert_int_equal(n, burnside(q));
        for (size_t i = 0; i < n; i++)
            assert_true(fabs(aa_mirrored_config_cost(&list[i]) - q / 4.0) < 1e-12);
        free(list);
    }
}

static void small_costs_by_hand(void **state)
{
    (void)state;
    aa_mirrored_config *list;
    size_t n;
    /* 0.25: one corner. 0.5: two adjacent corners, two opposite corners, one edge sample. */
    assert_int_equal(aa_enumerate_mirrored(0.25, &list, &n, NULL), AA_OK);
    assert_int_equal(n, 1);
    free(list);
    assert_int_equal(aa_enumerate_mirrored(0.5, &list, &n, NULL), AA_OK);
    assert_int_equal(n, 3);
    free(list);
}

static void rejects_bad_costs(void **state)
{
    (void)state;
    aa_mirrored_config *list;
    size_t n;
    aa_error err = {0};
    assert_int_equal(aa_enumerate_mirrored(0.3, &list, &n, &err), AA_EINVAL);
    assert_string_equal(err.field, "cost");
    assert_int_equal(aa_enumerate_mirrored(0, &list, &n, &err), AA_EINVAL);
    assert_int_equal(aa_enumerate_mirrored(NAN, &list, &n, &err), AA_EINVAL);
}

static void seed_has_the_configuration(void **state)
{
    (void)state;
    aa_mirrored_config c = {{1, 0, 0, 0}, {0, 2, 0, 0}, 1};
    aa_filter f;
    aa_filter_default(&f);
    aa_rng rng;
    aa_rng_seed(&rng, 7, 0);
    aa_pattern p;
    assert_int_equal(aa_mirrored_config_seed(&c, AA_SEED_UNIFORM, &f, &rng, &p, NULL), AA_OK);
    assert_true(fabs(p.cost_spp - aa_mirrored_config_cost(&c)) < 1e-12);
    assert_int_equal(p.source_count, 4);
    aa_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(counts_match_burnside),
        cmocka_unit_test(small_costs_by_hand),
        cmocka_unit_test(rejects_bad_costs),
        cmocka_unit_test(seed_has_the_configuration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
