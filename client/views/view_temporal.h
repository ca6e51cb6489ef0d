/* Pieces both temporal job views print (temporal-optimize, temporal-render). */
#ifndef AALAB_VIEW_TEMPORAL_H
#define AALAB_VIEW_TEMPORAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <jansson.h>

/* "exponential, alpha 0.1" or "box" of a blend object ("-" when it has no kind). */
const char *view_blend_text(char *buf, size_t cap, const json_t *blend);
/* "LABEL (K values, from FIRST)" (FIRST: the index of the first value, phase 0 or frame 1) and
 * the numbers 10 to a line, at most 40 of them (every s-th of a longer list, which the heading
 * says). */
void view_number_lines(FILE *out, const char *label, const json_t *values, int first, int decimals);
/* A sequence ({jitter, jitter_range, blend}): its blend and its first 8 offsets, or with full
 * every offset a line ("frame x y"). */
void view_sequence(FILE *out, const json_t *temporal, bool full);

#endif
