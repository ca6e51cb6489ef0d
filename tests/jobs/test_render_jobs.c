/* The render job kinds (compare, reference-convergence, animation) through their job_kind
 * interface, with a stub job context: spec validation names fields, results carry the rows the
 * dashboard plots, tiles land in the store, cancellation stops a run. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "job_animation.h"
#include "job_compare.h"
#include "job_reference_convergence.h"
#include "kinds.h"
#include "tile_store.h"

/* The kinds' own rows (job_kind_compare, ... in their kind files) are run. */

/* Stub context: the worker pool is not part of this test. */
struct job_ctx {
    tile_store *tiles;
    int progress_calls;
    int cancel_after; /* 0: never */
    double last_fraction;
    bool private_job;
    double best_e2; /* e2 of the last best posted; NaN: none */
    char best_family[64];
};

bool job_ctx_progress(job_ctx *ctx, double fraction, json_t *best_so_far)
{
    if (best_so_far) {
        ctx->best_e2 = json_real_value(json_object_get(best_so_far, "e2"));
        snprintf(
            ctx->best_family, sizeof ctx->best_family, "%s",
            json_string_value(json_object_get(json_object_get(best_so_far, "pattern"), "family")));
    }
    assert_true(fraction >= ctx->last_fraction - 1e-12 && fraction <= 1 + 1e-12);
    ctx->last_fraction = fraction;
    ctx->progress_calls++;
    return ctx->cancel_after && ctx->progress_calls >= ctx->cancel_after;
}

void job_ctx_trace(job_ctx *ctx, const job_trace_point *point)
{
    (void)ctx;
    (void)point;
}

bool job_ctx_cancelled(const job_ctx *ctx)
{
    return ctx->cancel_after && ctx->progress_calls >= ctx->cancel_after;
}

int job_ctx_workers(const job_ctx *ctx)
{
    (void)ctx;
    return 2; /* exercises the banded reference */
}

tile_store *job_ctx_tiles(job_ctx *ctx)
{
    return ctx->tiles;
}

long long job_ctx_owner(const job_ctx *ctx)
{
    (void)ctx;
    return 1000;
}

bool job_ctx_private(const job_ctx *ctx)
{
    return ctx->private_job;
}

static json_t *parse(const char *text)
{
    json_error_t e;
    json_t *j = json_loads(text, JSON_REJECT_DUPLICATES, &e);
    assert_non_null(j);
    return j;
}

/* A result the kind made decodes with its strict proto decoder and encodes to the same bytes. */
#define ROUND_TRIP(T, decode, encode, free_fn, j)                                                  \
    do {                                                                                           \
        T r_;                                                                                      \
        aa_error e_ = {0};                                                                         \
        assert_int_equal(decode(j, &r_, &e_), AA_OK);                                              \
        json_t *again_ = encode(&r_);                                                              \
        char *a_ = json_dumps(j, JSON_COMPACT), *b_ = json_dumps(again_, JSON_COMPACT);            \
        assert_string_equal(a_, b_);                                                               \
        free(a_);                                                                                  \
        free(b_);                                                                                  \
        json_decref(again_);                                                                       \
        free_fn(&r_);                                                                              \
    } while (0)

static void strict_round_trip(const job_kind *k, const json_t *j)
{
    if (!strcmp(k->name, "compare"))
        ROUND_TRIP(proto_compare_result, proto_decode_compare_result, proto_encode_compare_result,
                   proto_compare_result_free, j);
    else if (!strcmp(k->name, "animation"))
        ROUND_TRIP(proto_animation_result, proto_decode_animation_result,
                   proto_encode_animation_result, proto_animation_result_free, j);
    else
        ROUND_TRIP(proto_reference_convergence_result, proto_decode_reference_convergence_result,
                   proto_encode_reference_convergence_result,
                   proto_reference_convergence_result_free, j);
}

static int run(const job_kind *k, const char *spec, job_ctx *ctx, json_t **result, aa_error *err)
{
    json_t *s = parse(spec);
    json_object_del(s, "kind"); /* the job manager's envelope */
    void *params = NULL;
    int rc = k->decode(s, &params, err);
    json_decref(s);
    if (rc)
        return rc;
    void *typed = NULL;
    *result = NULL;
    rc = k->run(params, ctx, &typed, err);
    if (rc == AA_OK) {
        *result = k->encode_result(typed);
        assert_non_null(*result);
        strict_round_trip(k, *result);
    }
    k->free_result(typed);
    k->free_params(params);
    return rc;
}

static void test_compare_rows(void **state)
{
    (void)state;
    /* A private job: its tiles are its owner's (uid 1000 in the stub) and root's only. */
    job_ctx ctx = {.tiles = tile_store_create(NULL, 1 << 22, NULL), .private_job = true};
    json_t *res = NULL;
    aa_error err = {0};
    int rc = run(&job_kind_compare,
                 "{\"kind\":\"compare\",\"scene\":{\"name\":\"siemens-star\",\"width\":48,"
                 "\"height\":48},\"reference\":{\"spp\":64},\"patterns\":[\"centroid\","
                 "\"flipquad\",{\"preset\":\"rgss\"},{\"kernels\":[[[0,0,1]]]},"
                 "{\"tile\":{\"size\":1,\"kernel\":2,\"samples\":[[0.25,0.25],[0.75,0.25],"
                 "[0.25,0.75],[0.75,0.75]]}}]}",
                 &ctx, &res, &err);
    assert_int_equal(rc, AA_OK);
    json_t *rows = json_object_get(res, "rows");
    assert_int_equal(json_array_size(rows), 5);
    /* The rows' E2 use the default table, recorded by name and version. */
    json_t *acuity = json_object_get(res, "acuity");
    aa_acuity naiman;
    aa_acuity_naiman(&naiman);
    assert_string_equal(json_string_value(json_object_get(acuity, "name")), "naiman");
    assert_int_equal(json_integer_value(json_object_get(acuity, "version")), naiman.version);
    /* Odd and even kernels are compared against references on their own output grids. */
    assert_int_equal(json_array_size(json_object_get(json_object_get(res, "reference"), "renders")),
                     2);
    json_t *centroid = json_array_get(rows, 0), *flipquad = json_array_get(rows, 1);
    assert_true(json_real_value(json_object_get(json_array_get(rows, 4), "rmse")) <
                json_real_value(json_object_get(centroid, "rmse")));
    assert_string_equal(json_string_value(json_object_get(centroid, "name")), "centroid");
    assert_string_equal(json_string_value(json_object_get(flipquad, "name")), "flipquad");
    assert_float_equal(json_real_value(json_object_get(flipquad, "samples_per_pixel")), 2, 0);
    assert_float_equal(json_real_value(json_object_get(flipquad, "e2")), 0.364, 0.002);
    /* More samples, less error: FLIPQUAD beats one sample per pixel on the star. */
    assert_true(json_real_value(json_object_get(flipquad, "rmse")) <
                json_real_value(json_object_get(centroid, "rmse")));
    /* The explicit one-sample kernel is the centroid pattern: same image, same error. */
    assert_float_equal(json_real_value(json_object_get(json_array_get(rows, 3), "rmse")),
                       json_real_value(json_object_get(centroid, "rmse")), 1e-9);
    /* The edge model beside every row, and its rank correlation with the renders. */
    for (size_t i = 0; i < json_array_size(rows); i++)
        assert_true(json_real_value(json_object_get(json_array_get(rows, i), "predicted_rmse")) >
                    0);
    json_t *prediction = json_object_get(res, "prediction");
    assert_true(json_is_number(json_object_get(prediction, "spearman")));
    assert_true(json_real_value(json_object_get(prediction, "spearman")) > 0.5);
    assert_true(json_real_value(json_object_get(prediction, "subpixel_area_share")) > 0);
    /* The star's centre is below the pixel scale: part of every row's error falls there. */
    double share = json_real_value(json_object_get(centroid, "subpixel_error_share"));
    assert_true(share > 0 && share < 1);
    const char *id = json_string_value(
        json_object_get(json_object_get(json_object_get(flipquad, "tiles"), "difference"), "id"));
    void *png;
    size_t len;
    assert_int_equal(tile_store_get_as(ctx.tiles, id, 1000, false, &png, &len), AA_OK);
    free(png);
    assert_int_equal(tile_store_get_as(ctx.tiles, id, 0, true, &png, &len), AA_OK);
    free(png);
    assert_int_equal(tile_store_get_as(ctx.tiles, id, 1001, false, &png, &len), TILE_ENOENT);
    assert_true(ctx.progress_calls > 0);
    json_decref(res);

    rc = run(&job_kind_compare, "{\"kind\":\"compare\",\"patterns\":[\"centroid\",\"nope\"]}", &ctx,
             &res, &err);
    assert_int_equal(rc, AA_EINVAL);
    assert_string_equal(err.field, "patterns[1]");
    rc = run(&job_kind_compare, "{\"kind\":\"compare\",\"patterns\":[]}", &ctx, &res, &err);
    assert_string_equal(err.field, "patterns");
    rc = run(&job_kind_compare, "{\"kind\":\"compare\",\"patterns\":[\"centroid\"],\"x\":1}", &ctx,
             &res, &err);
    assert_string_equal(err.field, "x");
    tile_store_destroy(ctx.tiles);
}

static void test_reference_convergence_decreases(void **state)
{
    (void)state;
    job_ctx ctx = {.tiles = NULL};
    json_t *res = NULL;
    aa_error err = {0};
    int rc = run(&job_kind_reference_convergence,
                 "{\"kind\":\"reference-convergence\",\"scene\":{\"name\":\"rings\",\"width\":40,"
                 "\"height\":40},\"levels\":[4,16,64],\"baseline_spp\":1024}",
                 &ctx, &res, &err);
    assert_int_equal(rc, AA_OK);
    json_t *rows = json_object_get(res, "rows");
    assert_int_equal(json_array_size(rows), 3);
    double prev = 1e9;
    for (size_t i = 0; i < 3; i++) {
        double rmse = json_real_value(json_object_get(json_array_get(rows, i), "rmse"));
        assert_true(rmse > 0 && rmse < prev);
        assert_true(json_real_value(json_object_get(json_array_get(rows, i), "seconds")) >= 0);
        prev = rmse;
    }
    assert_int_equal(json_integer_value(json_object_get(json_object_get(res, "baseline"), "spp")),
                     1024);
    json_decref(res);
    rc = run(&job_kind_reference_convergence,
             "{\"kind\":\"reference-convergence\",\"levels\":[16,50]}", &ctx, &res, &err);
    assert_int_equal(rc, AA_EINVAL);
    assert_string_equal(err.field, "levels[1]");
}

static void test_animation_frames_and_cancel(void **state)
{
    (void)state;
    job_ctx ctx = {.tiles = tile_store_create(NULL, 1 << 22, NULL)};
    json_t *res = NULL;
    aa_error err = {0};
    const char *spec = "{\"kind\":\"animation\",\"scene\":{\"name\":\"rotating-triangle\","
                       "\"width\":48,\"height\":40,\"frames\":3},\"pattern\":\"quincunx\","
                       "\"reference\":{\"spp\":16},\"acuity\":{\"name\":\"naiman-envelope\"}}";
    assert_int_equal(run(&job_kind_animation, spec, &ctx, &res, &err), AA_OK);
    /* The pattern's E2 is posted as the job's best, so the job list has it (issue 34: the list
     * showed "-" where the detail said 0.438987). */
    assert_true(ctx.best_e2 > 0);
    assert_float_equal(ctx.best_e2, json_real_value(json_object_get(res, "e2")), 0);
    assert_string_equal(ctx.best_family, json_string_value(json_object_get(
                                             json_object_get(res, "pattern"), "family")));
    /* e2 uses the table the spec named, and the result says which. */
    json_t *acuity = json_object_get(res, "acuity");
    assert_string_equal(json_string_value(json_object_get(acuity, "name")), "naiman-envelope");
    assert_int_equal(json_integer_value(json_object_get(acuity, "version")), 1);
    json_t *frames = json_object_get(res, "frames");
    assert_int_equal(json_array_size(frames), 3);
    json_t *total = json_object_get(res, "total");
    assert_int_equal(json_integer_value(json_object_get(total, "pixels")), 3 * 48 * 40);
    assert_int_equal(json_array_size(json_object_get(total, "penalised_histogram")), 256);
    assert_non_null(
        json_object_get(json_object_get(json_array_get(frames, 2), "tiles"), "difference"));
    json_decref(res);
    job_ctx stop = {.cancel_after = 2};
    assert_int_equal(run(&job_kind_animation, spec, &stop, &res, &err), AA_ECANCELED);
    assert_int_equal(run(&job_kind_animation,
                         "{\"kind\":\"animation\",\"scene\":{\"name\":\"spiral\"},"
                         "\"pattern\":\"quincunx\"}",
                         &ctx, &res, &err),
                     AA_EINVAL);
    assert_string_equal(err.field, "scene.name");
    tile_store_destroy(ctx.tiles);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compare_rows),
        cmocka_unit_test(test_reference_convergence_decreases),
        cmocka_unit_test(test_animation_frames_and_cancel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
