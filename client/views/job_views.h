/* Readable views of a job's result, one file per kind, found by kind name. Each reads the
 * fields its kind's result schema (proto/schemas/kinds/<kind>.result.json) names, nothing else.
 * With csv a view prints only its main table, as RFC 4180 CSV. */
#ifndef AALAB_JOB_VIEWS_H
#define AALAB_JOB_VIEWS_H

#include <stdbool.h>
#include <stdio.h>

#include <jansson.h>

typedef void (*job_view_fn)(FILE *out, const json_t *result, bool csv);

typedef struct job_view {
    const char *kind;
    job_view_fn print;
} job_view;

/* The view of kind; the generic one (every scalar of the result) for a kind without a view. */
const job_view *job_view_find(const char *kind);

void view_optimize(FILE *out, const json_t *result, bool csv);
void view_family_sweep(FILE *out, const json_t *result, bool csv);
void view_random_stats(FILE *out, const json_t *result, bool csv);
void view_table3(FILE *out, const json_t *result, bool csv);
void view_compare(FILE *out, const json_t *result, bool csv);
void view_animation(FILE *out, const json_t *result, bool csv);
void view_reference_convergence(FILE *out, const json_t *result, bool csv);
void view_temporal_optimize(FILE *out, const json_t *result, bool csv);
void view_temporal_render(FILE *out, const json_t *result, bool csv);
void view_generic(FILE *out, const json_t *result, bool csv);

/* A pattern in wire form (pattern.json) as one row per sample of kernels_expanded: kernel
 * (from 0), sample, x, y, weight; a pattern without kernels_expanded as its family and cost. */
void view_pattern(FILE *out, const json_t *pattern, bool csv);
/* A job's trace: seconds, iterations, evaluations, best_e2 per point. */
void view_trace(FILE *out, const json_t *trace, bool csv);

#endif
