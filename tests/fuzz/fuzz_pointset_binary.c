/* libFuzzer driver: arbitrary bytes -> the sampling tools' point-set formats (issue 31):
 * UTK .bin, PSA .rps (proto_pointset_parse_binary) and sets of '#'-separated utk/xyw text
 * (proto_pointset_parse_set), then proto_pattern_from_pointset. Byte 0 picks the format (bits
 * 0-1: bin, rps, utk, xyw), the set (bits 2-3: whole file, 0, 1, 2), the weights (bits 4-5:
 * file/filter/equal) and the tile (bit 6: 1 or 2); the rest is the file. A parsed set must hold
 * 1..4096 finite points; the set count must agree with proto_pointset_count_sets; a built
 * pattern must export as bin and read back to the same E2 (1e-12) when small, and as rps to
 * float32 points within float32 rounding. Errors must name the field given. Any crash, leak or
 * sanitizer report is a bug. */
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

static const char FIELD[] = "pattern.points.base64";
static const char SET_FIELD[] = "pattern.points.set";

/* bin: the same pattern back (its header rides as a trailer); rps: the same points to float32
 * rounding. */
static void check_round_trips(const aa_pattern *p)
{
    size_t len;
    aa_error err = {0};
    char *b = proto_export_points(p, PROTO_POINTS_BIN, &len, &err);
    if (!b) {
        FUZZ_CHECK(err.code == AA_ENOMEM);
        return;
    }
    proto_pointset ps;
    int rc = proto_pointset_parse_binary((const unsigned char *)b, len, PROTO_POINTS_BIN,
                                         PROTO_POINTS_WHOLE, &ps, NULL, FIELD, SET_FIELD, &err);
    FUZZ_CHECK(rc == AA_OK && ps.header != NULL);
    aa_pattern q;
    proto_points_options o = proto_points_options_default();
    rc = proto_pattern_from_pointset(&ps, &o, &q, "pattern.points", FIELD, &err);
    FUZZ_CHECK(rc == AA_OK);
    FUZZ_CHECK(q.kernel_count == p->kernel_count && q.tile_count == p->tile_count);
    double a = fuzz_small_e2(p), e = fuzz_small_e2(&q);
    FUZZ_CHECK((isnan(a) && isnan(e)) || fabs(a - e) <= 1e-12 || (isinf(a) && a == e));
    aa_pattern_free(&q);
    proto_pointset_free(&ps);
    free(b);
    b = proto_export_points(p, PROTO_POINTS_RPS, &len, &err);
    if (!b)
        return;
    rc = proto_pointset_parse_binary((const unsigned char *)b, len, PROTO_POINTS_RPS,
                                     PROTO_POINTS_WHOLE, &ps, NULL, FIELD, SET_FIELD, &err);
    FUZZ_CHECK(rc == AA_OK);
    FUZZ_CHECK(ps.count == (p->tile > 0 ? p->tile_count : p->kernels[0].count));
    proto_pointset mine;
    FUZZ_CHECK(proto_pointset_of_pattern(p, &mine, &err) == AA_OK);
    for (size_t i = 0; i < ps.count; i++)
        FUZZ_CHECK(ps.points[i].x == (float)mine.points[i].x &&
                   ps.points[i].y == (float)mine.points[i].y);
    proto_pointset_free(&mine);
    proto_pointset_free(&ps);
    free(b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    uint8_t sel = data[0];
    static const proto_points_format fmts[] = {PROTO_POINTS_BIN, PROTO_POINTS_RPS, PROTO_POINTS_UTK,
                                               PROTO_POINTS_XYW};
    proto_points_format fmt = fmts[sel & 3];
    size_t set = (sel >> 2) & 3 ? (size_t)((sel >> 2) & 3) - 1 : PROTO_POINTS_WHOLE;
    proto_points_options o = proto_points_options_default();
    o.weights = (proto_weights_rule)(((sel >> 4) & 3) % 3);
    o.tile = 1 + ((sel >> 6) & 1);
    const char *bytes = (const char *)data + 1;
    size_t len = size - 1;
    const char *field = proto_points_format_is_binary(fmt) ? FIELD : "pattern.points.text";

    proto_pointset ps;
    aa_error err = {0};
    size_t count = 0, counted = 0;
    int rc = proto_pointset_parse_set(bytes, len, fmt, set, &ps, &count, field, SET_FIELD, &err);
    if (rc) {
        fuzz_check_pointset_error(rc, &err);
        return 0;
    }
    if (set != PROTO_POINTS_WHOLE) {
        FUZZ_CHECK(set < count);
        aa_error e2 = {0};
        FUZZ_CHECK(proto_pointset_count_sets(bytes, len, fmt, &counted, field, &e2) == AA_OK);
        FUZZ_CHECK(counted == count);
    }
    FUZZ_CHECK(ps.count >= 1 && ps.count <= PROTO_POINTS_MAX);
    for (size_t i = 0; i < ps.count; i++)
        FUZZ_CHECK(isfinite(ps.points[i].x) && isfinite(ps.points[i].y) &&
                   isfinite(ps.points[i].w));
    aa_pattern p;
    rc = proto_pattern_from_pointset(&ps, &o, &p, "pattern.points", field, &err);
    if (rc) {
        fuzz_check_pointset_error(rc, &err);
    } else {
        FUZZ_CHECK(p.kernel_count >= 1 && p.kernel_count <= AA_MAX_KERNELS);
        check_round_trips(&p);
        aa_pattern_free(&p);
    }
    proto_pointset_free(&ps);
    return 0;
}
