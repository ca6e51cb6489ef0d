/* Helpers private to the codec (the proto directory). */
#ifndef AALAB_PROTO_CODEC_INTERNAL_H
#define AALAB_PROTO_CODEC_INTERNAL_H

#include "codec.h"

#define PROTO_FIELD_MAX 96
#define PROTO_MAX_KEYS 64 /* keys of one object, over all the lists of proto_check_keys_in */

/* Drops a last UTF-8 character that truncation left incomplete (error fields and messages go
 * into JSON, which must be UTF-8). */
void proto_utf8_trim(char *s);
/* Sets err with field prefix+sub and a fixed message; returns code. */
int proto_fail(aa_error *err, int code, const char *prefix, const char *sub, const char *msg);
/* A finite JSON number (integer or real). */
int proto_number(const json_t *j, double *out, aa_error *err, const char *prefix, const char *sub);

/* The "points" form's object (codec_points.c); weight_filter NULL = the default filter. */
int proto_decode_points_form(const json_t *j, unsigned flags, const aa_filter *weight_filter,
                             aa_pattern *out, const char *prefix, aa_error *err);
/* The number of sets in a "points" form's file (1 for json, csv, rps; codec_points.c). */
int proto_points_form_set_count(const json_t *j, size_t *count, const char *prefix, aa_error *err);

#endif
