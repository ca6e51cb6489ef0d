/* Small helpers shared by the views: tolerant lookups in the daemon's JSON answers. */
#ifndef AALAB_VIEW_UTIL_H
#define AALAB_VIEW_UTIL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <jansson.h>

/* The list in an answer that is either a bare array or {"<member>":[...]}. */
const json_t *list_member(const json_t *resp, const char *member);
/* Prints every scalar of obj (nested objects as "a.b"), one "key  value" line each, in order. */
void print_flat(FILE *out, const json_t *obj);
/* print_flat, or the same lines as a key,value CSV. */
void print_flat_as(FILE *out, const json_t *obj, bool csv);
/* Epoch seconds as "2026-11-23 01:20:07" (UTC); other values as fmt_number. */
const char *fmt_time(char *buf, size_t cap, const json_t *v);
/* Best E2 of a job or a job summary: its best_e2 (job.json, jobs_list.json), else best.e2. */
const json_t *job_best_e2(const json_t *job);

#endif
