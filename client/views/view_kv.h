/* A "key  value" listing built cell by cell, for the heads of the job views. */
#ifndef AALAB_VIEW_KV_H
#define AALAB_VIEW_KV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <jansson.h>

#define VIEW_KV_MAX 24

typedef struct view_kv {
    const char *keys[VIEW_KV_MAX];
    char values[VIEW_KV_MAX][128];
    size_t n;
} view_kv;

/* Adds a line (silently dropped past VIEW_KV_MAX: the views add fewer). */
void view_kv_add(view_kv *kv, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Adds a JSON number with decimals ("-" when missing or null). */
void view_kv_number(view_kv *kv, const char *key, const json_t *v, int decimals);
void view_kv_print(FILE *out, const view_kv *kv);

/* Adds "executor  slurm, 8 shards, reproducible" (or "best effort": a time budget) of an
 * optimizer kind's result, then its acuity line; nothing for results made before those fields
 * existed. */
void view_kv_execution(view_kv *kv, const json_t *result);
/* Which acuity table the E2 values use: "naiman version 2" (or "custom") of obj["acuity"]
 * (results and evaluations since issue 17); NULL / nothing added when absent. */
const char *view_acuity_text(char *buf, size_t cap, const json_t *obj);
void view_kv_acuity(view_kv *kv, const json_t *obj);
/* The string, or "-" when v is not one. */
const char *view_str(const json_t *v);
/* Adds the "scene" line, "siemens-star 64x64", of a scene object. */
void view_kv_scene(view_kv *kv, const json_t *scene);

/* "images" lines: one per labelled set of tiles ({"pattern"|"reference"|"difference": {url}}),
 * "  LABEL  pattern URL  difference URL", under a heading that says how to fetch them. */
void view_images_heading(FILE *out);
void view_images_line(FILE *out, const char *label, const json_t *tiles);

#endif
