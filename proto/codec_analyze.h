/* POST /v1/analyze on the wire: point-set analysis of a pattern's tile (engine
 * pattern/point_set.h, docs/analysis.md).
 *
 * Request: {"pattern": name | {...} (any pattern form; its tile samples are the point set; a
 *            points form with "set": "all" analyses every set of its file, spectra averaged;
 *            a temporal pattern: its frames' samples shifted by the N jitter offsets, on the
 *            frame pattern's tile),
 *           "metrics": ["discrepancy", "star_discrepancy", "spacing", "spectrum", "pcf"]
 *                      (default: all),
 *           "spectrum": {"radius": 1..128 (default 32)},
 *           "pcf": {"bins": 1..1024 (default 64), "r_max": (0, 0.5] (default: 4 packing
 *                   distances, at most 0.5), "sigma": > 0 (default: packing distance / 8)}}
 * Answer: proto/schemas/analyze_response.json. */
#ifndef AALAB_PROTO_CODEC_ANALYZE_H
#define AALAB_PROTO_CODEC_ANALYZE_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_pattern.h"

#define PROTO_ANALYZE_MAX_RADIUS 128
#define PROTO_ANALYZE_MAX_BINS 1024
/* "set": "all": at most this many sets and points over all sets (about 0.1 s per 4,096 points
 * at the defaults: bench_analysis). */
#define PROTO_ANALYZE_MAX_SETS 1024
#define PROTO_ANALYZE_MAX_SET_POINTS 65536

typedef enum {
    PROTO_ANALYZE_DISCREPANCY = 1u << 0,
    PROTO_ANALYZE_STAR = 1u << 1,
    PROTO_ANALYZE_SPACING = 1u << 2,
    PROTO_ANALYZE_SPECTRUM = 1u << 3,
    PROTO_ANALYZE_PCF = 1u << 4,
    PROTO_ANALYZE_ALL = (1u << 5) - 1
} proto_analyze_metric;

typedef struct proto_analyze_request {
    aa_pattern pattern;    /* with "set": "all", set 0 */
    size_t set_count;      /* 0: one pattern; else the file's sets ("set": "all") */
    aa_pattern *more_sets; /* sets 1 .. set_count - 1 */
    unsigned metrics;      /* proto_analyze_metric bits */
    int radius;
    size_t bins;
    double r_max, sigma; /* 0: the default, from the point count */
} proto_analyze_request;

/* On error out holds nothing to free. Errors name "pattern...", "metrics[i]",
 * "spectrum.radius", "pcf.bins", "pcf.r_max", "pcf.sigma" or an unknown key. */
int proto_decode_analyze_request(const json_t *body, proto_analyze_request *out, aa_error *err);
void proto_analyze_request_free(proto_analyze_request *r);

/* The computed figures; the parts not asked for are left zero/NULL. With several sets: the
 * means (the spectrum of the mean periodogram, the mean PCF) and per_set[set_count], each set's
 * own figures without its spectrum arrays and PCF. */
typedef struct proto_analysis {
    size_t set_count;
    struct proto_analysis *per_set;
    size_t points;
    aa_discrepancy discrepancy;
    double star_discrepancy;
    aa_spacing spacing;
    aa_spectrum spectrum;
    double r_max, sigma;
    double *pcf; /* [bins] */
} proto_analysis;

void proto_analysis_free(proto_analysis *a);
/* NULL on allocation failure. */
json_t *proto_encode_analysis(const proto_analyze_request *r, const proto_analysis *a);

#endif
