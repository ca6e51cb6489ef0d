/* PNG round trip, tile store (bounds, LRU, ids, disk persistence, threads), request decoding
 * with field paths, and the tile render JSON. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "codec_render.h"
#include "png_encode.h"
#include "aa_pattern.h"
#include "tile_parallel.h"
#include "tile_render.h"
#include "tile_store.h"

static void test_png_round_trip(void **state)
{
    (void)state;
    uint8_t px[6 * 4];
    for (int k = 0; k < 24; k++)
        px[k] = (uint8_t)(k * 11);
    void *png;
    size_t len;
    assert_int_equal(tile_png_encode_gray(px, 6, 4, &png, &len, NULL), AA_OK);
    assert_true(len > 8 && memcmp(png, "\x89PNG", 4) == 0);
    uint8_t *back;
    int w, h;
    assert_int_equal(tile_png_decode_gray(png, len, &back, &w, &h, NULL), AA_OK);
    assert_int_equal(w, 6);
    assert_int_equal(h, 4);
    assert_memory_equal(back, px, 24);
    free(back);
    free(png);
    assert_int_not_equal(tile_png_decode_gray("nope", 4, &back, &w, &h, NULL), AA_OK);
}

static void test_store_ids_bounds_and_lru(void **state)
{
    (void)state;
    tile_store *ts = tile_store_create(NULL, 100, NULL);
    assert_non_null(ts);
    char a[TILE_ID_LEN + 1], b[TILE_ID_LEN + 1], c[TILE_ID_LEN + 1], again[TILE_ID_LEN + 1];
    char buf[60];
    memset(buf, 'a', sizeof buf);
    assert_int_equal(tile_store_put(ts, buf, 40, a, NULL), AA_OK);
    assert_true(tile_id_valid(a));
    assert_int_equal(tile_store_put(ts, buf, 40, again, NULL), AA_OK);
    assert_string_equal(a, again); /* content addressed */
    buf[0] = 'b';
    assert_int_equal(tile_store_put(ts, buf, 40, b, NULL), AA_OK);
    assert_string_not_equal(a, b);
    void *data;
    size_t len;
    assert_int_equal(tile_store_get(ts, a, &data, &len), AA_OK); /* a is now most recent */
    assert_int_equal(len, 40);
    free(data);
    buf[0] = 'c';
    assert_int_equal(tile_store_put(ts, buf, 40, c, NULL), AA_OK); /* evicts b */
    assert_int_equal(tile_store_get(ts, b, &data, &len), TILE_ENOENT);
    assert_int_equal(tile_store_get(ts, a, &data, &len), AA_OK);
    free(data);
    tile_store_usage u = tile_store_usage_get(ts);
    assert_true(u.bytes <= 100);
    assert_int_equal(u.tiles, 2);
    assert_int_equal(tile_store_get(ts, "../etc/passwd", &data, &len), AA_EINVAL);
    assert_int_equal(tile_store_put(ts, buf, 0, c, NULL), AA_OK);
    char big[200] = {0};
    assert_int_equal(tile_store_put(ts, big, sizeof big, c, NULL), AA_ERANGE);
    tile_store_destroy(ts);
}

static void test_store_persists_in_state_dir(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-tiles-XXXXXX";
    assert_non_null(mkdtemp(dir));
    tile_store *ts = tile_store_create(dir, 1000, NULL);
    assert_non_null(ts);
    char id[TILE_ID_LEN + 1];
    assert_int_equal(tile_store_put(ts, "hello tile", 10, id, NULL), AA_OK);
    tile_store_destroy(ts);
    ts = tile_store_create(dir, 1000, NULL);
    void *data;
    size_t len;
    assert_int_equal(tile_store_get(ts, id, &data, &len), AA_OK);
    assert_int_equal(len, 10);
    assert_memory_equal(data, "hello tile", 10);
    free(data);
    tile_store_destroy(ts);
    char path[256];
    snprintf(path, sizeof path, "%s/tiles/%s.png", dir, id);
    unlink(path);
    snprintf(path, sizeof path, "%s/tiles", dir);
    rmdir(path);
    rmdir(dir);
}

/* Private tiles: readable by the uids that stored them (and admin), also after a restart; a team
 * put of the same bytes makes the tile the team's; eviction removes the readers file too. */
static void test_store_private_tiles(void **state)
{
    (void)state;
    char dir[] = "/tmp/aalab-tiles-XXXXXX";
    assert_non_null(mkdtemp(dir));
    tile_store *ts = tile_store_create(dir, 1000, NULL);
    char id[TILE_ID_LEN + 1], other[TILE_ID_LEN + 1];
    tile_access alice = {.owner = 1000, .private_tile = true};
    tile_access bob = {.owner = 1001, .private_tile = true};
    assert_int_equal(tile_store_put_as(ts, "secret tile", 11, &alice, id, NULL), AA_OK);
    void *data;
    size_t len;
    assert_int_equal(tile_store_get_as(ts, id, 1001, false, &data, &len), TILE_ENOENT);
    assert_null(data);
    assert_int_equal(tile_store_get_as(ts, id, -1, false, &data, &len), TILE_ENOENT);
    assert_int_equal(tile_store_get_as(ts, id, 1000, false, &data, &len), AA_OK);
    free(data);
    assert_int_equal(tile_store_get_as(ts, id, 0, true, &data, &len), AA_OK);
    free(data);
    tile_store_destroy(ts);

    ts = tile_store_create(dir, 1000, NULL); /* restart: the readers come back from disk */
    assert_int_equal(tile_store_get_as(ts, id, 1001, false, &data, &len), TILE_ENOENT);
    assert_int_equal(tile_store_get_as(ts, id, 1000, false, &data, &len), AA_OK);
    free(data);
    /* bob renders the same bytes privately: both read it, nobody else */
    assert_int_equal(tile_store_put_as(ts, "secret tile", 11, &bob, other, NULL), AA_OK);
    assert_string_equal(other, id);
    assert_int_equal(tile_store_get_as(ts, id, 1001, false, &data, &len), AA_OK);
    free(data);
    assert_int_equal(tile_store_get_as(ts, id, 1002, false, &data, &len), TILE_ENOENT);
    /* a team put opens it to all, durably */
    assert_int_equal(tile_store_put(ts, "secret tile", 11, other, NULL), AA_OK);
    tile_store_destroy(ts);
    ts = tile_store_create(dir, 1000, NULL);
    assert_int_equal(tile_store_get_as(ts, id, 1002, false, &data, &len), AA_OK);
    free(data);
    /* eviction of a private tile removes its readers file */
    assert_int_equal(tile_store_put_as(ts, "other secret", 12, &alice, other, NULL), AA_OK);
    char path[256];
    snprintf(path, sizeof path, "%s/tiles/%s.readers", dir, other);
    assert_int_equal(access(path, F_OK), 0);
    char big[990];
    memset(big, 7, sizeof big);
    char big_id[TILE_ID_LEN + 1];
    assert_int_equal(tile_store_put(ts, big, sizeof big, big_id, NULL), AA_OK);
    assert_int_not_equal(access(path, F_OK), 0);
    tile_store_destroy(ts);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static void *put_many(void *arg)
{
    tile_store *ts = arg;
    char buf[32], id[TILE_ID_LEN + 1];
    for (int k = 0; k < 500; k++) {
        snprintf(buf, sizeof buf, "%p-%d", (void *)&buf, k);
        if (tile_store_put(ts, buf, strlen(buf), id, NULL))
            return (void *)1;
        void *d;
        size_t len;
        int rc = tile_store_get(ts, id, &d, &len);
        if (rc == AA_OK)
            free(d);
        else if (rc != TILE_ENOENT)
            return (void *)1;
    }
    return NULL;
}

static void test_store_is_thread_safe(void **state)
{
    (void)state;
    tile_store *ts = tile_store_create(NULL, 2000, NULL);
    pthread_t t[4];
    for (int k = 0; k < 4; k++)
        assert_int_equal(pthread_create(&t[k], NULL, put_many, ts), 0);
    for (int k = 0; k < 4; k++) {
        void *r;
        pthread_join(t[k], &r);
        assert_null(r);
    }
    assert_true(tile_store_usage_get(ts).bytes <= 2000);
    tile_store_destroy(ts);
}

static json_t *parse(const char *text)
{
    json_error_t e;
    json_t *j = json_loads(text, JSON_REJECT_DUPLICATES, &e);
    assert_non_null(j);
    return j;
}

static void test_decoding_names_fields(void **state)
{
    (void)state;
    aa_scene_params sp;
    aa_error err = {0};
    json_t *j = parse("{\"name\":\"spiral\",\"width\":64,\"height\":48,\"zoom\":2}");
    assert_int_equal(proto_decode_scene(j, &sp, "scene", &err), AA_OK);
    assert_int_equal(sp.shape, AA_SCENE_SPIRAL);
    assert_int_equal(sp.width, 64);
    json_decref(j);
    const struct {
        const char *json, *field;
    } bad[] = {
        {"{\"name\":\"teapot\"}", "scene.name"},
        {"{\"width\":\"wide\"}", "scene.width"},
        {"{\"width\":0}", "scene.width"},
        {"{\"zoom\":0}", "scene.zoom"},
        {"{\"colour\":1}", "scene.colour"},
        {"{\"name\":\"rotating-triangle\",\"frames\":4,\"frame\":4}", "scene.frame"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        j = parse(bad[k].json);
        memset(&err, 0, sizeof err);
        assert_int_equal(proto_decode_scene(j, &sp, "scene", &err), AA_EINVAL);
        assert_string_equal(err.field, bad[k].field);
        json_decref(j);
    }
    proto_reference_spec rs;
    j = parse("{\"spp\":256,\"seed\":9,\"filter\":{\"name\":\"mitchell\",\"B\":0,\"C\":0.5}}");
    assert_int_equal(proto_decode_reference(j, &rs, "reference", &err), AA_OK);
    assert_int_equal(rs.params.spp, 256);
    assert_ptr_equal(rs.params.filter, &rs.filter);
    assert_float_equal(rs.filter.C, 0.5, 1e-15);
    json_decref(j);
    j = parse("{\"spp\":1000}");
    assert_int_equal(proto_decode_reference(j, &rs, "reference", &err), AA_EINVAL);
    assert_string_equal(err.field, "reference.spp");
    json_decref(j);
    j = parse("{\"filter\":\"wobbly\"}");
    assert_int_equal(proto_decode_reference(j, &rs, "reference", &err), AA_EINVAL);
    assert_true(strncmp(err.field, "reference.filter", 16) == 0);
    json_decref(j);
    proto_crop crop;
    j = parse("{\"x\":60,\"width\":10}");
    assert_int_equal(proto_decode_crop(j, 64, 64, &crop, "crop", &err), AA_EINVAL);
    assert_string_equal(err.field, "crop.width");
    json_decref(j);
    aa_pattern p;
    j = json_string("nonesuch");
    assert_int_equal(proto_pattern_from_preset_name(j, &p, "pattern", &err), AA_EINVAL);
    assert_string_equal(err.field, "pattern");
    json_decref(j);
}

static void test_render_result_json_and_tiles(void **state)
{
    (void)state;
    tile_store *ts = tile_store_create(NULL, 1 << 20, NULL);
    aa_render_params rp = aa_render_params_default(AA_SCENE_SIEMENS_STAR);
    rp.scene.width = 48;
    rp.scene.height = 40;
    rp.reference.spp = 16;
    aa_pattern p;
    json_t *name = json_string("flipquad");
    assert_int_equal(proto_pattern_from_preset_name(name, &p, "pattern", NULL), AA_OK);
    json_decref(name);
    aa_render_result r;
    assert_int_equal(aa_render_tile(&rp, &p, &r, NULL), AA_OK);
    proto_crop crop = {true, {8, 8, 24, 20}, 4};
    json_t *tiles_json = tile_put_render_images_as(ts, NULL, &r.pattern, &r.reference, &crop, NULL);
    json_t *out = proto_encode_render_result(&rp, &p, &r, tiles_json);
    assert_non_null(out);
    assert_float_equal(json_real_value(json_object_get(json_object_get(out, "stats"), "rmse")),
                       r.diff.rmse, 1e-12);
    assert_float_equal(json_real_value(json_object_get(out, "e2")), 0.364, 0.002);
    json_t *tiles = json_object_get(out, "tiles");
    const char *id = json_string_value(json_object_get(json_object_get(tiles, "difference"), "id"));
    assert_non_null(id);
    void *png;
    size_t len;
    assert_int_equal(tile_store_get(ts, id, &png, &len), AA_OK);
    uint8_t *px;
    int w, h;
    assert_int_equal(tile_png_decode_gray(png, len, &px, &w, &h, NULL), AA_OK);
    assert_int_equal(w, 48);
    assert_int_equal(h, 40);
    assert_int_equal(px[0], 255); /* corner: no error */
    free(px);
    free(png);
    json_t *c = json_object_get(json_object_get(tiles, "crop"), "pattern");
    assert_int_equal(json_integer_value(json_object_get(c, "width")), 64);
    assert_int_equal(json_integer_value(json_object_get(c, "height")), 48);
    assert_int_equal(
        json_array_size(json_object_get(json_object_get(out, "stats"), "penalised_histogram")),
        256);
    json_decref(out);
    aa_render_result_free(&r);
    aa_pattern_free(&p);
    tile_store_destroy(ts);
}

static int stop_at_half(void *user, double fraction)
{
    (void)user;
    return fraction > 0.5;
}

/* Bands on threads give the very image one call gives; cancellation stops all bands. */
static void test_parallel_reference_is_identical(void **state)
{
    (void)state;
    aa_scene_params sp = aa_scene_params_default(AA_SCENE_CHECKERBOARD);
    sp.width = 40;
    sp.height = 50;
    aa_scene s;
    assert_int_equal(aa_scene_init(&s, &sp, NULL), AA_OK);
    aa_image a, b;
    assert_int_equal(aa_image_init(&a, 40, 50, NULL), AA_OK);
    assert_int_equal(aa_image_init(&b, 40, 50, NULL), AA_OK);
    aa_reference_params rp = aa_reference_params_default();
    rp.spp = 16;
    aa_reference_stats one, many;
    assert_int_equal(aa_render_reference(&s, &rp, 0.5, &a, NULL, &one, NULL), AA_OK);
    assert_int_equal(tile_reference_parallel(&s, &rp, 0.5, &b, 3, &many, NULL), AA_OK);
    assert_memory_equal(a.px, b.px, sizeof(float) * 40 * 50);
    assert_int_equal(one.pixels_supersampled, many.pixels_supersampled);
    assert_true(many.input_pixels >= one.input_pixels);
    rp.progress = stop_at_half;
    aa_error err = {0};
    assert_int_equal(tile_reference_parallel(&s, &rp, 0.5, &b, 3, NULL, &err), AA_ECANCELED);
    aa_image_free(&a);
    aa_image_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png_round_trip),
        cmocka_unit_test(test_store_ids_bounds_and_lru),
        cmocka_unit_test(test_store_persists_in_state_dir),
        cmocka_unit_test(test_store_private_tiles),
        cmocka_unit_test(test_store_is_thread_safe),
        cmocka_unit_test(test_decoding_names_fields),
        cmocka_unit_test(test_render_result_json_and_tiles),
        cmocka_unit_test(test_parallel_reference_is_identical),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
