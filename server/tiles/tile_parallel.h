/* The reference split into horizontal bands rendered on several threads (for the render job
 * kinds, which may use job_ctx_workers() threads). The result is bit-identical to one
 * aa_render_reference call: the jitter depends only on (seed, input pixel, stratum), and bands
 * write disjoint pixels. Only the first band calls the caller's progress callback; its nonzero
 * answer stops every band. */
#ifndef AALAB_TILE_PARALLEL_H
#define AALAB_TILE_PARALLEL_H

#include "aa_render.h"

#define TILE_MAX_THREADS 16

int tile_reference_parallel(const aa_scene *s, const aa_reference_params *rp, double out_offset,
                            aa_image *out, int threads, aa_reference_stats *st, aa_error *err);

#endif
