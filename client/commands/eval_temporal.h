/* aalab eval with a temporal pattern (docs/temporal.md, issue 30): the request built from
 * --temporal and its flags, and the per-phase view of the answer. */
#ifndef AALAB_EVAL_TEMPORAL_H
#define AALAB_EVAL_TEMPORAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <jansson.h>

#include "../args.h"

/* True when the command line asks for a temporal evaluation: --temporal, or a FILE.json whose
 * pattern is {"temporal": ...} (a pattern file or a saved request). */
bool eval_is_temporal(const cli_args *a);

/* --temporal's argument as a temporal object (new reference): a temporal preset NAME, a
 * FILE.json or an inline JSON object (the temporal object itself, {"temporal": T} or a request
 * {"pattern": {"temporal": T}, ...}, whose other members go to *extras), or a generator:
 * halton:N[:START], r2:N[:START], rgss4, fsr2:SCALE, positions:PRESET. extras may be NULL.
 * Returns 0, or -1 with err. */
int temporal_argument(const char *arg, json_t **temporal, json_t **extras, char *err,
                      size_t errcap);

/* The evaluate request: the temporal object with --alpha, --blend, --cut-frames, --resolve and
 * --frame-pattern applied over it, checked locally with the daemon's codec, and --filter,
 * --acuity and --angles as for a spatial pattern. 0 with *req, or -1 with err. */
int eval_temporal_request(const cli_args *a, json_t **req, char *err, size_t errcap);

/* A temporal answer (it has "phases"). */
bool eval_answer_is_temporal(const json_t *resp);

/* The summary (E2 of the worst phase, mean, F2, frames to 5 %), the per-phase table (phase,
 * newest offset, age weight, E2, argmax angle, then the worst and the mean) and the after-cut
 * curve, eight frames a line; detail adds the per-angle table (W, E1 of the worst phase and the
 * mean over phases, F1). csv: the per-phase table (with detail: the per-angle table). */
void eval_temporal_print(FILE *out, const json_t *resp, bool detail, bool csv);

#endif
