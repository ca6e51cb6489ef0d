/* GET /v1/patterns/{job}/export?format=json|utk|vulkan|d3d12: a job's best pattern as JSON,
 * as a UTK point set (text, one "x y" per line in the unit square of the tile), and as
 * Vulkan (VK_EXT_sample_locations) or D3D12 (SetSamplePositions) programmable sample positions
 * where representable: every pixel of the tile must hold the same power-of-two number of
 * samples (1..16); D3D12 also needs a 1x1 or 2x2 tile and positions on its 1/16 grid in
 * [-8, 7]. Both APIs resolve with equal weights, so kernel weights are reported, not applied. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "handlers.h"
#include "job_access.h"
#include "job_manager.h"

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

static json_t *export_gpu(const aa_pattern *p, bool d3d12)
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

static char *export_utk(const aa_pattern *p, size_t *len)
{
    size_t cap = 128 + (p->tile_count + 64) * 64, n = 0;
    char *out = malloc(cap);
    if (!out)
        return NULL;
    n += (size_t)snprintf(out + n, cap - n, "# aalab %s, cost %.17g spp, tile %d\n", p->family,
                          p->cost_spp, p->tile);
    if (p->tile > 0) {
        for (size_t i = 0; i < p->tile_count; i++)
            n += (size_t)snprintf(out + n, cap - n, "%.17g %.17g\n", p->tile_samples[i].x / p->tile,
                                  p->tile_samples[i].y / p->tile);
    } else {
        /* No tile: the first kernel's samples around the pixel centre. */
        const aa_kernel *k = &p->kernels[0];
        out = realloc(out, cap + k->count * 64);
        cap += k->count * 64;
        for (size_t i = 0; out && i < k->count; i++)
            n += (size_t)snprintf(out + n, cap - n, "%.17g %.17g\n", k->samples[i].x + 0.5,
                                  k->samples[i].y + 0.5);
    }
    *len = n;
    return out;
}

void handle_export(api_context *ctx, const api_request *req, api_response *resp,
                   const char *id_text)
{
    char fmt[16];
    const char *format = api_query_get(req->query, "format", fmt, sizeof fmt);
    if (!format)
        format = "json";
    if (strcmp(format, "json") && strcmp(format, "utk") && strcmp(format, "vulkan") &&
        strcmp(format, "d3d12")) {
        api_reply_wire(resp, WIRE_INVALID_FIELD, "format",
                       "format must be json, utk, vulkan or d3d12");
        return;
    }
    long long id = api_parse_job_id(id_text);
    const char *why = "no such job";
    /* Someone else's private job is "no such job", as in GET /v1/jobs/{id}. */
    json_t *pj = job_access_check(job_manager_store(api_context_jobs(ctx)), &req->caller, id, NULL)
                     ? job_manager_best_pattern(api_context_jobs(ctx), id, &why)
                     : NULL;
    if (!pj) {
        api_reply_wire(resp, strcmp(why, "no such job") ? WIRE_CONFLICT : WIRE_NOT_FOUND, "id",
                       "job %.40s: %s", id_text, why);
        return;
    }
    aa_pattern p;
    aa_error err = {0};
    int rc = proto_decode_pattern(pj, AA_PATTERN_NORMALIZE, &p, "pattern", &err);
    json_decref(pj);
    if (rc) {
        api_reply_wire(resp, WIRE_INTERNAL, err.field, "the job's pattern does not decode: %s",
                       err.message);
        return;
    }
    if (!strcmp(format, "json")) {
        api_reply_json(
            resp, 200,
            json_pack("{s:I,s:o}", "job", (json_int_t)id, "pattern", proto_encode_pattern(&p)));
    } else if (!strcmp(format, "utk")) {
        size_t len = 0;
        char *text = export_utk(&p, &len);
        if (!text) {
            api_reply_wire(resp, WIRE_OUT_OF_MEMORY, "", "out of memory");
        } else {
            resp->status = 200;
            resp->content_type = "text/plain; charset=utf-8";
            resp->body = text;
            resp->body_len = len;
        }
    } else {
        api_reply_json(resp, 200, export_gpu(&p, !strcmp(format, "d3d12")));
    }
    aa_pattern_free(&p);
}
