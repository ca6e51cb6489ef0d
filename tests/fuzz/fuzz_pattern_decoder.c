/* libFuzzer driver: arbitrary bytes -> JSON -> proto_decode_pattern (with and without
 * normalisation). A decoded pattern must satisfy the engine's invariants and, when small, must
 * evaluate to a finite E2; a rejected one must name a field under the given prefix. Any crash,
 * leak or sanitizer report is a bug. */
#include "fuzz_check.h"
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <jansson.h>

#include "aa_metric.h"
#include "codec.h"
#include "aa_pattern.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_decoded(const aa_pattern *p)
{
    FUZZ_CHECK(p->kernel_count >= 1 && p->kernel_count <= AA_MAX_KERNELS);
    FUZZ_CHECK(p->family[0] == 'P');
    FUZZ_CHECK(memchr(p->family, '\0', sizeof p->family));
    FUZZ_CHECK(isfinite(p->cost_spp) && p->cost_spp > 0);
    for (size_t k = 0; k < p->kernel_count; k++) {
        const aa_kernel *ker = &p->kernels[k];
        FUZZ_CHECK(ker->count >= 1 && ker->count <= AA_MAX_KERNEL_SAMPLES);
        double sum = 0;
        for (size_t i = 0; i < ker->count; i++) {
            FUZZ_CHECK(isfinite(ker->samples[i].x) && isfinite(ker->samples[i].y));
            FUZZ_CHECK(isfinite(ker->samples[i].w));
            sum += ker->samples[i].w;
        }
        (void)sum;
    }
    /* Evaluating small patterns keeps the fuzzer fast and still reaches the metric. */
    if (aa_pattern_total_kernel_samples(p) > 256)
        return;
    aa_filter f;
    aa_acuity a;
    aa_filter_default(&f);
    aa_acuity_naiman(&a);
    const double angles[] = {0, 22.5, 45, 135};
    aa_metric_params mp = {&f, &a, angles, 4, 0};
    aa_evaluation ev;
    aa_error err = {0};
    int rc = aa_evaluate(p, &mp, &ev, &err);
    FUZZ_CHECK(rc == AA_OK || rc == AA_ENOMEM || rc == AA_EINVAL || rc == AA_ERANGE);
    if (rc == AA_OK) {
        FUZZ_CHECK(!isnan(ev.e2));
        aa_evaluation_free(&ev);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    json_error_t jerr;
    json_t *j =
        json_loadb((const char *)data, size, JSON_REJECT_DUPLICATES | JSON_DECODE_ANY, &jerr);
    if (!j)
        return 0;
    static const unsigned flag_sets[] = {0, AA_PATTERN_NORMALIZE};
    for (size_t f = 0; f < sizeof flag_sets / sizeof flag_sets[0]; f++) {
        aa_pattern p;
        aa_error err;
        memset(&err, 0, sizeof err);
        int rc = proto_decode_pattern(j, flag_sets[f], &p, "pattern", &err);
        if (rc == AA_OK) {
            check_decoded(&p);
        } else {
            FUZZ_CHECK(rc < 0);
            FUZZ_CHECK(memchr(err.field, '\0', sizeof err.field));
            FUZZ_CHECK(memchr(err.message, '\0', sizeof err.message));
            FUZZ_CHECK(err.message[0] != '\0');
            /* Field paths are relative to the request body: under the prefix we gave. */
            FUZZ_CHECK(err.field[0] == '\0' || strncmp(err.field, "pattern", 7) == 0);
        }
        aa_pattern_free(&p);
    }
    json_decref(j);
    return 0;
}
