/* The one JSON codec of aalab (jansson), shared by the daemon and the client: decodes the wire
 * forms of patterns, filters and acuity tables into engine values, naming the full JSON path of
 * any bad input ("pattern.kernels[0][2][1]"), and encodes engine values back to JSON.
 * Schemas documenting the formats live in proto/schemas/. */
#ifndef AALAB_PROTO_CODEC_H
#define AALAB_PROTO_CODEC_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "aa_core.h"
#include "aa_metric.h"
#include "aa_pattern.h"

/* Limits of the wire format beyond the engine's (documented in proto/schemas). */
#define PROTO_MAX_ANGLES AA_MAX_ANGLES

/* Pattern: {"preset":"name"} | {"kernels":[[[x,y,w],...],...]} | {"mirrored":[[x,y,w],...]} |
 * {"tile":{"size":T,"kernel":K,"border":bool,"samples":[[x,y],...],"weights":[[w,...],...]?}} |
 * {"points":{"format":"utk"|"xyw"|"csv"|"json","text":"..."|"data":[...],"tile":T,...}},
 * optional "normalize":true (ORed into flags as AA_PATTERN_NORMALIZE). The informational keys
 * written by proto_encode_pattern ("family", "cost_spp", "form", "kernels_expanded", "name")
 * are accepted and ignored so that an encoded pattern decodes back. field_prefix (may be NULL
 * or "") is prepended to every error field. On error *out holds nothing to free. */
int proto_decode_pattern(const json_t *j, unsigned flags, aa_pattern *out, const char *field_prefix,
                         aa_error *err);
/* The same where the request has its own reference filter: the "points" form's "weights":
 * "filter" weights by it (NULL: the default Mitchell filter, as proto_decode_pattern).
 * {"points":{...}} is a point-set file (proto/pointset.h). */
int proto_decode_pattern_filtered(const json_t *j, unsigned flags, const aa_filter *weight_filter,
                                  aa_pattern *out, const char *field_prefix, aa_error *err);
/* {"name":"mitchell","B":..,"C":..,"radius":..} / {"name":"gaussian","sigma":..,"radius":..} /
 * {"name":"lanczos","a":..}; NULL j -> the default Mitchell filter. */
int proto_decode_filter(const json_t *j, aa_filter *out, const char *field_prefix, aa_error *err);
/* {"name":"naiman"|"naiman-envelope"|"uniform"} or {"knots":[[deg,W],...]}; NULL j -> naiman. */
int proto_decode_acuity(const json_t *j, aa_acuity *out, const char *field_prefix, aa_error *err);
/* [deg,...] -> malloc'd array (*out, *count); NULL j -> *out = NULL, *count = 0. */
int proto_decode_angles(const json_t *j, double **out, size_t *count, const char *field_prefix,
                        aa_error *err);

/* {"family","cost_spp","form", the wire form ("kernels" | "mirrored" | "tile") that decodes back
 * to an equal pattern, "kernels_expanded": explicit kernels}. NULL on allocation failure. */
json_t *proto_encode_pattern(const aa_pattern *p);
/* {"e2","argmax":{"kernel","angle_deg"},"mean","lp_norm"?,"family","cost_spp","kernel_count",
 * "angle_count", and with detail "detail":[{"kernel":k,"angles":[{"angle_deg","weight","e1",
 * "weighted"},...]},...]}. p may be NULL (no family/cost). */
json_t *proto_encode_evaluation(const aa_evaluation *e, const aa_pattern *p, bool detail);
json_t *proto_encode_filter(const aa_filter *f);
json_t *proto_encode_acuity(const aa_acuity *a);
/* Which table a result used, so stored results stay interpretable when the default table
 * changes: {"name":"naiman","version":2} for a named table, {"name":"custom"} for knots. */
json_t *proto_encode_acuity_ref(const aa_acuity *a);
/* The table a result records, as name and version: a named table's own, "custom" and 0 for knots
 * given in a spec. Encoded at obj["acuity"] as proto_encode_acuity_ref does (name "": a result
 * stored before it was recorded, nothing; false when out of memory); decoded from obj["acuity"]
 * (absent: name "", version 0). */
void proto_acuity_ref_set(const aa_acuity *acuity, char *name, size_t cap, int *version);
bool proto_acuity_ref_encode(json_t *obj, const char *name, int version);
int proto_acuity_ref_decode(const json_t *obj, char *name, size_t cap, int *version, aa_error *err);

/* At most max bytes of s into buf (cap bytes), cut at a character boundary, each byte that is
 * not part of a well-formed UTF-8 character replaced by '?': text that echoes input (jansson's
 * error text does) made fit for a JSON string; returns buf. */
const char *proto_utf8_prefix(char *buf, size_t cap, const char *s, size_t max);
/* "prefix.sub" (or "prefix[..]" when sub starts with '['), written to out. */
void proto_join_field(char *out, size_t cap, const char *prefix, const char *sub);
/* Prepends prefix to err->field (engine errors are relative to the engine object); returns
 * err's code. */
int proto_prefix_error(aa_error *err, const char *prefix);
/* Rejects keys of obj not in the NULL-terminated allowed list, naming the first one
 * ("prefix.key", "unknown field"). */
int proto_check_keys(const json_t *obj, const char *const *allowed, aa_error *err,
                     const char *prefix);
/* The same with the allowed keys in several NULL-terminated lists (lists ends with NULL), e.g.
 * the keys a family of job kinds shares and the kind's own. */
int proto_check_keys_in(const json_t *obj, const char *const *const *lists, aa_error *err,
                        const char *prefix);
/* A JSON number for a double; null for non-finite values (JSON has no NaN). */
json_t *proto_real(double v);
/* [proto_real(v[0]), ...]; NULL when out of memory. */
json_t *proto_real_array(const double *v, size_t n);

#endif
