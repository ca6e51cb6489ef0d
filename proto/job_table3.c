#include "job_table3.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "codec_internal.h"
#include "job_result_util.h"

const char *const proto_table3_columns[PROTO_T3_COLS] = {"min", "avg", "max", "opt_w", "opt_wp"};

static const char *const kind_keys[] = {"family",         "seeds",   "count", "distributions",
                                        "poisson_radius", "metrics", NULL};

int proto_decode_table3_spec(const json_t *spec, proto_table3_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, 0, 60, &s->common, err);
    if (rc)
        return rc;
    bool have_family = false;
    rc = proto_spec_family(spec, false, &have_family, &s->family, err);
    if (!rc && !have_family)
        rc = aa_family_parse("P(16,16,4)", &s->family, err);
    if (!rc && (s->family.mirrored || s->family.kernel_size < s->family.tile))
        rc = aa_error_set(err, AA_EINVAL, "family",
                          "Table 3 takes a tiled family whose kernels read the whole tile "
                          "(r >= s), e.g. P(16,16,4)");
    json_int_t seeds = 8, count = 1000;
    if (!rc)
        rc = proto_spec_integer(spec, "seeds", 1, PROTO_TABLE3_MAX_SEEDS, &seeds, err);
    if (!rc)
        rc = proto_spec_integer(spec, "count", 1, 1000000, &count, err);
    s->seeds = (size_t)seeds;
    s->count = (size_t)count;
    if (!rc)
        rc = proto_spec_distributions(spec, s->distributions, &s->distribution_count, err);
    if (!rc && s->distribution_count == 0) {
        s->distributions[0] = AA_SEED_POISSON;
        s->distributions[1] = AA_SEED_JITTERED;
        s->distribution_count = 2;
    }
    if (!rc)
        rc = proto_spec_poisson_radius(spec, s->family.cost, &s->poisson_radius, err);
    if (!rc)
        rc = proto_spec_point_metrics(spec, &s->family, s->seeds * s->count * s->distribution_count,
                                      &s->metrics, err);
    if (rc)
        proto_table3_spec_free(s);
    return rc;
}

void proto_table3_spec_free(proto_table3_spec *s)
{
    proto_optimizer_spec_free(&s->common);
}

double proto_table3_spec_seconds(const proto_table3_spec *s)
{
    if (s->common.max_seconds <= 0)
        return 0;
    aa_table3_params tp;
    aa_table3_params_default(&tp);
    return (double)(s->seeds * s->distribution_count) * (s->common.max_seconds + tp.opt_w_seconds);
}

static json_t *encode_row(const proto_table3_row *row, const proto_table3_result *r)
{
    json_t *gen = json_pack("{s:s}", "name", aa_seed_generator_name(row->distribution));
    if (gen && row->distribution == AA_SEED_POISSON)
        json_object_set_new(gen, "radius", proto_real(row->radius));
    json_t *cols = json_object(), *per_seed = json_array();
    for (int c = 0; cols && c < PROTO_T3_COLS; c++)
        json_object_set_new(cols, proto_table3_columns[c],
                            json_pack("{s:o,s:o,s:o}", "mean", proto_real(row->mean[c]), "sd",
                                      proto_real(row->sd[c]), "paper", proto_real(row->paper[c])));
    for (size_t s = 0; per_seed && s < r->seed_count; s++) {
        json_t *o = json_pack("{s:I}", "rng_seed", (json_int_t)r->seeds[s]);
        for (int c = 0; o && c < PROTO_T3_COLS; c++)
            json_object_set_new(o, proto_table3_columns[c], proto_real(row->values[c][s]));
        json_array_append_new(per_seed, o);
    }
    json_t *o =
        json_pack("{s:s,s:o,s:o,s:o}", "distribution", aa_seed_distribution_name(row->distribution),
                  "generator", gen, "columns", cols, "per_seed", per_seed);
    if (o && row->point_metrics.spec.count &&
        json_object_set_new(o, "point_metrics", proto_encode_point_metrics(&row->point_metrics))) {
        json_decref(o);
        o = NULL;
    }
    return o;
}

json_t *proto_encode_table3_result(const proto_table3_result *r)
{
    json_t *seeds = json_array(), *rows = json_array();
    for (size_t s = 0; seeds && s < r->seed_count; s++)
        json_array_append_new(seeds, json_integer((json_int_t)r->seeds[s]));
    for (size_t i = 0; rows && i < r->row_count; i++)
        json_array_append_new(rows, encode_row(&r->rows[i], r));
    json_t *o = json_pack("{s:s,s:I,s:o,s:o,s:o,s:o}", "family", r->family, "count",
                          (json_int_t)r->count, "seeds", seeds, "rows", rows, "best",
                          proto_encode_pattern(&r->best), "e2", proto_real(r->e2));
    if (o && !proto_run_info_encode(o, &r->run)) {
        json_decref(o);
        o = NULL;
    }
    return o;
}

static int decode_row(const json_t *j, const char *field, proto_table3_row *row,
                      const proto_table3_result *r, aa_error *err)
{
    static const char *const keys[] = {"distribution", "generator",     "columns",
                                       "per_seed",     "point_metrics", NULL};
    static const char *const stat_keys[] = {"mean", "sd", "paper", NULL};
    static const char *const column_keys[] = {"min", "avg", "max", "opt_w", "opt_wp", NULL};
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an object");
    int rc = proto_check_keys(j, keys, err, field);
    if (!rc && aa_seed_distribution_parse(json_string_value(json_object_get(j, "distribution")),
                                          &row->distribution))
        rc = aa_error_set(err, AA_EINVAL, "distribution", "unknown distribution");
    const json_t *gen = json_object_get(j, "generator");
    row->radius = NAN;
    if (!rc && (!json_is_object(gen) || !json_is_string(json_object_get(gen, "name"))))
        rc = aa_error_set(err, AA_EINVAL, "generator", "expected {\"name\",\"radius\"?}");
    if (!rc && json_object_get(gen, "radius"))
        rc = proto_result_real(gen, "radius", &row->radius, err);
    const json_t *cols = json_object_get(j, "columns");
    const json_t *per_seed = json_object_get(j, "per_seed");
    if (!rc && !json_is_object(cols))
        rc = aa_error_set(err, AA_EINVAL, "columns", "must be an object");
    if (!rc)
        rc = proto_check_keys(cols, column_keys, err, "columns");
    for (int c = 0; !rc && c < PROTO_T3_COLS; c++) {
        const json_t *st = json_object_get(cols, proto_table3_columns[c]);
        if (!json_is_object(st))
            rc = aa_error_set(err, AA_EINVAL, "columns", "expected every column");
        if (!rc)
            rc = proto_check_keys(st, stat_keys, err, "columns");
        if (!rc)
            rc = proto_result_real(st, "mean", &row->mean[c], err);
        if (!rc)
            rc = proto_result_real(st, "sd", &row->sd[c], err);
        if (!rc)
            rc = proto_result_real(st, "paper", &row->paper[c], err);
    }
    if (!rc && (!json_is_array(per_seed) || json_array_size(per_seed) != r->seed_count))
        rc = aa_error_set(err, AA_EINVAL, "per_seed", "expected one entry per seed");
    for (size_t s = 0; !rc && s < r->seed_count; s++) {
        const json_t *o = json_array_get(per_seed, s);
        for (int c = 0; !rc && c < PROTO_T3_COLS; c++)
            rc = proto_result_real(o, proto_table3_columns[c], &row->values[c][s], err);
    }
    const json_t *pm = json_object_get(j, "point_metrics");
    if (!rc && pm)
        rc = proto_decode_point_metrics(pm, "point_metrics", &row->point_metrics, err);
    return rc ? proto_prefix_error(err, field) : AA_OK;
}

int proto_decode_table3_result(const json_t *j, proto_table3_result *r, aa_error *err)
{
    static const char *const keys[] = {"family",   "count",  "seeds",        "rows",   "best", "e2",
                                       "executor", "shards", "reproducible", "acuity", NULL};
    memset(r, 0, sizeof *r);
    const char *family = json_string_value(json_object_get(j, "family"));
    const json_t *seeds = json_object_get(j, "seeds"), *rows = json_object_get(j, "rows");
    long long count = 0;
    int rc = proto_check_keys(j, keys, err, "");
    if (!rc && !family)
        rc = aa_error_set(err, AA_EINVAL, "family", "must be a string");
    if (!rc)
        rc = proto_result_integer(j, "count", &count, err);
    if (!rc && (!json_is_array(seeds) || json_array_size(seeds) < 1 ||
                json_array_size(seeds) > PROTO_TABLE3_MAX_SEEDS))
        rc = aa_error_set(err, AA_EINVAL, "seeds", "must be an array of 1..%d seeds",
                          PROTO_TABLE3_MAX_SEEDS);
    for (size_t s = 0; !rc && s < json_array_size(seeds); s++) {
        const json_t *v = json_array_get(seeds, s);
        if (!json_is_integer(v) || json_integer_value(v) < 0)
            rc = aa_error_set(err, AA_EINVAL, "seeds", "must be non-negative integers");
        else
            r->seeds[r->seed_count++] = (uint64_t)json_integer_value(v);
    }
    if (!rc && (!json_is_array(rows) || json_array_size(rows) < 1 ||
                json_array_size(rows) > PROTO_MAX_DISTRIBUTIONS))
        rc = aa_error_set(err, AA_EINVAL, "rows", "must be an array of 1..%d rows",
                          PROTO_MAX_DISTRIBUTIONS);
    for (size_t i = 0; !rc && i < json_array_size(rows); i++) {
        char field[32];
        snprintf(field, sizeof field, "rows[%zu]", i);
        rc = decode_row(json_array_get(rows, i), field, &r->rows[i], r, err);
        r->row_count = i + 1;
    }
    if (!rc)
        rc = proto_result_pattern(j, "best", false, &r->best, NULL, err);
    if (!rc)
        rc = proto_result_real(j, "e2", &r->e2, err);
    if (!rc)
        rc = proto_run_info_decode(j, &r->run, err);
    if (family)
        snprintf(r->family, sizeof r->family, "%s", family);
    r->count = (long)count;
    if (rc)
        proto_table3_result_free(r);
    return rc;
}

void proto_table3_result_free(proto_table3_result *r)
{
    aa_pattern_free(&r->best);
    for (size_t i = 0; i < PROTO_MAX_DISTRIBUTIONS; i++)
        proto_point_metrics_free(&r->rows[i].point_metrics);
}
