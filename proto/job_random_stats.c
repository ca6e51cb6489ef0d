#include "job_random_stats.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codec_internal.h"
#include "job_result_util.h"

static const char *const kind_keys[] = {"family",         "count",   "distribution",
                                        "poisson_radius", "metrics", NULL};

int proto_decode_random_stats_spec(const json_t *spec, proto_random_stats_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, 0, 30, &s->common, err);
    if (rc)
        return rc;
    rc = proto_spec_family(spec, true, NULL, &s->family, err);
    /* A random pattern must give every pixel's kernel a sample; when a kernel reads only part
     * of the tile (r < s) random positions can leave it empty, and the job would fail late. */
    if (!rc && !s->family.mirrored && s->family.kernel_size < s->family.tile)
        rc = aa_error_set(err, AA_EINVAL, "family",
                          "random patterns of %s can leave a pixel's kernel without samples "
                          "(r < s): use r >= s, e.g. P(%d,%d,n)",
                          s->family.label, s->family.tile * s->family.tile,
                          s->family.tile * s->family.tile);
    json_int_t n = 1000;
    if (!rc)
        rc = proto_spec_integer(spec, "count", 1, 1000000, &n, err);
    s->count = (size_t)n;
    const char *dist = "uniform";
    if (!rc)
        rc = proto_spec_string(spec, "distribution", &dist, err);
    if (!rc && aa_seed_distribution_parse(dist, &s->distribution))
        rc = aa_error_set(err, AA_EINVAL, "distribution",
                          "must be uniform, jittered, n-rooks, poisson or lloyd");
    /* The family's samples per pixel. */
    if (!rc)
        rc = proto_spec_poisson_radius(spec, s->family.mirrored ? 1 : s->family.cost,
                                       &s->poisson_radius, err);
    if (!rc)
        rc = proto_spec_point_metrics(spec, &s->family, s->count, &s->metrics, err);
    if (rc)
        proto_random_stats_spec_free(s);
    return rc;
}

void proto_random_stats_spec_free(proto_random_stats_spec *s)
{
    proto_optimizer_spec_free(&s->common);
}

static json_t *encode_stage(const proto_stats_stage *s)
{
    return json_pack("{s:o,s:o,s:s}", "e2", proto_real(s->e2), "pattern",
                     proto_encode_pattern(&s->pattern), "method",
                     aa_optimize_method_name(s->method));
}

json_t *proto_encode_random_stats_result(const proto_random_stats_result *r)
{
    json_t *o = json_pack("{s:s,s:s,s:I,s:{s:o,s:o,s:o},s:o,s:o,s:o,s:o,s:o}", "family", r->family,
                          "distribution", aa_seed_distribution_name(r->distribution), "count",
                          (json_int_t)r->count, "random", "min", proto_real(r->min), "avg",
                          proto_real(r->avg), "max", proto_real(r->max), "best_random",
                          proto_encode_pattern(&r->best_random), "opt_w", encode_stage(&r->opt_w),
                          "opt_wp", encode_stage(&r->opt_wp), "best",
                          proto_encode_pattern(&r->opt_wp.pattern), "e2", proto_real(r->opt_wp.e2));
    json_t *gen = o ? json_pack("{s:s}", "name", aa_seed_generator_name(r->distribution)) : NULL;
    if (gen && r->distribution == AA_SEED_POISSON && !isnan(r->radius))
        json_object_set_new(gen, "radius", proto_real(r->radius));
    if (o && gen)
        json_object_set_new(o, "generator", gen);
    if (o && r->point_metrics.spec.count &&
        json_object_set_new(o, "point_metrics", proto_encode_point_metrics(&r->point_metrics))) {
        json_decref(o);
        return NULL;
    }
    if (o && !proto_run_info_encode(o, &r->run)) {
        json_decref(o);
        o = NULL;
    }
    return o;
}

static int decode_stage(const json_t *j, const char *field, proto_stats_stage *s, aa_error *err)
{
    static const char *const keys[] = {"e2", "pattern", "method", NULL};
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an object");
    int rc = proto_check_keys(j, keys, err, field);
    if (!rc)
        rc = proto_result_real(j, "e2", &s->e2, err);
    if (!rc)
        rc = proto_result_pattern(j, "pattern", false, &s->pattern, NULL, err);
    if (!rc)
        rc = proto_result_method(j, "method", &s->method, err);
    return rc ? proto_prefix_error(err, field) : AA_OK;
}

int proto_decode_random_stats_result(const json_t *j, proto_random_stats_result *r, aa_error *err)
{
    static const char *const keys[] = {
        "family",      "distribution", "count",         "random",
        "best_random", "opt_w",        "opt_wp",        "best",
        "e2",          "executor",     "shards",        "reproducible",
        "acuity",      "generator",    "point_metrics", NULL};
    static const char *const random_keys[] = {"min", "avg", "max", NULL};
    memset(r, 0, sizeof *r);
    const json_t *random = json_object_get(j, "random");
    const char *family = json_string_value(json_object_get(j, "family"));
    long long count = 0;
    int rc = proto_check_keys(j, keys, err, "");
    if (!rc && !family)
        rc = aa_error_set(err, AA_EINVAL, "family", "must be a string");
    if (!rc && aa_seed_distribution_parse(json_string_value(json_object_get(j, "distribution")),
                                          &r->distribution))
        rc = aa_error_set(err, AA_EINVAL, "distribution", "unknown distribution");
    if (!rc)
        rc = proto_result_integer(j, "count", &count, err);
    if (!rc && !json_is_object(random))
        rc = aa_error_set(err, AA_EINVAL, "random", "must be an object");
    if (!rc)
        rc = proto_check_keys(random, random_keys, err, "random");
    if (!rc)
        rc = proto_result_real(random, "min", &r->min, err);
    if (!rc)
        rc = proto_result_real(random, "avg", &r->avg, err);
    if (!rc)
        rc = proto_result_real(random, "max", &r->max, err);
    if (!rc)
        rc = proto_result_pattern(j, "best_random", false, &r->best_random, NULL, err);
    if (!rc)
        rc = decode_stage(json_object_get(j, "opt_w"), "opt_w", &r->opt_w, err);
    if (!rc)
        rc = decode_stage(json_object_get(j, "opt_wp"), "opt_wp", &r->opt_wp, err);
    r->radius = NAN;
    const json_t *gen = json_object_get(j, "generator");
    if (!rc && gen && (!json_is_object(gen) || !json_is_string(json_object_get(gen, "name"))))
        rc = aa_error_set(err, AA_EINVAL, "generator", "expected {\"name\",\"radius\"?}");
    if (!rc && json_object_get(gen, "radius"))
        rc = proto_result_real(gen, "radius", &r->radius, err);
    if (!rc)
        rc = proto_run_info_decode(j, &r->run, err);
    const json_t *pm = json_object_get(j, "point_metrics");
    if (!rc && pm)
        rc = proto_decode_point_metrics(pm, "point_metrics", &r->point_metrics, err);
    if (family)
        snprintf(r->family, sizeof r->family, "%s", family);
    r->count = (long)count;
    if (rc)
        proto_random_stats_result_free(r);
    return rc;
}

void proto_random_stats_result_free(proto_random_stats_result *r)
{
    aa_pattern_free(&r->best_random);
    aa_pattern_free(&r->opt_w.pattern);
    aa_pattern_free(&r->opt_wp.pattern);
    proto_point_metrics_free(&r->point_metrics);
}
