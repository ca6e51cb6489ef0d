/* The pattern exports' requests on the wire:
 *   GET  /v1/patterns/{job}/export?format=F&phase=P   (the query)
 *   POST /v1/patterns/export {"pattern", "format", "filter"?, "phase"?}
 * F is one of PROTO_EXPORT_FORMATS (pointset.h) or PROTO_JITTER_FORMATS (export_temporal.h). A
 * temporal pattern, a jitter format or a phase is the temporal half's (export_temporal.h): the
 * decoder stops there, and its answer decodes the rest. */
#ifndef AALAB_PROTO_REQUEST_EXPORT_H
#define AALAB_PROTO_REQUEST_EXPORT_H

#include <stdbool.h>

#include <jansson.h>

#include "aa_core.h"
#include "codec.h"
#include "pointset.h"

typedef struct proto_export_request {
    const char *format;    /* borrowed from the body; NULL in a query without it (json) */
    const json_t *pattern; /* borrowed: the pattern as posted */
    const json_t *phase;   /* borrowed, or NULL */
    bool temporal;         /* the temporal half's: the fields below are not decoded */
    proto_export_writer writer;
    proto_points_format points;
    aa_filter filter;
    aa_pattern decoded; /* the pattern, decoded with the filter's weights */
} proto_export_request;

/* GET's query, its values as given (NULL: absent). */
typedef struct proto_export_query {
    const char *format; /* borrowed; NULL: json */
    proto_export_writer writer;
    proto_points_format points;
    json_t *phase; /* owned: an integer when the text is one, else the text; NULL: none */
} proto_export_query;

/* A format that is in neither list is AA_EINVAL on "format"; the phase is checked by the
 * temporal half. Free with proto_export_query_free (also after an error). */
int proto_decode_export_query(const char *format, const char *phase, proto_export_query *out,
                              aa_error *err);
void proto_export_query_free(proto_export_query *q);

/* POST's body, strict, in the wire's order: unknown keys, format present and a string, pattern
 * present, then refs (the outcome of resolving the body's pattern references: code != 0 is
 * answered here; NULL: none), then (unless temporal) the format's name, filter and pattern.
 * On success and !out->temporal, out->decoded is to be freed (aa_pattern_free). */
int proto_decode_export_request(const json_t *body, const aa_error *refs, proto_export_request *out,
                                aa_error *err);

#endif
