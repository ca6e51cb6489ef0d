/* aalab_render: test scenes, their supersampled references, rendering with a pattern and the
 * error against the reference, images and the rasterizer. The only header code outside
 * server/engine/render includes. */
#ifndef AA_RENDER_PUBLIC_H
#define AA_RENDER_PUBLIC_H

#include "../image.h"
#include "../scene.h"
#include "../raster.h"
#include "../reference.h"
#include "../render.h"
#include "../edge_histogram.h"
#include "../edge_profile.h"
#include "../predict.h"
#include "../taa_render.h"

#endif
