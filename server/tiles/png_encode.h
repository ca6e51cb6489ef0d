/* 8-bit grey PNG encoding and decoding in memory (libpng's simplified API). */
#ifndef AALAB_PNG_ENCODE_H
#define AALAB_PNG_ENCODE_H

#include <stddef.h>
#include <stdint.h>

#include "aa_core.h"

/* px: width * height bytes, top row first. On success *out is malloc'd (caller frees). */
int tile_png_encode_gray(const uint8_t *px, int width, int height, void **out, size_t *len,
                         aa_error *err);
/* Decodes any PNG to 8-bit grey; *px malloc'd. For tests and checks. */
int tile_png_decode_gray(const void *png, size_t len, uint8_t **px, int *width, int *height,
                         aa_error *err);

#endif
