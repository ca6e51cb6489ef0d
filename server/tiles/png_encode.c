/* PNG in memory with png_image_write_to_memory / png_image_begin_read_from_memory. */
#include "png_encode.h"

#include <stdlib.h>
#include <string.h>

#include <png.h>

int tile_png_encode_gray(const uint8_t *px, int width, int height, void **out, size_t *len,
                         aa_error *err)
{
    *out = NULL;
    *len = 0;
    if (width < 1 || height < 1)
        return aa_error_set(err, AA_EINVAL, "", "empty image");
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width;
    image.height = (png_uint_32)height;
    image.format = PNG_FORMAT_GRAY;
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&image, NULL, &size, 0, px, width, NULL))
        return aa_error_set(err, AA_EINVAL, "", "png: %s", image.message);
    void *buf = malloc(size);
    if (!buf)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    if (!png_image_write_to_memory(&image, buf, &size, 0, px, width, NULL)) {
        free(buf);
        return aa_error_set(err, AA_EINVAL, "", "png: %s", image.message);
    }
    *out = buf;
    *len = size;
    return AA_OK;
}

int tile_png_decode_gray(const void *png, size_t len, uint8_t **px, int *width, int *height,
                         aa_error *err)
{
    *px = NULL;
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&image, png, len))
        return aa_error_set(err, AA_EINVAL, "", "png: %s", image.message);
    image.format = PNG_FORMAT_GRAY;
    uint8_t *buf = malloc(PNG_IMAGE_SIZE(image));
    if (!buf) {
        png_image_free(&image);
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    }
    if (!png_image_finish_read(&image, NULL, buf, 0, NULL)) {
        free(buf);
        return aa_error_set(err, AA_EINVAL, "", "png: %s", image.message);
    }
    *px = buf;
    *width = (int)image.width;
    *height = (int)image.height;
    return AA_OK;
}
