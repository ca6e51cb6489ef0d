/* POST /v1/render, GET /v1/tiles/{id}.png, POST /v1/predict's e1_by_angle and model and the
 * render job kinds through the daemon's own api_handle() (router, access checks, pattern
 * references, worker pool), no socket. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "aa_pattern.h"
#include "aa_render.h"
#include "api_fixture.h"
#include "png_encode.h"

static api_fixture *fx;

static void configure(aalab_config *cfg)
{
    cfg->workers = 1;
    cfg->test_kinds = true;
}

static int setup(void **state)
{
    (void)state;
    fx = api_fixture_open("render-api", configure);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    return api_fixture_close(fx);
}

static api_response call(const char *method, const char *path, const char *body)
{
    api_response resp;
    api_request_raw(fx, method, path, body, getuid(), &resp);
    return resp;
}

static json_t *json_of(const api_response *r)
{
    json_t *j = json_loadb(r->body, r->body_len, 0, NULL);
    assert_non_null(j);
    return j;
}

static const char *error_field(json_t *j)
{
    return json_string_value(json_object_get(json_object_get(j, "error"), "field"));
}

/* A POST that must fail with status, naming field. */
static void expect_error(const char *path, const char *body, int status, const char *field)
{
    api_response r = call("POST", path, body);
    assert_int_equal(r.status, status);
    json_t *j = json_of(&r);
    assert_string_equal(error_field(j), field);
    json_decref(j);
    api_response_free(&r);
}

static void test_render_and_fetch_tiles(void **state)
{
    (void)state;
    api_response r = call("POST", "/v1/render",
                          "{\"scene\":{\"name\":\"sliver\",\"width\":64,\"height\":48},"
                          "\"pattern\":\"flipquad\",\"reference\":{\"spp\":64},"
                          "\"crop\":{\"x\":8,\"y\":8,\"width\":8,\"height\":8,\"scale\":4}}");
    assert_int_equal(r.status, 200);
    json_t *j = json_of(&r);
    assert_true(json_real_value(json_object_get(json_object_get(j, "stats"), "rmse")) > 0);
    assert_true(json_integer_value(json_object_get(json_object_get(j, "pixels"), "supersampled")) <
                64 * 48);
    const char *url = json_string_value(
        json_object_get(json_object_get(json_object_get(j, "tiles"), "difference"), "url"));
    assert_non_null(url);
    api_response t = call("GET", url, NULL);
    assert_int_equal(t.status, 200);
    assert_string_equal(t.content_type, "image/png");
    uint8_t *px;
    int w, h;
    assert_int_equal(tile_png_decode_gray(t.body, t.body_len, &px, &w, &h, NULL), AA_OK);
    assert_int_equal(w, 64);
    assert_int_equal(h, 48);
    free(px);
    api_response_free(&t);
    api_response missing = call("GET", "/v1/tiles/0123456789abcdef0123456789abcdef.png", NULL);
    assert_int_equal(missing.status, 404);
    api_response_free(&missing);
    json_decref(j);
    api_response_free(&r);
}

static void test_render_errors_name_fields(void **state)
{
    (void)state;
    const struct {
        const char *body, *field;
        int status;
    } cases[] = {
        {"{\"scene\":{\"width\":-1},\"pattern\":\"rgss\"}", "scene.width", 400},
        {"{\"scene\":{\"name\":\"teapot\"},\"pattern\":\"rgss\"}", "scene.name", 400},
        {"{\"pattern\":{\"kernels\":[[[0,0,2]]]}}", "pattern.kernels[0]", 400},
        {"{\"pattern\":\"rgss\",\"reference\":{\"spp\":1000}}", "reference.spp", 400},
        {"{\"pattern\":{\"job\":999999}}", "pattern.job", 400},
        {"{\"pattern\":\"rgss\",\"scene\":{\"width\":1024,\"height\":1024}}", "scene.width", 400},
        {"{\"scene\":{}}", "pattern", 400},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        expect_error("/v1/render", cases[k].body, cases[k].status, cases[k].field);
    }
}

static json_t *wait_job(const char *path)
{
    for (int tries = 0; tries < 600; tries++) {
        api_response r = call("GET", path, NULL);
        json_t *j = json_of(&r);
        api_response_free(&r);
        const char *st = json_string_value(json_object_get(j, "state"));
        if (st && strcmp(st, "queued") != 0 && strcmp(st, "running") != 0)
            return j;
        json_decref(j);
        nanosleep(&(struct timespec){0, 50 * 1000 * 1000}, NULL);
    }
    fail_msg("job %s did not finish", path);
    return NULL;
}

static void test_compare_job_through_the_pool(void **state)
{
    (void)state;
    api_response r = call("POST", "/v1/jobs",
                          "{\"kind\":\"compare\",\"scene\":{\"name\":\"rings\",\"width\":48,"
                          "\"height\":48},\"reference\":{\"spp\":64},\"patterns\":[\"centroid\","
                          "\"flipquad\"]}");
    assert_int_equal(r.status, 202);
    json_t *j = json_of(&r);
    char path[64];
    json_t *id = json_object_get(j, "id");
    if (json_is_integer(id))
        snprintf(path, sizeof path, "/v1/jobs/%lld", (long long)json_integer_value(id));
    else
        snprintf(path, sizeof path, "/v1/jobs/%s", json_string_value(id));
    json_decref(j);
    api_response_free(&r);
    json_t *done = wait_job(path);
    assert_string_equal(json_string_value(json_object_get(done, "state")), "done");
    json_t *rows = json_object_get(json_object_get(done, "result"), "rows");
    assert_int_equal(json_array_size(rows), 2);
    json_decref(done);
    expect_error("/v1/jobs",
                 "{\"kind\":\"animation\",\"scene\":{\"name\":\"rings\"},\"pattern\":\"rgss\"}",
                 400, "scene.name");
}

/* sqrt(mean over kernels of E1²) at angle deg from POST /v1/evaluate's detail: the metric's
 * own evaluation, a second path to the values POST /v1/predict's e1_by_angle gives. */
static double evaluate_e1_rms(const char *preset, int deg)
{
    char body[160];
    snprintf(body, sizeof body, "{\"pattern\":{\"preset\":\"%s\"},\"angles\":[%d],\"detail\":true}",
             preset, deg);
    api_response r = call("POST", "/v1/evaluate", body);
    assert_int_equal(r.status, 200);
    json_t *j = json_of(&r);
    json_t *detail = json_object_get(j, "detail");
    double sum = 0;
    size_t n = json_array_size(detail);
    assert_true(n > 0);
    for (size_t k = 0; k < n; k++) {
        json_t *a = json_array_get(json_object_get(json_array_get(detail, k), "angles"), 0);
        double e1 = json_real_value(json_object_get(a, "e1"));
        sum += e1 * e1;
    }
    json_decref(j);
    api_response_free(&r);
    return sqrt(sum / (double)n);
}

static void test_predict_e1_by_angle(void **state)
{
    (void)state;
    const char *scene = "\"scene\":{\"name\":\"half-plane\",\"width\":64,\"height\":64,"
                        "\"angle\":27,\"offset\":0.37}";
    char body[256];
    snprintf(body, sizeof body, "{%s,\"pattern\":\"flipquad\",\"e1_by_angle\":true}", scene);
    api_response r = call("POST", "/v1/predict", body);
    assert_int_equal(r.status, 200);
    json_t *j = json_of(&r);
    json_t *pred = json_array_get(json_object_get(j, "predictions"), 0);
    json_t *by_angle = json_object_get(pred, "e1_by_angle");
    assert_int_equal(json_array_size(by_angle), 180);
    /* Where the scene has its edge, the value the prediction used. */
    json_t *top = json_array_get(json_object_get(pred, "angles"), 0);
    assert_int_equal(json_integer_value(json_object_get(top, "angle")), 27);
    double at27 = json_real_value(json_array_get(by_angle, 27));
    assert_float_equal(at27, json_real_value(json_object_get(top, "e1_rms")), 1e-12 * at27);
    /* Everywhere, the metric's E1 as POST /v1/evaluate computes it (FLIPQUAD: four kernels). */
    for (int deg = 0; deg < 180; deg += 45) {
        double want = evaluate_e1_rms("flipquad", deg);
        double got = json_real_value(json_array_get(by_angle, (size_t)deg));
        assert_true(want > 0);
        assert_float_equal(got, want, 1e-9 * want);
    }
    json_decref(j);
    api_response_free(&r);
    /* Off by default: the same prediction, without the 180 values. */
    snprintf(body, sizeof body, "{%s,\"pattern\":\"flipquad\"}", scene);
    r = call("POST", "/v1/predict", body);
    assert_int_equal(r.status, 200);
    j = json_of(&r);
    pred = json_array_get(json_object_get(j, "predictions"), 0);
    assert_null(json_object_get(pred, "e1_by_angle"));
    json_decref(j);
    api_response_free(&r);
    expect_error("/v1/predict", "{\"pattern\":\"rgss\",\"e1_by_angle\":1}", 400, "e1_by_angle");
}

/* POST /v1/predict's model: each gives the engine's own value (aa_predict_rmse_with on the same
 * scene, pattern and histogram) for the phase-locked 27° half-plane, the default is the edge
 * model, the answer names the model, and a bad value is named. */
static double engine_prediction(unsigned model)
{
    aa_error err = {0};
    aa_pattern p;
    assert_int_equal(aa_pattern_from_preset(&p, aa_preset_find("rgss"), &err), 0);
    aa_scene_params sp = aa_scene_params_default(aa_scene_shape_from_name("half-plane"));
    sp.width = 96;
    sp.height = 64;
    sp.angle_deg = 27;
    sp.offset = 0.37;
    aa_scene scene;
    assert_int_equal(aa_scene_init(&scene, &sp, &err), 0);
    aa_edge_histogram *h = malloc(sizeof *h);
    assert_non_null(h);
    assert_int_equal(aa_edge_histogram_of_scene(&scene, h, &err), 0);
    aa_prediction pred;
    assert_int_equal(aa_predict_rmse_with(&p, NULL, h, model, &pred, &err), 0);
    free(h);
    aa_pattern_free(&p);
    return pred.rmse;
}

static double served_prediction(const char *model_key, const char *want_model)
{
    char body[256];
    snprintf(body, sizeof body,
             "{\"scene\":{\"name\":\"half-plane\",\"width\":96,\"height\":64,\"angle\":27,"
             "\"offset\":0.37},\"pattern\":\"rgss\",\"e1_by_angle\":true%s}",
             model_key);
    api_response r = call("POST", "/v1/predict", body);
    assert_int_equal(r.status, 200);
    json_t *j = json_of(&r);
    assert_string_equal(json_string_value(json_object_get(j, "model")), want_model);
    json_t *pred = json_array_get(json_object_get(j, "predictions"), 0);
    double rmse = json_real_value(json_object_get(pred, "predicted_rmse"));
    /* E1 at every angle is against the same reference as the prediction's bins. */
    json_t *top = json_array_get(json_object_get(pred, "angles"), 0);
    double at27 = json_real_value(json_array_get(json_object_get(pred, "e1_by_angle"), 27));
    assert_int_equal(json_integer_value(json_object_get(top, "angle")), 27);
    assert_float_equal(at27, json_real_value(json_object_get(top, "e1_rms")), 1e-12 * at27);
    json_decref(j);
    api_response_free(&r);
    return rmse;
}

static void test_predict_models(void **state)
{
    (void)state;
    double edge = engine_prediction(0), profile = engine_prediction(AA_PREDICT_REFERENCE_PROFILE),
           exact = engine_prediction(AA_PREDICT_EXACT_REFERENCE);
    /* The three differ on this scene, so each comparison below tells the models apart. */
    assert_true(fabs(edge - exact) > 1e-3 * exact && fabs(profile - exact) > 1e-3 * exact &&
                fabs(edge - profile) > 1e-6 * edge);
    double got = served_prediction("", "edge");
    assert_float_equal(got, edge, 1e-12 * edge);
    got = served_prediction(",\"model\":\"edge\"", "edge");
    assert_float_equal(got, edge, 1e-12 * edge);
    got = served_prediction(",\"model\":\"reference-profile\"", "reference-profile");
    assert_float_equal(got, profile, 1e-12 * profile);
    got = served_prediction(",\"model\":\"exact\"", "exact");
    assert_float_equal(got, exact, 1e-12 * exact);
    /* The exact sums count towards the work bound: 64 patterns on a 4096² half-plane at 27° are
     * within it for the edge model, not for the exact one. */
    char body[2048];
    int n = snprintf(body, sizeof body,
                     "{\"scene\":{\"name\":\"half-plane\",\"width\":4096,"
                     "\"height\":4096,\"angle\":27},\"patterns\":[");
    for (int i = 0; i < 64; i++)
        n += snprintf(body + n, sizeof body - (size_t)n, "%s\"d3d-16x\"", i ? "," : "");
    snprintf(body + n, sizeof body - (size_t)n, "],\"model\":\"exact\"}");
    expect_error("/v1/predict", body, 400, "patterns");
    snprintf(strstr(body, ",\"model\""), 20, "}");
    api_response r = call("POST", "/v1/predict", body);
    assert_int_equal(r.status, 200);
    api_response_free(&r);
    expect_error("/v1/predict", "{\"pattern\":\"rgss\",\"model\":\"segments\"}", 400, "model");
    expect_error("/v1/predict", "{\"pattern\":\"rgss\",\"model\":3}", 400, "model");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_render_and_fetch_tiles),
        cmocka_unit_test(test_render_errors_name_fields),
        cmocka_unit_test(test_compare_job_through_the_pool),
        cmocka_unit_test(test_predict_e1_by_angle),
        cmocka_unit_test(test_predict_models),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
