/* Family labels and seed patterns: parsing, cost, sites, weights from the filter. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>

#include <cmocka.h>

#include "aa_pattern.h"

static void parses_the_families_of_issue_3(void **state)
{
    (void)state;
    struct {
        const char *text;
        int T, K;
        bool border, mirrored;
        double n;
        const char *label;
    } cases[] = {
        {"P(1,1,4)", 1, 1, false, false, 4, "P(1,1,4)"},
        {"P(1,1+,3)", 1, 1, true, false, 3, "P(1,1+,3)"},
        {"P(4,1+,1.25)", 2, 1, true, true, 1.25, "P(4,1+,1.25)"},
        {" p( 1 , 4 , 2 ) ", 1, 2, false, false, 2, "P(1,4,2)"},
        {"P(4,4,2)", 2, 2, false, false, 2, "P(4,4,2)"},
        {"P(16,16,4)", 4, 4, false, false, 4, "P(16,16,4)"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        aa_family f;
        assert_int_equal(aa_family_parse(cases[i].text, &f, NULL), AA_OK);
        assert_int_equal(f.tile, cases[i].T);
        assert_int_equal(f.kernel_size, cases[i].K);
        assert_int_equal(f.border, cases[i].border);
        assert_int_equal(f.mirrored, cases[i].mirrored);
        assert_true(f.cost == cases[i].n);
        assert_string_equal(f.label, cases[i].label);
    }
}

static void rejects_bad_labels_naming_family(void **state)
{
    (void)state;
    const char *bad[] = {"",        "Q(1,1,2)",  "P(2,1,2)",    "P(1,2,2)",      "P(1,1,0)",
                         "P(1,1,2", "P(1,1,2)x", "P(4,1+,1.3)", "P(16,16,0.01)", "P(1,1,nan)"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        aa_family f;
        aa_error err = {0};
        assert_true(aa_family_parse(bad[i], &f, &err) < 0);
        assert_string_equal(err.field, "family");
    }
}

static void seeds_have_the_family_and_unit_weights(void **state)
{
    (void)state;
    const char *fams[] = {"P(1,1,3)", "P(1,1+,3)", "P(4,1+,2.5)",
                          "P(1,4,2)", "P(4,4,2)",  "P(16,16,4)"};
    aa_filter filter;
    aa_filter_default(&filter);
    for (size_t i = 0; i < sizeof fams / sizeof fams[0]; i++) {
        aa_family f;
        assert_int_equal(aa_family_parse(fams[i], &f, NULL), AA_OK);
        for (int k = 0; k < 5; k++) {
            aa_rng rng;
            aa_rng_seed(&rng, 1234, (uint64_t)k);
            aa_pattern p;
            assert_int_equal(aa_family_seed(&f, (aa_seed_distribution)k, &filter, &rng, &p, NULL),
                             AA_OK);
            assert_true(fabs(p.cost_spp - f.cost) < 1e-12);
            assert_int_equal(p.kernel_count, (size_t)(f.tile * f.tile));
            if (!f.border)
                assert_string_equal(p.family, f.label);
            for (size_t j = 0; j < p.kernel_count; j++) {
                double s = 0;
                for (size_t m = 0; m < p.kernels[j].count; m++)
                    s += p.kernels[j].samples[m].w;
                assert_true(fabs(s - 1) < 1e-9);
            }
            aa_pattern_free(&p);
        }
    }
}

static void seed_kind_names_round_trip(void **state)
{
    (void)state;
    for (int k = 0; k < 5; k++) {
        aa_seed_distribution back;
        assert_int_equal(
            aa_seed_distribution_parse(aa_seed_distribution_name((aa_seed_distribution)k), &back),
            AA_OK);
        assert_int_equal(back, k);
    }
    aa_seed_distribution x;
    assert_int_equal(aa_seed_distribution_parse("sobol", &x), AA_EINVAL);
}

static double min_torus_distance(const aa_point *p, size_t n, double T)
{
    double best = INFINITY;
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            double dx = fabs(p[i].x - p[j].x), dy = fabs(p[i].y - p[j].y);
            dx = fmin(dx, T - dx);
            dy = fmin(dy, T - dy);
            best = fmin(best, hypot(dx, dy));
        }
    return best;
}

static void distributions_are_stratified_or_spread(void **state)
{
    (void)state;
    enum { N = 64 };
    aa_point p[N];
    aa_rng rng;
    aa_rng_seed(&rng, 5, 0);
    /* N-rooks: one point in every row and every column stratum. */
    assert_int_equal(aa_seed_points(AA_SEED_NROOKS, N, 1, &rng, p), AA_OK);
    int rows[N] = {0}, cols[N] = {0};
    for (int i = 0; i < N; i++) {
        cols[(int)(p[i].x * N)]++;
        rows[(int)(p[i].y * N)]++;
    }
    for (int i = 0; i < N; i++)
        assert_true(rows[i] == 1 && cols[i] == 1);
    /* Jittered 8x8: one point per cell. */
    assert_int_equal(aa_seed_points(AA_SEED_JITTERED, N, 1, &rng, p), AA_OK);
    int cells[N] = {0};
    for (int i = 0; i < N; i++)
        cells[(int)(p[i].y * 8) * 8 + (int)(p[i].x * 8)]++;
    for (int i = 0; i < N; i++)
        assert_int_equal(cells[i], 1);
    /* Poisson and Lloyd spread points much further apart than uniform random points. */
    double uniform = 0, poisson = 0, lloyd = 0;
    for (int t = 0; t < 4; t++) {
        assert_int_equal(aa_seed_points(AA_SEED_UNIFORM, N, 2, &rng, p), AA_OK);
        uniform += min_torus_distance(p, N, 2);
        assert_int_equal(aa_seed_points(AA_SEED_POISSON, N, 2, &rng, p), AA_OK);
        poisson += min_torus_distance(p, N, 2);
        assert_int_equal(aa_seed_points(AA_SEED_LLOYD, N, 2, &rng, p), AA_OK);
        lloyd += min_torus_distance(p, N, 2);
        for (int i = 0; i < N; i++)
            assert_true(p[i].x >= 0 && p[i].x < 2 && p[i].y >= 0 && p[i].y < 2);
    }
    assert_true(poisson > 2 * uniform);
    assert_true(lloyd > 2 * uniform);
}

static void seeds_are_deterministic(void **state)
{
    (void)state;
    aa_point a[20], b[20];
    for (int k = 0; k < 5; k++) {
        aa_rng r1, r2;
        aa_rng_seed(&r1, 99, 7);
        aa_rng_seed(&r2, 99, 7);
        assert_int_equal(aa_seed_points((aa_seed_distribution)k, 20, 3, &r1, a), AA_OK);
        assert_int_equal(aa_seed_points((aa_seed_distribution)k, 20, 3, &r2, b), AA_OK);
        assert_memory_equal(a, b, sizeof a);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(parses_the_families_of_issue_3),
        cmocka_unit_test(rejects_bad_labels_naming_family),
        cmocka_unit_test(seeds_have_the_family_and_unit_weights),
        cmocka_unit_test(seed_kind_names_round_trip),
        cmocka_unit_test(distributions_are_stratified_or_spread),
        cmocka_unit_test(seeds_are_deterministic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
