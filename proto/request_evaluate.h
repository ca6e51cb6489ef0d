/* POST /v1/evaluate on the wire: {"pattern", "filter"?, "acuity"?, "angles"?, "lp"?,
 * "detail"?}. The pattern is any pattern form (codec.h; a "points" pattern may take its weights
 * from the filter) or a temporal pattern {"temporal": {...}} (codec_temporal.h), for which "lp"
 * is refused. */
#ifndef AALAB_PROTO_REQUEST_EVALUATE_H
#define AALAB_PROTO_REQUEST_EVALUATE_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"
#include "codec.h"
#include "codec_temporal.h"

typedef struct proto_evaluate_request {
    bool detail; /* per-kernel, per-angle rows in the answer */
    double lp;   /* 0: not given */
    aa_filter filter;
    aa_acuity acuity;
    double *angles; /* [angle_count], NULL: the acuity table's default set */
    size_t angle_count;
    bool temporal;        /* a temporal pattern: in spec, pattern unused */
    aa_pattern pattern;   /* a spatial pattern */
    proto_temporal *spec; /* a temporal pattern (allocated: 27 KB a spatial one does not pay) */
} proto_evaluate_request;

/* Is body's pattern a temporal one? (Its evaluation is far larger than a spatial one's.) */
bool proto_evaluate_is_temporal(const json_t *body);

/* Strict, in the wire's order of checks: unknown keys, then refs (the outcome of resolving the
 * body's pattern references: code != 0 is answered here; NULL: none), then pattern, detail, lp,
 * filter, pattern, acuity and angles. Errors name the field. *out is to be freed (also after an
 * error) with proto_evaluate_request_free. Only the small fields are cleared first: the filter
 * and acuity (32 KB) are written by their decoders, and an evaluate costs a few µs. */
int proto_decode_evaluate_request(const json_t *body, const aa_error *refs,
                                  proto_evaluate_request *out, aa_error *err);
void proto_evaluate_request_free(proto_evaluate_request *r);

#endif
