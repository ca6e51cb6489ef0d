/* Rendered images as stored PNG tiles (tile_render.h). */
#include "tile_render.h"

#include <stdio.h>
#include <stdlib.h>

#include "png_encode.h"

json_t *tile_put_gray8_as(tile_store *ts, const tile_access *access, const uint8_t *px, int width,
                          int height, aa_error *err)
{
    void *png;
    size_t len;
    char id[TILE_ID_LEN + 1];
    if (tile_png_encode_gray(px, width, height, &png, &len, err))
        return NULL;
    int rc = tile_store_put_as(ts, png, len, access, id, err);
    free(png);
    if (rc)
        return NULL;
    char url[64];
    snprintf(url, sizeof url, "/v1/tiles/%s.png", id);
    return json_pack("{s:s, s:s, s:I, s:I, s:I}", "id", id, "url", url, "width", (json_int_t)width,
                     "height", (json_int_t)height, "bytes", (json_int_t)len);
}

json_t *tile_put_image(tile_store *ts, const tile_access *access, const aa_image *img,
                       aa_error *err)
{
    uint8_t *px = malloc((size_t)img->width * (size_t)img->height);
    if (!px) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    aa_image_to_gray8(img, px);
    json_t *o = tile_put_gray8_as(ts, access, px, img->width, img->height, err);
    free(px);
    return o;
}

json_t *tile_put_difference(tile_store *ts, const tile_access *access, const aa_image *a,
                            const aa_image *ref, aa_error *err)
{
    uint8_t *px = malloc((size_t)a->width * (size_t)a->height);
    if (!px) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    aa_image_difference_gray8(a, ref, 0.1, px);
    json_t *o = tile_put_gray8_as(ts, access, px, a->width, a->height, err);
    free(px);
    return o;
}

static json_t *put_crop(tile_store *ts, const tile_access *access, const uint8_t *full, int width,
                        const proto_crop *c, aa_error *err)
{
    int w = (c->rect.x1 - c->rect.x0) * c->scale, h = (c->rect.y1 - c->rect.y0) * c->scale;
    uint8_t *px = malloc((size_t)w * (size_t)h);
    if (!px) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    aa_gray8_crop_magnify(full, width, c->rect, c->scale, px);
    json_t *o = tile_put_gray8_as(ts, access, px, w, h, err);
    free(px);
    return o;
}

json_t *tile_put_render_images_as(tile_store *ts, const tile_access *access,
                                  const aa_image *pattern, const aa_image *reference,
                                  const proto_crop *crop, aa_error *err)
{
    size_t n = (size_t)pattern->width * (size_t)pattern->height;
    uint8_t *g[3] = {malloc(n), malloc(n), malloc(n)};
    json_t *out = json_object(), *crops = NULL;
    const char *names[3] = {"pattern", "reference", "difference"};
    if (!g[0] || !g[1] || !g[2] || !out) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        goto fail;
    }
    aa_image_to_gray8(pattern, g[0]);
    aa_image_to_gray8(reference, g[1]);
    aa_image_difference_gray8(pattern, reference, 0.1, g[2]);
    if (crop && crop->enabled)
        crops = json_object();
    for (int k = 0; k < 3; k++) {
        json_t *t = tile_put_gray8_as(ts, access, g[k], pattern->width, pattern->height, err);
        if (!t)
            goto fail;
        json_object_set_new(out, names[k], t);
        if (crops) {
            json_t *c = put_crop(ts, access, g[k], pattern->width, crop, err);
            if (!c)
                goto fail;
            json_object_set_new(crops, names[k], c);
        }
    }
    if (crops) {
        json_object_set_new(crops, "rect",
                            json_pack("{s:I, s:I, s:I, s:I, s:I}", "x", (json_int_t)crop->rect.x0,
                                      "y", (json_int_t)crop->rect.y0, "width",
                                      (json_int_t)(crop->rect.x1 - crop->rect.x0), "height",
                                      (json_int_t)(crop->rect.y1 - crop->rect.y0), "scale",
                                      (json_int_t)crop->scale));
        json_object_set_new(out, "crop", crops);
        crops = NULL;
    }
    for (int k = 0; k < 3; k++)
        free(g[k]);
    return out;
fail:
    for (int k = 0; k < 3; k++)
        free(g[k]);
    json_decref(crops);
    json_decref(out);
    return NULL;
}
