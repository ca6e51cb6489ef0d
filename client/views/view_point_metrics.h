/* The point_metrics block of random-stats results and table3 rows (point_metrics.json):
 * Spearman's rho of each point-set figure with E2, as extra CSV columns and as a text table. */
#ifndef AALAB_VIEW_POINT_METRICS_H
#define AALAB_VIEW_POINT_METRICS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <jansson.h>

#define VIEW_PM_MAX 16

/* CSV headers "spearman_<figure>" of the block's figures (unique ASCII names) into names;
 * returns how many (0 without a block). */
size_t view_point_metrics_headers(const json_t *pm, char (*names)[48], size_t max);
/* The block's rho values, one cell per figure of `count`, full precision in CSV ("-" for a
 * missing value, e.g. a table3 row without the block). */
void view_point_metrics_cells(const json_t *pm, size_t count, const char **cells, char (*bufs)[32],
                              bool csv);
/* A text table "[label] figure  rho  n  p_value" for each block of blocks (label: the
 * distribution, or NULL), with a heading line; nothing when no block has figures. */
void view_point_metrics_print(FILE *out, const json_t *const *blocks, const char *const *labels,
                              size_t count);

#endif
