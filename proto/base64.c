/* Base64 (RFC 4648, padded, no line breaks) for the binary point-set files on the wire
 * (pointset.h: the points form's "base64"). */
#include "pointset.h"

#include <assert.h>
#include <stdint.h>
#include <stdlib.h>

static const char B64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static int b64_value(unsigned char c)
{
    if (c >= 'A' && c <= 'Z')
        return c - 'A';
    if (c >= 'a' && c <= 'z')
        return c - 'a' + 26;
    if (c >= '0' && c <= '9')
        return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

unsigned char *proto_base64_decode(const char *s, size_t n, size_t *len, size_t *bad_at)
{
    if (n % 4) {
        *bad_at = n;
        return NULL;
    }
    unsigned char *out = malloc(n / 4 * 3 + 1);
    if (!out) {
        *bad_at = (size_t)-1;
        return NULL;
    }
    assert(s || !n);
    size_t o = 0;
    for (size_t i = 0; i < n; i += 4) {
        int v[4];
        int pad = 0;
        for (int k = 0; k < 4; k++) {
            unsigned char c = (unsigned char)s[i + k];
            /* '=' only as the last one or two characters of the text. */
            if (c == '=' && i + 4 == n && k >= 2 && (k == 3 || s[i + 3] == '=')) {
                v[k] = 0;
                pad++;
                continue;
            }
            v[k] = b64_value(c);
            if (v[k] < 0 || pad) {
                free(out);
                *bad_at = i + (size_t)k;
                return NULL;
            }
        }
        uint32_t t =
            (uint32_t)v[0] << 18 | (uint32_t)v[1] << 12 | (uint32_t)v[2] << 6 | (uint32_t)v[3];
        out[o++] = (unsigned char)(t >> 16);
        if (pad < 2)
            out[o++] = (unsigned char)(t >> 8);
        if (pad < 1)
            out[o++] = (unsigned char)t;
    }
    assert(o <= n / 4 * 3); /* three bytes at most per four characters: the buffer's size */
    *len = o;
    return out;
}

char *proto_base64_encode(const unsigned char *b, size_t n)
{
    assert(b || !n);
    char *out = malloc((n + 2) / 3 * 4 + 1);
    if (!out)
        return NULL;
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t t = (uint32_t)b[i] << 16;
        if (i + 1 < n)
            t |= (uint32_t)b[i + 1] << 8;
        if (i + 2 < n)
            t |= b[i + 2];
        out[o++] = B64[t >> 18 & 63];
        out[o++] = B64[t >> 12 & 63];
        out[o++] = i + 1 < n ? B64[t >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? B64[t & 63] : '=';
    }
    assert(o == (n + 2) / 3 * 4); /* padded: whole groups of four, what was allocated */
    out[o] = 0;
    return out;
}
