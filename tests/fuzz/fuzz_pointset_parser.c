/* libFuzzer driver: arbitrary bytes -> proto_pointset_parse -> proto_pattern_from_pointset. Byte 0
 * picks the format (utk, xyw, csv, json) and the reading options (tile 1..4, kernel 1..2,
 * weights file/filter/equal); the rest is the file's text. A parsed set must hold 1..4096 finite
 * points with increasing lines; a built pattern must satisfy the engine's invariants and export
 * -> import in the same format back to the same E2 (1e-12) when small. Errors must name the
 * field given. Any crash, leak or sanitizer report is a bug. */
#include "fuzz_check.h"
#include "fuzz_pointset_checks.h"
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "aa_metric.h"
#include "aa_pattern.h"
#include "codec.h"
#include "pointset.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char FIELD[] = "pattern.points.text";

/* Export p in fmt and read it back: the same pattern (header), so the same E2. */
static void check_round_trip(const aa_pattern *p, proto_points_format fmt)
{
    size_t len;
    aa_error err = {0};
    char *text = proto_export_points(p, fmt, &len, &err);
    if (!text) {
        FUZZ_CHECK(err.code == AA_ENOMEM);
        return;
    }
    proto_pointset ps;
    int rc = proto_pointset_parse(text, len, fmt, &ps, FIELD, &err);
    FUZZ_CHECK(rc == AA_OK);
    FUZZ_CHECK(ps.header != NULL);
    aa_pattern q;
    proto_points_options o = proto_points_options_default();
    rc = proto_pattern_from_pointset(&ps, &o, &q, "pattern.points", FIELD, &err);
    FUZZ_CHECK(rc == AA_OK);
    FUZZ_CHECK(q.kernel_count == p->kernel_count && q.tile_count == p->tile_count);
    double a = fuzz_small_e2(p), b = fuzz_small_e2(&q);
    FUZZ_CHECK((isnan(a) && isnan(b)) || fabs(a - b) <= 1e-12 || (isinf(a) && a == b));
    aa_pattern_free(&q);
    proto_pointset_free(&ps);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    uint8_t sel = data[0];
    proto_points_format fmt = (proto_points_format)(sel & 3);
    proto_points_options o = proto_points_options_default();
    o.tile = 1 + ((sel >> 2) & 3);
    o.kernel = 1 + ((sel >> 4) & 1);
    o.weights = (proto_weights_rule)(((sel >> 5) & 3) % 3);
    o.flags = (sel & 0x80) ? AA_PATTERN_NORMALIZE : 0;
    const char *text = (const char *)data + 1;
    size_t len = size - 1;

    proto_pointset ps;
    aa_error err = {0};
    int rc = proto_pointset_parse(text, len, fmt, &ps, FIELD, &err);
    if (rc) {
        fuzz_check_pointset_error(rc, &err);
        return 0;
    }
    FUZZ_CHECK(ps.count >= 1 && ps.count <= PROTO_POINTS_MAX);
    for (size_t i = 0; i < ps.count; i++) {
        FUZZ_CHECK(isfinite(ps.points[i].x) && isfinite(ps.points[i].y));
        FUZZ_CHECK(isfinite(ps.points[i].w));
        FUZZ_CHECK(i == 0 || ps.where[i] > ps.where[i - 1]);
    }
    aa_pattern p;
    rc = proto_pattern_from_pointset(&ps, &o, &p, "pattern.points", FIELD, &err);
    if (rc) {
        fuzz_check_pointset_error(rc, &err);
    } else {
        FUZZ_CHECK(p.kernel_count >= 1 && p.kernel_count <= AA_MAX_KERNELS);
        FUZZ_CHECK(isfinite(p.cost_spp) && p.cost_spp > 0);
        for (size_t k = 0; k < p.kernel_count; k++)
            for (size_t m = 0; m < p.kernels[k].count; m++)
                FUZZ_CHECK(isfinite(p.kernels[k].samples[m].w));
        check_round_trip(&p, fmt);
        aa_pattern_free(&p);
    }
    proto_pointset_free(&ps);
    return 0;
}
