/* The job kinds' spec and result codecs (proto/job_*.h): defaults, one unknown-key check naming
 * the key, ranges and invalid families naming the field, result round trips (decode(encode(x))
 * encodes to the same JSON), and nearest-name suggestions for unknown presets. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "codec.h"
#include "codec_check.h"
#include "job_family_sweep.h"
#include "job_optimize.h"
#include "job_random_stats.h"
#include "job_table3.h"
#include "preset_suggest.h"
#include "aa_pattern.h"

static void preset_pattern(const char *name, aa_pattern *p)
{
    aa_error err = {0};
    const aa_preset *pr = aa_preset_find(name);
    assert_non_null(pr);
    assert_int_equal(aa_pattern_from_preset(p, pr, &err), AA_OK);
}

/* Decoding text fails with code naming field. */
#define OPT_FAILS(text, want)                                                                      \
    do {                                                                                           \
        json_t *j_ = parse(text);                                                                  \
        proto_optimize_spec s_;                                                                    \
        aa_error e_ = {0};                                                                         \
        assert_int_not_equal(proto_decode_optimize_spec(j_, &s_, &e_), AA_OK);                     \
        assert_string_equal(e_.field, want);                                                       \
        json_decref(j_);                                                                           \
    } while (0)

static void test_optimize_spec(void **state)
{
    (void)state;
    json_t *j = parse("{\"family\":\"P(4,1+,2)\"}");
    proto_optimize_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_true(s.have_family);
    assert_int_equal(s.seeds, 64);
    assert_true(s.common.max_seconds == 30);
    assert_int_equal(s.common.rng_seed, 1);
    assert_int_equal(s.common.mode, AA_OPTIMIZE_BOTH);
    assert_true(s.common.method_auto);
    assert_int_equal(s.common.grid_bits, 0);
    assert_int_equal(s.distribution_count, 0);
    proto_optimize_spec_free(&s);
    json_decref(j);

    j = parse("{\"pattern\":{\"preset\":\"rgss\"},\"mode\":\"weights\",\"method\":\"minimax\","
              "\"grid\":{\"bits\":3,\"d3d12\":true},\"rng_seed\":9,\"max_seconds\":2}");
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_false(s.have_family);
    assert_int_equal(s.seeds, 1);
    assert_int_equal(s.common.mode, AA_OPTIMIZE_WEIGHTS);
    assert_false(s.common.method_auto);
    assert_int_equal(s.common.method, AA_METHOD_MINIMAX);
    assert_int_equal(s.common.grid_bits, 3);
    assert_true(s.common.d3d12);
    assert_int_equal(s.common.rng_seed, 9);
    proto_optimize_spec_free(&s);
    json_decref(j);

    /* The envelope is the job manager's: a kind's decoder rejects it as unknown. */
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"label\":\"x\"}", "label");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"kind\":\"optimize\"}", "kind");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"seedz\":3}", "seedz");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"seeds\":0}", "seeds");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"seeds\":2.5}", "seeds");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"max_seconds\":0}", "max_seconds");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"max_iterations\":0}", "max_iterations");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"max_iterations\":10000001}", "max_iterations");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"max_iterations\":1.5}", "max_iterations");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"grid\":{\"bits\":13}}", "grid.bits");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"mode\":\"all\"}", "mode");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"distributions\":[\"gauss\"]}", "distributions[0]");
    OPT_FAILS("{\"family\":\"Q(4,1,2)\"}", "family");
    OPT_FAILS("{}", "family");
    OPT_FAILS("{\"family\":\"P(4,1+,2)\",\"pattern\":{\"preset\":\"rgss\"}}", "family");
    OPT_FAILS("{\"pattern\":{\"preset\":\"rgss\"},\"seeds\":2}", "seeds");
    OPT_FAILS("{\"pattern\":{\"preset\":\"flipqaud\"}}", "pattern.preset");
}

/* max_iterations alone: no time budget and a reproducible result; with max_seconds, or with
 * neither, best effort. The same rule for the three optimizer kinds (shared decoder). */
static void test_budget_and_reproducibility(void **state)
{
    (void)state;
    aa_error err = {0};
    proto_optimize_spec s;
    json_t *j = parse("{\"family\":\"P(4,1+,2)\",\"max_iterations\":300}");
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_true(s.common.reproducible);
    assert_true(s.common.max_seconds == 0);
    assert_int_equal(proto_optimizer_spec_iterations(&s.common, 20000), 300);
    proto_optimize_spec_free(&s);
    json_decref(j);
    j = parse("{\"family\":\"P(4,1+,2)\",\"max_iterations\":300,\"max_seconds\":5}");
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_false(s.common.reproducible);
    assert_true(s.common.max_seconds == 5);
    proto_optimize_spec_free(&s);
    json_decref(j);
    j = parse("{\"family\":\"P(4,1+,2)\"}");
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_false(s.common.reproducible);
    assert_int_equal(proto_optimizer_spec_iterations(&s.common, 20000), 20000);
    proto_optimize_spec_free(&s);
    json_decref(j);
    proto_family_sweep_spec f;
    j = parse("{\"cost\":1.25,\"max_iterations\":50}");
    assert_int_equal(proto_decode_family_sweep_spec(j, &f, &err), AA_OK);
    assert_true(f.common.reproducible && f.common.max_seconds == 0);
    proto_family_sweep_spec_free(&f);
    json_decref(j);
    proto_random_stats_spec r;
    j = parse("{\"family\":\"P(1,4,2)\",\"max_iterations\":50}");
    assert_int_equal(proto_decode_random_stats_spec(j, &r, &err), AA_OK);
    assert_true(r.common.reproducible && r.common.max_seconds == 0);
    proto_random_stats_spec_free(&r);
    json_decref(j);
}

static void test_sweep_and_stats_spec(void **state)
{
    (void)state;
    aa_error err = {0};
    json_t *j = parse("{\"family\":\"P(4,1+,1.25)\",\"seeds_per_config\":2}");
    proto_family_sweep_spec s;
    assert_int_equal(proto_decode_family_sweep_spec(j, &s, &err), AA_OK);
    assert_true(s.cost == 1.25);
    assert_string_equal(s.family, "P(4,1+,1.25)");
    assert_int_equal(s.per_config, 2);
    assert_true(s.common.max_seconds == 60);
    proto_family_sweep_spec_free(&s);
    json_decref(j);

    const char *bad[][2] = {{"{\"family\":\"P(16,16,4)\"}", "family"},
                            {"{\"cost\":0.1}", "cost"},
                            {"{}", "family"},
                            {"{\"cost\":1,\"seeds\":3}", "seeds"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        j = parse(bad[i][0]);
        assert_int_not_equal(proto_decode_family_sweep_spec(j, &s, &err), AA_OK);
        assert_string_equal(err.field, bad[i][1]);
        json_decref(j);
    }

    proto_random_stats_spec r;
    j = parse("{\"family\":\"P(1,4,2)\",\"distribution\":\"poisson\"}");
    assert_int_equal(proto_decode_random_stats_spec(j, &r, &err), AA_OK);
    assert_int_equal(r.count, 1000);
    assert_int_equal(r.distribution, AA_SEED_POISSON);
    proto_random_stats_spec_free(&r);
    json_decref(j);
    /* Random patterns of P(4,1,2) can leave a pixel without samples: refused at submit. */
    const char *bad_stats[][2] = {
        {"{\"family\":\"P(4,1,2)\"}", "family"},
        {"{\"family\":\"P(1,4,2)\",\"distribution\":\"x\"}", "distribution"},
        {"{\"family\":\"P(1,4,2)\",\"mode\":\"both\"}", "mode"},
        {"{\"family\":\"P(1,4,2)\",\"count\":0}", "count"}};
    for (size_t i = 0; i < sizeof bad_stats / sizeof bad_stats[0]; i++) {
        j = parse(bad_stats[i][0]);
        assert_int_not_equal(proto_decode_random_stats_spec(j, &r, &err), AA_OK);
        assert_string_equal(err.field, bad_stats[i][1]);
        json_decref(j);
    }
}

/* The shared round trip, its encoding dropped. */
#define ROUND_TRIP_ONLY(type, encode, decode, release, value)                                      \
    do {                                                                                           \
        json_t *enc_;                                                                              \
        ROUND_TRIP(type, encode, decode, release, value, enc_);                                    \
        json_decref(enc_);                                                                         \
    } while (0)

static void test_optimize_result(void **state)
{
    (void)state;
    proto_seed_summary seeds[2] = {{0, AA_SEED_UNIFORM, 0.9, 0.5, 120},
                                   {3, AA_SEED_POISSON, 0.8, 0.45, 80}};
    proto_optimize_result r = {.e2 = 0.45,
                               .argmax_kernel = 0,
                               .argmax_angle_deg = 12.5,
                               .seeds_run = 4,
                               .iterations = 200,
                               .evaluations = 900,
                               .seconds = 1.5,
                               .method = AA_METHOD_LAINE_AILA,
                               .per_seed = seeds,
                               .per_seed_count = 2};
    preset_pattern("rgss", &r.best);
    json_t *j = proto_encode_optimize_result(&r);
    const char *order[] = {"best",        "e2",      "argmax",      "seeds_run", "iterations",
                           "evaluations", "seconds", "family",      "method",    "per_seed",
                           "executor",    "shards",  "reproducible"};
    const char *key;
    json_t *v;
    size_t i = 0;
    json_object_foreach(j, key, v) assert_string_equal(key, order[i++]);
    assert_int_equal(i, 13);
    assert_string_equal(json_string_value(json_object_get(j, "family")), r.best.family);
    assert_string_equal(json_string_value(json_object_get(j, "executor")), "local");
    assert_int_equal(json_integer_value(json_object_get(j, "shards")), 1);
    assert_true(json_is_false(json_object_get(j, "reproducible")));
    json_decref(j);
    ROUND_TRIP_ONLY(proto_optimize_result, proto_encode_optimize_result,
                    proto_decode_optimize_result, proto_optimize_result_free, &r);
    r.run = (proto_run_info){"slurm", 7, true, "naiman-envelope", 1};
    j = proto_encode_optimize_result(&r);
    assert_string_equal(json_string_value(json_object_get(json_object_get(j, "acuity"), "name")),
                        "naiman-envelope");
    assert_int_equal(json_integer_value(json_object_get(json_object_get(j, "acuity"), "version")),
                     1);
    json_decref(j);
    ROUND_TRIP_ONLY(proto_optimize_result, proto_encode_optimize_result,
                    proto_decode_optimize_result, proto_optimize_result_free, &r);
    r.have_grid = true;
    r.grid_bits = 4;
    r.e2_before_snap = 0.44;
    j = proto_encode_optimize_result(&r);
    assert_true(
        fabs(json_number_value(json_object_get(json_object_get(j, "grid"), "quantisation_cost")) -
             0.01) < 1e-12);
    json_decref(j);
    ROUND_TRIP_ONLY(proto_optimize_result, proto_encode_optimize_result,
                    proto_decode_optimize_result, proto_optimize_result_free, &r);
    r.e2 = NAN; /* null on the wire, NaN back */
    ROUND_TRIP_ONLY(proto_optimize_result, proto_encode_optimize_result,
                    proto_decode_optimize_result, proto_optimize_result_free, &r);
    aa_pattern_free(&r.best);
}

/* The scene objective (proto/job_scene_objective.h): spec forms, bad fields, result round trip. */
static void test_optimize_scene_objective(void **state)
{
    (void)state;
    json_t *j = parse("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":{\"name\":\"half-plane\","
                      "\"angle\":2,\"offset\":0.37},\"size\":[64,32],\"blend\":0.25}}");
    proto_optimize_spec s;
    aa_error err = {0};
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_true(s.objective.enabled);
    assert_int_equal(s.objective.scene.shape, AA_SCENE_HALF_PLANE);
    assert_int_equal(s.objective.scene.width, 64);
    assert_int_equal(s.objective.scene.height, 32);
    assert_true(s.objective.scene.angle_deg == 2 && s.objective.scene.offset == 0.37);
    assert_true(s.objective.blend == 0.25);
    proto_optimize_spec_free(&s);
    json_decref(j);
    j = parse("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":\"siemens-star\"}}");
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_true(s.objective.enabled && s.objective.blend == 0);
    assert_int_equal(s.objective.scene.shape, AA_SCENE_SIEMENS_STAR);
    proto_optimize_spec_free(&s);
    json_decref(j);
    j = parse("{\"family\":\"P(1,1,4)\"}");
    assert_int_equal(proto_decode_optimize_spec(j, &s, &err), AA_OK);
    assert_false(s.objective.enabled);
    proto_optimize_spec_free(&s);
    json_decref(j);
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":1}", "objective");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":{}}", "objective.scene");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":\"nope\"}}", "objective.scene");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":{\"name\":\"rings\","
              "\"width\":-1}}}",
              "objective.scene.width");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":\"rings\",\"blend\":-0.1}}",
              "objective.blend");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":\"rings\",\"x\":1}}",
              "objective.x");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"objective\":{\"scene\":\"translating-circle\"}}",
              "objective.scene");
    OPT_FAILS("{\"family\":\"P(1,1,4)\",\"grid\":{\"bits\":4},\"objective\":{\"scene\":"
              "\"rings\"}}",
              "objective");

    proto_optimize_result r = {.e2 = 0.41, .method = AA_METHOD_LAINE_AILA, .seeds_run = 1};
    preset_pattern("rgss", &r.best);
    r.scene = (proto_scene_objective_result){.objective = 0.97,
                                             .predicted_rmse = 1.45,
                                             .e2 = 0.41,
                                             .optimum_predicted_rmse = 1.5,
                                             .optimum_e2 = 0.36};
    r.scene.spec.enabled = true;
    r.scene.spec.blend = 0.5;
    r.scene.spec.scene = aa_scene_params_default(AA_SCENE_HALF_PLANE);
    r.scene.spec.scene.angle_deg = 30;
    j = proto_encode_optimize_result(&r);
    const json_t *so = json_object_get(j, "scene_objective");
    assert_true(json_is_object(so));
    assert_true(json_number_value(json_object_get(so, "predicted_rmse")) == 1.45);
    assert_true(json_number_value(json_object_get(json_object_get(so, "e2_optimum"), "e2")) ==
                0.36);
    json_decref(j);
    ROUND_TRIP_ONLY(proto_optimize_result, proto_encode_optimize_result,
                    proto_decode_optimize_result, proto_optimize_result_free, &r);
    proto_optimize_result back;
    j = proto_encode_optimize_result(&r);
    assert_int_equal(proto_decode_optimize_result(j, &back, &err), AA_OK);
    assert_true(back.scene.spec.enabled && back.scene.spec.scene.angle_deg == 30);
    assert_true(back.scene.objective == 0.97 && back.scene.optimum_predicted_rmse == 1.5);
    proto_optimize_result_free(&back);
    json_decref(j);
    aa_pattern_free(&r.best);
}

static void test_sweep_and_stats_result(void **state)
{
    (void)state;
    proto_sweep_row rows[2] = {
        {1, {{1, 0, 0, 0}, {0, 1, 0, 0}, 0}, 0.75, 0.5, true, {0}},
        {2, {{1, 1, 0, 0}, {0, 0, 0, 0}, 0}, 0.5, INFINITY, false, {0}},
    };
    preset_pattern("rgss", &rows[0].best);
    proto_family_sweep_result s = {0.75, 2, 1, rows, 2, {"slurm", 3, true, "custom", 0}};
    json_t *j = proto_encode_family_sweep_result(&s);
    json_t *custom = json_pack("{s:s}", "name", "custom");
    assert_true(json_equal(json_object_get(j, "acuity"), custom));
    json_decref(custom);
    assert_true(
        json_is_null(json_object_get(json_array_get(json_object_get(j, "ranked"), 1), "best")));
    assert_true(
        json_equal(json_object_get(j, "best"),
                   json_object_get(json_array_get(json_object_get(j, "ranked"), 0), "best")));
    json_decref(j);
    ROUND_TRIP_ONLY(proto_family_sweep_result, proto_encode_family_sweep_result,
                    proto_decode_family_sweep_result, proto_family_sweep_result_free, &s);
    aa_pattern_free(&rows[0].best);

    proto_random_stats_result r = {.distribution = AA_SEED_JITTERED,
                                   .count = 50,
                                   .min = 0.3,
                                   .avg = 0.4,
                                   .max = 0.6,
                                   .opt_w = {0.28, {0}, AA_METHOD_LAINE_AILA},
                                   .opt_wp = {0.25, {0}, AA_METHOD_SMOOTH}};
    snprintf(r.family, sizeof r.family, "P(1,4,1)");
    preset_pattern("rgss", &r.best_random);
    preset_pattern("rgss", &r.opt_w.pattern);
    preset_pattern("flipquad", &r.opt_wp.pattern);
    j = proto_encode_random_stats_result(&r);
    assert_true(json_number_value(json_object_get(j, "e2")) == 0.25);
    assert_true(json_equal(json_object_get(j, "best"),
                           json_object_get(json_object_get(j, "opt_wp"), "pattern")));
    json_decref(j);
    ROUND_TRIP_ONLY(proto_random_stats_result, proto_encode_random_stats_result,
                    proto_decode_random_stats_result, proto_random_stats_result_free, &r);
    proto_random_stats_result_free(&r);
}

/* Issue 31: the metrics list of random-stats and table3 specs, and the point_metrics block of
 * their results through encode / decode (NaN as null) and the shards' columns. */
static void test_point_metrics_codecs(void **state)
{
    (void)state;
    aa_error err = {0};
    proto_random_stats_spec sp;
    json_t *j = parse("{\"family\":\"P(1,1,4)\",\"metrics\":[\"star_linf\",\"centered\"]}");
    assert_int_equal(proto_decode_random_stats_spec(j, &sp, &err), AA_OK);
    assert_int_equal(sp.metrics.count, 2);
    assert_int_equal(sp.metrics.which[0], AA_PM_STAR_LINF);
    assert_int_equal(sp.metrics.which[1], AA_PM_CENTERED);
    proto_random_stats_spec_free(&sp);
    json_decref(j);
    DECODE_FAILS(proto_random_stats_spec, proto_decode_random_stats_spec,
                 "{\"family\":\"P(1,1,4)\",\"metrics\":[\"centered\",\"centered\"]}", AA_EINVAL,
                 "metrics[1]");
    DECODE_FAILS(proto_random_stats_spec, proto_decode_random_stats_spec,
                 "{\"family\":\"P(1,1,4)\",\"metrics\":{}}", AA_EINVAL, "metrics");
    DECODE_FAILS(proto_table3_spec, proto_decode_table3_spec,
                 "{\"family\":\"P(1,1,4)\",\"metrics\":[\"fft\"]}", AA_EINVAL, "metrics[0]");
    /* 8 seeds x 1000 x 2 distributions by default: over the 10,000 patterns */
    DECODE_FAILS(proto_table3_spec, proto_decode_table3_spec,
                 "{\"family\":\"P(1,1,4)\",\"metrics\":[\"mixture\"]}", AA_EINVAL, "metrics");

    proto_point_metrics_spec ms = {{AA_PM_MIXTURE, AA_PM_OSCILLATION}, 2};
    proto_point_metrics pm;
    assert_int_equal(proto_point_metrics_init(&pm, &ms, 5, &err), AA_OK);
    const double e2[5] = {0.5, 0.7, 0.6, 0.9, 0.8};
    const double mix[5] = {0.1, 0.3, 0.2, 0.5, 0.4}, osc[5] = {1, NAN, 3, 2, 2};
    json_t *cols = json_pack("{s:[f,f,f,f,f],s:[f,f,f,f,f],s:[f,n,f,f,f]}", "e2", e2[0], e2[1],
                             e2[2], e2[3], e2[4], "mixture", mix[0], mix[1], mix[2], mix[3], mix[4],
                             "oscillation", osc[0], osc[2], osc[3], osc[4]);
    assert_int_equal(proto_point_metrics_append(&pm, cols, "x", &err), AA_OK);
    /* a shard's columns missing a figure are refused, naming the field given */
    json_object_del(cols, "oscillation");
    assert_int_equal(proto_point_metrics_append(&pm, cols, "output[1]", &err), AA_EINVAL);
    assert_string_equal(err.field, "output[1]");
    json_decref(cols);
    assert_int_equal(proto_point_metrics_rank(&pm, &err), AA_OK);
    assert_true(fabs(pm.rho[0].rho - 1) < 1e-15 && pm.rho[0].n == 5);
    assert_int_equal(pm.rho[1].n, 4); /* the NaN pattern is left out */
    proto_random_stats_result r = {.distribution = AA_SEED_UNIFORM, .count = 5};
    snprintf(r.family, sizeof r.family, "P(1,1,4)");
    preset_pattern("rgss", &r.best_random);
    preset_pattern("rgss", &r.opt_w.pattern);
    preset_pattern("rgss", &r.opt_wp.pattern);
    r.point_metrics = pm;
    j = proto_encode_random_stats_result(&r);
    const json_t *b = json_object_get(j, "point_metrics");
    assert_true(json_is_null(
        json_array_get(json_object_get(json_object_get(b, "patterns"), "oscillation"), 1)));
    assert_int_equal(json_integer_value(json_object_get(b, "spectrum_radius")), 32);
    json_decref(j);
    ROUND_TRIP_ONLY(proto_random_stats_result, proto_encode_random_stats_result,
                    proto_decode_random_stats_result, proto_random_stats_result_free, &r);
    proto_random_stats_result_free(&r);
}

static void test_preset_suggestions(void **state)
{
    (void)state;
    const char *near[PROTO_SUGGEST_MAX];
    size_t n = proto_preset_nearest("flipqaud", near);
    assert_true(n >= 1 && n <= PROTO_SUGGEST_MAX);
    assert_string_equal(near[0], "flipquad");
    n = proto_preset_nearest("RGSS", near); /* case does not count */
    assert_string_equal(near[0], "rgss");
    aa_error err = {0};
    assert_int_equal(proto_unknown_preset(&err, "patterns[1]", "flipqaud"), AA_EINVAL);
    assert_string_equal(err.field, "patterns[1]");
    assert_non_null(strstr(err.message, "unknown preset \"flipqaud\"; did you mean \"flipquad\""));
    assert_int_equal(err.message[strlen(err.message) - 1], '?');
}

/* table3: the spec's defaults (P(16,16,4), 8 seeds, Poisson and jittered, 0.365 px) and
 * refusals naming the field; the result round-trips with the generator, the paper's values and
 * every seed's values, and records the acuity table. */
static void test_table3_codecs(void **state)
{
    (void)state;
    aa_error err = {0};
    proto_table3_spec s;
    json_t *j = parse("{}");
    assert_int_equal(proto_decode_table3_spec(j, &s, &err), AA_OK);
    assert_string_equal(s.family.label, "P(16,16,4)");
    assert_int_equal(s.seeds, 8);
    assert_int_equal(s.count, 1000);
    assert_int_equal(s.distribution_count, 2);
    assert_int_equal(s.distributions[0], AA_SEED_POISSON);
    assert_int_equal(s.distributions[1], AA_SEED_JITTERED);
    assert_true(fabs(s.poisson_radius - 0.365) < 1e-12);
    assert_true(s.common.max_seconds == 60);
    assert_true(proto_table3_spec_seconds(&s) == 8 * 2 * 120);
    proto_table3_spec_free(&s);
    json_decref(j);
    const char *bad[][2] = {{"{\"family\":\"P(4,1+,2)\"}", "family"},
                            {"{\"family\":\"P(16,4,2)\"}", "family"},
                            {"{\"seeds\":0}", "seeds"},
                            {"{\"seeds\":65}", "seeds"},
                            {"{\"poisson_radius\":0.41}", "poisson_radius"},
                            {"{\"distributions\":[\"blue\"]}", "distributions[0]"},
                            {"{\"mode\":\"both\"}", "mode"},
                            {"{\"acuity\":{\"name\":\"naiman-v3\"}}", "acuity.name"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        j = parse(bad[i][0]);
        assert_int_not_equal(proto_decode_table3_spec(j, &s, &err), AA_OK);
        assert_string_equal(err.field, bad[i][1]);
        json_decref(j);
    }

    proto_table3_result r = {.count = 1000, .seed_count = 2, .seeds = {1, 2}, .row_count = 2};
    snprintf(r.family, sizeof r.family, "P(16,16,4)");
    for (int k = 0; k < 2; k++) {
        r.rows[k].distribution = k ? AA_SEED_JITTERED : AA_SEED_POISSON;
        r.rows[k].radius = k ? NAN : 0.365;
        for (int c = 0; c < PROTO_T3_COLS; c++) {
            r.rows[k].mean[c] = 0.2 + 0.1 * c + 0.01 * k;
            r.rows[k].sd[c] = 0.01;
            r.rows[k].paper[c] = k ? NAN : 0.3;
            r.rows[k].values[c][0] = 0.19 + c;
            r.rows[k].values[c][1] = 0.21 + c;
        }
    }
    r.e2 = 0.17;
    r.run = (proto_run_info){"local", 2, false, "naiman", 2};
    preset_pattern("rgss", &r.best);
    j = proto_encode_table3_result(&r);
    const json_t *row0 = json_array_get(json_object_get(j, "rows"), 0);
    assert_string_equal(
        json_string_value(json_object_get(json_object_get(row0, "generator"), "name")),
        "dart-throwing-torus");
    assert_true(json_number_value(json_object_get(json_object_get(row0, "generator"), "radius")) ==
                0.365);
    const json_t *row1 = json_array_get(json_object_get(j, "rows"), 1);
    assert_null(json_object_get(json_object_get(row1, "generator"), "radius"));
    assert_true(json_is_null(
        json_object_get(json_object_get(json_object_get(row1, "columns"), "opt_wp"), "paper")));
    assert_int_equal(json_integer_value(json_object_get(json_object_get(j, "acuity"), "version")),
                     2);
    json_decref(j);
    ROUND_TRIP_ONLY(proto_table3_result, proto_encode_table3_result, proto_decode_table3_result,
                    proto_table3_result_free, &r);
    aa_pattern_free(&r.best);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_optimize_spec),
        cmocka_unit_test(test_sweep_and_stats_spec),
        cmocka_unit_test(test_optimize_result),
        cmocka_unit_test(test_optimize_scene_objective),
        cmocka_unit_test(test_sweep_and_stats_result),
        cmocka_unit_test(test_preset_suggestions),
        cmocka_unit_test(test_point_metrics_codecs),
        cmocka_unit_test(test_budget_and_reproducibility),
        cmocka_unit_test(test_table3_codecs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
