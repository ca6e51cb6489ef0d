/* Laine & Aila 2005, Table 2, with the default filter (Mitchell-Netravali 1/3, 1/3) and the
 * Naiman acuity table on the default angles 0, 5, ..., 175:
 *   2x2 grid 0.698, RGSS 0.439, Quincunx 0.518, FLIPQUAD 0.364, FLIPTRI 0.636, each +-0.003.
 * Positions and weights are the presets' (data/presets.json): FLIPQUAD with its edge samples
 * 1/3 and 2/3 along each edge, FLIPTRI as one corner plus the two far edge midpoints, equal
 * weights 1/3 (the papers do not print either; these are the inferred ones that reproduce the
 * published values). Checked twice: through aa_evaluate, and through the independent reference
 * (own W table, own mirrored kernels, long-double E1), which must also agree with the engine to
 * 1e-12 relative. The worst angle is checked as well (0/90 or 45/135 after folding). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "reference_e2.h"

typedef struct table2_row {
    const char *preset;
    double published;
    double folded_worst_deg; /* 0: horizontal/vertical, 45: diagonal */
} table2_row;

static const table2_row table2[] = {
    {"grid-2x2", 0.698, 0.0}, {"rgss", 0.439, 0.0},     {"quincunx", 0.518, 45.0},
    {"flipquad", 0.364, 0.0}, {"fliptri", 0.636, 45.0},
};

static aa_filter filter;
static aa_acuity acuity;
static ref_filter rfilter;

static int setup(void **state)
{
    (void)state;
    aa_filter_default(&filter);
    aa_acuity_naiman(&acuity);
    ref_filter_mitchell(&rfilter, 1.0L / 3, 1.0L / 3, 2.0L);
    return 0;
}

static double engine_e2(const char *name, size_t *argmax_kernel, double *argmax_deg)
{
    const aa_preset *pr = aa_preset_find(name);
    assert_non_null(pr);
    aa_pattern p;
    aa_error err = {0};
    assert_int_equal(aa_pattern_from_preset(&p, pr, &err), AA_OK);
    aa_metric_params mp = {.filter = &filter, .acuity = &acuity};
    aa_evaluation ev;
    assert_int_equal(aa_evaluate(&p, &mp, &ev, &err), AA_OK);
    assert_int_equal(ev.angle_count, 36);
    double e2 = ev.e2;
    if (argmax_kernel)
        *argmax_kernel = ev.argmax_kernel;
    if (argmax_deg)
        *argmax_deg = ev.argmax_angle_deg;
    aa_evaluation_free(&ev);
    aa_pattern_free(&p);
    return e2;
}

/* Independent E2 from the preset's coordinates: one kernel, or the four mirror images. */
static long double reference_e2(const aa_preset *pr, double *argmax_deg)
{
    ref_sample src[64], k[64];
    assert_true(pr->sample_count <= 64);
    for (size_t i = 0; i < pr->sample_count; i++)
        src[i] = (ref_sample){pr->samples[i].x, pr->samples[i].y, pr->samples[i].w};
    int mirrors = pr->form == AA_FORM_MIRRORED ? 4 : 1;
    long double best = -1.0L;
    for (int m = 0; m < mirrors; m++) {
        ref_mirror(src, pr->sample_count, m, k);
        double deg = NAN;
        long double v = ref_kernel_e2(&rfilter, k, pr->sample_count, &deg);
        if (v > best) {
            best = v;
            *argmax_deg = deg;
        }
    }
    return best;
}

static void test_table2_engine(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof table2 / sizeof table2[0]; i++) {
        size_t kernel = 0;
        double deg = NAN;
        double e2 = engine_e2(table2[i].preset, &kernel, &deg);
        print_message("%-9s E2 = %.6f (published %.3f), worst kernel %zu at %g deg\n",
                      table2[i].preset, e2, table2[i].published, kernel, deg);
        assert_true(fabs(e2 - table2[i].published) <= 0.003);
        assert_true(fabs(ref_fold_deg(deg) - table2[i].folded_worst_deg) < 1e-9);
        const aa_preset *pr = aa_preset_find(table2[i].preset);
        assert_true(pr->published_e2 == table2[i].published);
    }
}

static void test_table2_reference(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof table2 / sizeof table2[0]; i++) {
        const aa_preset *pr = aa_preset_find(table2[i].preset);
        assert_non_null(pr);
        double deg = NAN;
        long double ref = reference_e2(pr, &deg);
        double e2 = engine_e2(table2[i].preset, NULL, NULL);
        print_message("%-9s reference E2 = %.15Lf, engine %.15f, rel %.2g\n", table2[i].preset, ref,
                      e2, (double)(fabsl(e2 - ref) / ref));
        assert_true(fabsl(ref - table2[i].published) <= 0.003L);
        assert_true(fabs(ref_fold_deg(deg) - table2[i].folded_worst_deg) < 1e-9);
        assert_true(fabsl(e2 - ref) <= 1e-12L * ref);
    }
}

/* Every preset (not only Table 2's): engine E2 equals the independent E2. */
static void test_all_presets_against_reference(void **state)
{
    (void)state;
    size_t n = aa_preset_count();
    assert_true(n >= 17);
    for (size_t i = 0; i < n; i++) {
        const aa_preset *pr = aa_preset_at(i);
        double deg = NAN;
        long double ref = reference_e2(pr, &deg);
        double e2 = engine_e2(pr->name, NULL, NULL);
        print_message("%-13s %-13s n=%-5g E2 = %.6f\n", pr->name, pr->family, pr->cost_spp, e2);
        assert_true(fabsl(e2 - ref) <= 1e-12L * ref);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table2_engine),
        cmocka_unit_test(test_table2_reference),
        cmocka_unit_test(test_all_presets_against_reference),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
