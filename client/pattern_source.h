/* Turning a command-line pattern argument into the wire form: a preset NAME becomes
 * {"preset":NAME}, job:ID becomes {"job":"ID"} (that job's best pattern); a FILE.json is read
 * strictly and checked locally with the shared codec (aalab_proto) so a typo is reported with its
 * field path before anything is sent. */
#ifndef AALAB_PATTERN_SOURCE_H
#define AALAB_PATTERN_SOURCE_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

/* True if arg names a file rather than a preset (contains '/', ends in ".json", or exists). */
bool pattern_argument_is_file(const char *arg);

/* *pattern: the pattern object (new reference). A file may hold the pattern itself or a request
 * object with a "pattern" member; the other members are returned in *extras (new reference, or
 * NULL) so `aalab eval request.json` works with saved requests; the "job" member of an
 * exported pattern ({"job":ID,"pattern":P}) is dropped. Returns 0, or -1 with err. */
int pattern_argument_load(const char *arg, json_t **pattern, json_t **extras, char *err,
                          size_t errcap);

/* Local check with the shared codec; err names the field ("pattern.kernels[0][1][2]: ..."). */
int pattern_check(const json_t *pattern, char *err, size_t errcap);

#endif
