/* Small helpers shared by the codec files: field paths and numbers. */
#include "codec_internal.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

void proto_utf8_trim(char *s)
{
    size_t i = strlen(s), cont = 0;
    while (i > 0 && cont < 4 && ((unsigned char)s[i - 1] & 0xC0) == 0x80) {
        i--;
        cont++;
    }
    if (i == 0) {
        if (cont)
            s[0] = 0;
        return;
    }
    unsigned char lead = (unsigned char)s[i - 1];
    size_t need = lead < 0x80           ? 1
                  : (lead >> 5) == 0x6  ? 2
                  : (lead >> 4) == 0xE  ? 3
                  : (lead >> 3) == 0x1E ? 4
                                        : 1;
    if (cont + 1 < need)
        s[i - 1] = 0;
}

/* Length of the well-formed UTF-8 character at s (n bytes left), or 0 if there is none: the
 * rules jansson's json_string applies (no overlong forms, no surrogates, nothing above
 * U+10FFFF). */
static size_t utf8_char_len(const unsigned char *s, size_t n)
{
    unsigned char c = s[0];
    if (c < 0x80)
        return 1;
    size_t len;
    unsigned char lo = 0x80, hi = 0xBF; /* the range of the second byte */
    if (c >= 0xC2 && c <= 0xDF)
        len = 2;
    else if (c >= 0xE0 && c <= 0xEF) {
        len = 3;
        lo = c == 0xE0 ? 0xA0 : 0x80;
        hi = c == 0xED ? 0x9F : 0xBF;
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4;
        lo = c == 0xF0 ? 0x90 : 0x80;
        hi = c == 0xF4 ? 0x8F : 0xBF;
    } else
        return 0;
    if (n < len || s[1] < lo || s[1] > hi)
        return 0;
    for (size_t i = 2; i < len; i++)
        if ((s[i] & 0xC0) != 0x80)
            return 0;
    return len;
}

const char *proto_utf8_prefix(char *buf, size_t cap, const char *s, size_t max)
{
    size_t n = strlen(s), out = 0;
    const unsigned char *u = (const unsigned char *)s;
    for (size_t i = 0; i < n && cap > 0;) {
        size_t len = utf8_char_len(u + i, n - i), step = len ? len : 1;
        if (i + step > max || out + step >= cap)
            break; /* a character the limit would cut is left out whole */
        if (len)
            memcpy(buf + out, s + i, len);
        else /* echoed input that is not UTF-8: one '?' per byte */
            buf[out] = '?';
        out += step;
        i += step;
    }
    if (cap > 0)
        buf[out] = 0;
    return buf;
}

void proto_join_field(char *out, size_t cap, const char *prefix, const char *sub)
{
    int n; /* a path longer than cap is cut short on purpose (checking n tells -O3 gcc so) */
    if (!prefix || !*prefix)
        n = snprintf(out, cap, "%s", sub ? sub : "");
    else if (!sub || !*sub)
        n = snprintf(out, cap, "%s", prefix);
    else if (sub[0] == '[')
        n = snprintf(out, cap, "%s%s", prefix, sub);
    else
        n = snprintf(out, cap, "%s.%s", prefix, sub);
    if (cap > 0 && (n < 0 || (size_t)n >= cap)) {
        out[cap - 1] = '\0';
        proto_utf8_trim(out); /* fields go into JSON answers: never half a character */
    }
}

json_t *proto_real(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

json_t *proto_real_array(const double *v, size_t n)
{
    assert(v || !n);
    json_t *a = json_array();
    for (size_t i = 0; a && i < n; i++)
        if (json_array_append_new(a, proto_real(v[i]))) {
            json_decref(a);
            return NULL;
        }
    return a;
}

int proto_fail(aa_error *err, int code, const char *prefix, const char *sub, const char *msg)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, sub);
    return aa_error_set(err, code, field, "%s", msg);
}

int proto_prefix_error(aa_error *err, const char *prefix)
{
    if (!err || !prefix || !*prefix)
        return err ? err->code : AA_EINVAL;
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, err->field);
    snprintf(err->field, sizeof err->field, "%s", field);
    return err->code;
}

int proto_number(const json_t *j, double *out, aa_error *err, const char *prefix, const char *sub)
{
    if (!json_is_number(j))
        return proto_fail(err, AA_EINVAL, prefix, sub, "must be a number");
    double v = json_number_value(j);
    if (!isfinite(v))
        return proto_fail(err, AA_EINVAL, prefix, sub, "must be a finite number");
    *out = v;
    return AA_OK;
}

int proto_check_keys_in(const json_t *obj, const char *const *const *lists, aa_error *err,
                        const char *prefix)
{
    const char *all[PROTO_MAX_KEYS + 1];
    size_t n = 0;
    for (size_t l = 0; lists[l]; l++)
        for (size_t i = 0; lists[l][i] && n < PROTO_MAX_KEYS; i++)
            all[n++] = lists[l][i];
    all[n] = NULL;
    return proto_check_keys(obj, all, err, prefix);
}

int proto_check_keys(const json_t *obj, const char *const *allowed, aa_error *err,
                     const char *prefix)
{
    const char *key;
    json_t *val;
    json_object_foreach((json_t *)obj, key, val)
    {
        bool ok = false;
        for (size_t i = 0; allowed[i] && !ok; i++)
            ok = !strcmp(key, allowed[i]);
        if (!ok) {
            char sub[80];
            snprintf(sub, sizeof sub, "%.60s", key);
            proto_utf8_trim(sub);
            return proto_fail(err, AA_EINVAL, prefix, sub, "unknown field");
        }
    }
    return AA_OK;
}
