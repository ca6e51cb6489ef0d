/* Turning a command-line pattern argument into the wire form: a preset NAME becomes
 * {"preset":NAME}, job:ID becomes {"job":"ID"} (that job's best pattern); a FILE.json is read
 * strictly and a point-set file (.dat, .txt, .xyw, .csv, a .json array of points, or any file
 * with --points-format) becomes the "points" form; files are checked locally with the shared
 * codec (aalab_proto) so a typo is reported with its field path, or its line, before anything is
 * sent. */
#ifndef AALAB_PATTERN_SOURCE_H
#define AALAB_PATTERN_SOURCE_H

#include <stdbool.h>
#include <stddef.h>

#include <jansson.h>

#include "args.h"

struct aa_error;

/* True if arg names a file rather than a preset (contains '/', ends in ".json", or exists). */
bool pattern_argument_is_file(const char *arg);

/* The point-set format a file is read in: --points-format, else by extension (.dat -> utk,
 * .txt and .xyw -> xyw, .csv -> csv); NULL for anything else (.json is decided by content). */
const char *pattern_points_format(const char *arg, const cli_args *opts);

/* *pattern: the pattern object (new reference). A JSON file may hold the pattern itself, a point
 * set ([[x,y],...] or {"aalab":{...},"points":[...]}) or a request object with a "pattern"
 * member; the other members are returned in *extras (new reference, or NULL) so
 * `aalab eval request.json` works with saved requests; the "job" member of an exported pattern
 * ({"job":ID,"pattern":P}) is dropped. opts (may be NULL) carries --points-format, --tile,
 * --kernel and --weights, which only apply to point sets. Returns 0, or -1 with err. */
int pattern_argument_load(const char *arg, const cli_args *opts, json_t **pattern, json_t **extras,
                          char *err, size_t errcap);

/* Local check with the shared codec; err names the field ("pattern.kernels[0][1][2]: ..."). */
int pattern_check(const json_t *pattern, char *err, size_t errcap);
/* The codec's refusal (rc, e) as the client prints it: "field F: message"; returns -1. */
int pattern_check_refusal(int rc, const struct aa_error *e, char *err, size_t errcap);

/* A JSON file read strictly (duplicate keys refused); NULL with err "FILE:LINE:COL: why". */
json_t *pattern_json_file(const char *path, char *err, size_t errcap);

#endif
