/* fuzz_pointset_checks.h: shared by fuzz_pointset_parser and fuzz_pointset_binary. */
#include "fuzz_pointset_checks.h"

#include <math.h>
#include <string.h>

#include <jansson.h>

#include "aa_metric.h"
#include "fuzz_check.h"

double fuzz_small_e2(const aa_pattern *p)
{
    if (aa_pattern_total_kernel_samples(p) > 256)
        return NAN;
    aa_filter f;
    aa_acuity a;
    aa_filter_default(&f);
    aa_acuity_naiman(&a);
    const double angles[] = {0, 22.5, 45, 135};
    aa_metric_params mp = {&f, &a, angles, 4, 0};
    aa_evaluation ev;
    aa_error err = {0};
    if (aa_evaluate(p, &mp, &ev, &err) != AA_OK)
        return NAN;
    double e2 = ev.e2;
    aa_evaluation_free(&ev);
    return e2;
}

void fuzz_check_pointset_error(int rc, const aa_error *err)
{
    FUZZ_CHECK(rc < 0);
    FUZZ_CHECK(memchr(err->field, '\0', sizeof err->field));
    FUZZ_CHECK(memchr(err->message, '\0', sizeof err->message));
    FUZZ_CHECK(err->message[0] != '\0');
    FUZZ_CHECK(strncmp(err->field, "pattern.points", 14) == 0);
    /* Messages go into JSON answers: they must be valid UTF-8. */
    json_t *s = json_string(err->message);
    FUZZ_CHECK(s != NULL);
    json_decref(s);
}
