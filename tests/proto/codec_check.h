/* Checks shared by the codec tests: JSON from test text, byte-equal encodings, and the round
 * trip every result codec must pass. Include after <cmocka.h>. */
#ifndef AALAB_TESTS_CODEC_CHECK_H
#define AALAB_TESTS_CODEC_CHECK_H

#include <stdlib.h>

#include <jansson.h>

static inline json_t *parse(const char *text)
{
    json_error_t e;
    json_t *j = json_loads(text, JSON_REJECT_DUPLICATES, &e);
    if (!j)
        fail_msg("bad test JSON: %s", e.text);
    return j;
}

static inline void assert_same_bytes(const json_t *a, const json_t *b)
{
    char *x = json_dumps(a, JSON_COMPACT), *y = json_dumps(b, JSON_COMPACT);
    assert_non_null(x);
    assert_non_null(y);
    assert_string_equal(x, y);
    free(x);
    free(y);
}

/* Decoding text with decode into a T fails with code, naming field want. */
#define DECODE_FAILS(T, decode, text, code, want)                                                  \
    do {                                                                                           \
        json_t *j_ = parse(text);                                                                  \
        T s_;                                                                                      \
        aa_error e_ = {0};                                                                         \
        assert_int_equal(decode(j_, &s_, &e_), code);                                              \
        assert_string_equal(e_.field, want);                                                       \
        json_decref(j_);                                                                           \
    } while (0)

/* Encodes r, decodes it into a fresh T, re-encodes: the same bytes; the decoder refuses the
 * encoding with an unknown key, naming it. out gets the first encoding (the caller's). */
#define ROUND_TRIP(T, encode, decode, free_fn, r, out)                                             \
    do {                                                                                           \
        json_t *a_ = encode(r);                                                                    \
        assert_non_null(a_);                                                                       \
        T d_;                                                                                      \
        aa_error e_ = {0};                                                                         \
        assert_int_equal(decode(a_, &d_, &e_), AA_OK);                                             \
        json_t *b_ = encode(&d_);                                                                  \
        assert_non_null(b_);                                                                       \
        assert_same_bytes(a_, b_);                                                                 \
        json_decref(b_);                                                                           \
        free_fn(&d_);                                                                              \
        json_t *c_ = json_deep_copy(a_);                                                           \
        json_object_set_new(c_, "surprise", json_true());                                          \
        assert_int_not_equal(decode(c_, &d_, &e_), AA_OK);                                         \
        assert_string_equal(e_.field, "surprise");                                                 \
        json_decref(c_);                                                                           \
        (out) = a_;                                                                                \
    } while (0)

#endif
