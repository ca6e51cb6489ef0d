/* Vulkan (VK_EXT_sample_locations), D3D12 (SetSamplePositions) and Metal (setSamplePositions)
 * programmable sample positions of a pattern, where representable: every pixel of the tile must
 * hold the same power-of-two number of samples (1..16); D3D12 also needs a 1x1 or 2x2 tile and
 * positions on its 1/16 grid in [-8, 7]; Metal one pattern for every pixel (a 1x1 tile) of 1, 2,
 * 4 or 8 samples on its 1/16 grid in [0, 15/16] (Apple's MTLRenderPassDescriptor
 * setSamplePositions documentation). The APIs resolve with equal weights, so kernel weights are
 * reported, not applied. */
#include "pointset.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "codec.h"

typedef struct pixel_samples {
    int count;
    int first; /* index into the sorted order */
} pixel_samples;

/* Tile samples bucketed by the pixel that owns them (floor of the coordinates). Returns the
 * per-pixel sample count if all pixels agree and it is a power of two <= 16, else 0 with why. */
static int uniform_pixel_count(const aa_pattern *p, size_t *order, const char **why)
{
    int T = p->tile;
    if (T <= 0) {
        *why = "the pattern has no repeating tile";
        return 0;
    }
    size_t n = 0;
    int per = -1;
    for (int j = 0; j < T; j++) {
        for (int i = 0; i < T; i++) {
            int c = 0;
            for (size_t s = 0; s < p->tile_count; s++) {
                if ((int)floor(p->tile_samples[s].x) == i &&
                    (int)floor(p->tile_samples[s].y) == j) {
                    order[n++] = s;
                    c++;
                }
            }
            if (per < 0)
                per = c;
            if (c != per) {
                *why = "pixels of the tile hold different numbers of samples";
                return 0;
            }
        }
    }
    if (per < 1 || per > 16 || (per & (per - 1))) {
        *why = "samples per pixel must be 1, 2, 4, 8 or 16";
        return 0;
    }
    return per;
}

json_t *proto_export_gpu(const aa_pattern *p, bool d3d12)
{
    json_t *o = json_pack("{s:s,s:s,s:o}", "api", d3d12 ? "d3d12" : "vulkan", "family", p->family,
                          "cost_spp", proto_real(p->cost_spp));
    size_t *order = malloc((p->tile_count ? p->tile_count : 1) * sizeof *order);
    const char *why = NULL;
    int per = order ? uniform_pixel_count(p, order, &why) : 0;
    if (per && d3d12 && p->tile > 2) {
        per = 0;
        why = "D3D12 programmable sample positions cover at most a 2x2 pixel quad";
    }
    json_t *locs = json_array();
    for (int k = 0; per && k < p->tile * p->tile * per; k++) {
        const aa_point *s = &p->tile_samples[order[k]];
        double fx = s->x - floor(s->x), fy = s->y - floor(s->y);
        if (d3d12) {
            /* 1/16 pixel units relative to the pixel centre, range -8..7. */
            long X = lround((fx - 0.5) * 16), Y = lround((fy - 0.5) * 16);
            if (X > 7 || Y > 7 || fabs((fx - 0.5) * 16 - X) > 1e-9 ||
                fabs((fy - 0.5) * 16 - Y) > 1e-9) {
                per = 0;
                why = "a position is not on D3D12's 1/16 pixel grid within [-8, 7]";
                break;
            }
            json_array_append_new(locs,
                                  json_pack("{s:I,s:I}", "X", (json_int_t)X, "Y", (json_int_t)Y));
        } else {
            json_array_append_new(locs, json_pack("{s:f,s:f}", "x", fx, "y", fy));
        }
    }
    free(order);
    json_object_set_new(o, "representable", json_boolean(per > 0));
    if (!per) {
        json_decref(locs);
        json_object_set_new(o, "reason", json_string(why ? why : "not representable"));
        return o;
    }
    char bits[40];
    snprintf(bits, sizeof bits, d3d12 ? "%d" : "VK_SAMPLE_COUNT_%d_BIT", per);
    if (d3d12) {
        json_object_set_new(o, "NumSamplesPerPixel", json_integer(per));
        json_object_set_new(o, "NumPixels", json_integer(p->tile * p->tile));
        json_object_set_new(o, "SamplePositions", locs);
    } else {
        json_object_set_new(o, "sampleLocationsPerPixel", json_string(bits));
        json_object_set_new(o, "sampleLocationGridSize",
                            json_pack("{s:i,s:i}", "width", p->tile, "height", p->tile));
        json_object_set_new(o, "sampleLocationsCount", json_integer(p->tile * p->tile * per));
        json_object_set_new(o, "pSampleLocations", locs);
    }
    json_object_set_new(o, "note",
                        json_string("pixel-major order (rows of the tile, then samples); the "
                                    "API resolves with equal weights, kernel weights are not "
                                    "applied; y grows with the tile's y axis"));
    return o;
}

json_t *proto_export_metal(const aa_pattern *p)
{
    json_t *o = json_pack("{s:s,s:s,s:o}", "api", "metal", "family", p->family, "cost_spp",
                          proto_real(p->cost_spp));
    size_t *order = malloc((p->tile_count ? p->tile_count : 1) * sizeof *order);
    const char *why = NULL;
    int per = order ? uniform_pixel_count(p, order, &why) : 0;
    if (per && p->tile != 1) {
        per = 0;
        why = "Metal sample positions are one pattern for every pixel: the tile must be 1x1";
    } else if (per == 16) {
        per = 0;
        why = "Metal sample counts are 1, 2, 4 or 8";
    }
    json_t *locs = json_array();
    for (int k = 0; per && k < per; k++) {
        const aa_point *s = &p->tile_samples[order[k]];
        double fx = s->x - floor(s->x), fy = s->y - floor(s->y);
        /* 0/16 .. 15/16 in steps of 1/16, origin at the pixel's top-left corner. */
        long X = lround(fx * 16), Y = lround(fy * 16);
        if (X > 15 || Y > 15 || fabs(fx * 16 - X) > 1e-9 || fabs(fy * 16 - Y) > 1e-9) {
            per = 0;
            why = "a position is not on Metal's 1/16 pixel grid within [0, 15/16]";
            break;
        }
        json_array_append_new(locs, json_pack("{s:f,s:f}", "x", X / 16.0, "y", Y / 16.0));
    }
    free(order);
    json_object_set_new(o, "representable", json_boolean(per > 0));
    if (!per) {
        json_decref(locs);
        json_object_set_new(o, "reason", json_string(why ? why : "not representable"));
        return o;
    }
    json_object_set_new(o, "sampleCount", json_integer(per));
    json_object_set_new(o, "samplePositions", locs);
    json_object_set_new(o, "note",
                        json_string("MTLSamplePosition list for setSamplePositions(_:) with a "
                                    "render pass sampleCount of sampleCount (check "
                                    "supportsTextureSampleCount(_:)); origin at the pixel's "
                                    "top-left corner, y down; the API resolves with equal "
                                    "weights, kernel weights are not applied"));
    return o;
}
