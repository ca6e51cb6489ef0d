/* POST /v1/render (one test tile: pattern, reference, difference PNGs and statistics) and
 * GET /v1/tiles/{id}.png (a stored tile). Request and response formats: proto/codec_render.h
 * and proto/schemas (render). */
#ifndef AALAB_HANDLERS_RENDER_H
#define AALAB_HANDLERS_RENDER_H

#include "api.h"

/* Limits of the synchronous endpoint (tile size and reference wall time are in the daemon's
 * configuration: --render-max-pixels, --render-seconds); larger renders belong in a job
 * ("compare"). */
#define RENDER_MAX_KERNEL_WORK (1L << 26) /* pixels x samples of the largest kernel */

void handle_render(api_context *ctx, const api_request *req, api_response *resp);
/* id with or without the ".png" suffix. */
void handle_tile(api_context *ctx, const api_request *req, api_response *resp, const char *id);

#endif
