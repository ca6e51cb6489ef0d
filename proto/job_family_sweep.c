#include "job_family_sweep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"
#include "aa_pattern.h"
#include "job_result_util.h"

static const char *const kind_keys[] = {"family", "cost", "seeds_per_config", "distributions",
                                        NULL};

int proto_decode_family_sweep_spec(const json_t *spec, proto_family_sweep_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, PROTO_OPT_MODE | PROTO_OPT_GRID, 60,
                                         &s->common, err);
    if (rc)
        return rc;
    bool have_family = false;
    aa_family fam;
    double cost = NAN;
    rc = proto_spec_family(spec, false, &have_family, &fam, err);
    if (!rc)
        rc = proto_spec_number(spec, "cost", 0.25, AA_ENUMERATE_MAX_COST, &cost, err);
    if (!rc && have_family == !isnan(cost))
        rc = aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and cost");
    if (!rc && have_family) {
        if (!fam.mirrored)
            rc = aa_error_set(err, AA_EINVAL, "family", "the sweep enumerates P(4,1+,n)");
        cost = fam.cost;
        snprintf(s->family, sizeof s->family, "%s", fam.label);
    }
    if (!rc) {
        aa_mirrored_config *list;
        size_t n;
        rc = aa_enumerate_mirrored(cost, &list, &n, err); /* validates the cost ("cost") */
        if (!rc)
            free(list);
    }
    s->cost = cost;
    json_int_t k = 8;
    if (!rc)
        rc = proto_spec_integer(spec, "seeds_per_config", 1, 10000, &k, err);
    s->per_config = (size_t)k;
    if (!rc)
        rc = proto_spec_distributions(spec, s->distributions, &s->distribution_count, err);
    if (rc)
        proto_family_sweep_spec_free(s);
    return rc;
}

void proto_family_sweep_spec_free(proto_family_sweep_spec *s)
{
    proto_optimizer_spec_free(&s->common);
}

static json_t *encode_row(const proto_sweep_row *row)
{
    const aa_mirrored_config *k = &row->config;
    return json_pack("{s:I,s:{s:[IIII],s:[IIII],s:I},s:f,s:o,s:o}", "rank", (json_int_t)row->rank,
                     "config", "corners", (json_int_t)k->corners[0], (json_int_t)k->corners[1],
                     (json_int_t)k->corners[2], (json_int_t)k->corners[3], "edges",
                     (json_int_t)k->edges[0], (json_int_t)k->edges[1], (json_int_t)k->edges[2],
                     (json_int_t)k->edges[3], "interior", (json_int_t)k->interior, "cost",
                     row->cost, "e2", proto_real(row->e2), "best",
                     row->have_best ? proto_encode_pattern(&row->best) : json_null());
}

json_t *proto_encode_family_sweep_result(const proto_family_sweep_result *r)
{
    json_t *list = json_array();
    for (size_t i = 0; list && i < r->ranked_count; i++)
        if (json_array_append_new(list, encode_row(&r->ranked[i]))) {
            json_decref(list);
            list = NULL;
        }
    json_t *o = json_pack("{s:f,s:I,s:I,s:o}", "cost", r->cost, "configurations",
                          (json_int_t)r->configurations, "seeds_per_config",
                          (json_int_t)r->seeds_per_config, "ranked", list);
    if (o && r->ranked_count && r->ranked[0].have_best) {
        json_object_set_new(o, "best", proto_encode_pattern(&r->ranked[0].best));
        json_object_set_new(o, "e2", proto_real(r->ranked[0].e2));
    }
    if (o && !proto_run_info_encode(o, &r->run)) {
        json_decref(o);
        o = NULL;
    }
    return o;
}

static int decode_ints(const json_t *a, int *out, size_t n, const char *field, aa_error *err)
{
    if (!json_is_array(a) || json_array_size(a) != n)
        return aa_error_set(err, AA_EINVAL, field, "must be %zu integers", n);
    for (size_t i = 0; i < n; i++) {
        if (!json_is_integer(json_array_get(a, i)))
            return aa_error_set(err, AA_EINVAL, field, "must be %zu integers", n);
        out[i] = (int)json_integer_value(json_array_get(a, i));
    }
    return AA_OK;
}

static int decode_row(const json_t *j, proto_sweep_row *row, aa_error *err)
{
    static const char *const keys[] = {"rank", "config", "cost", "e2", "best", NULL};
    static const char *const config_keys[] = {"corners", "edges", "interior", NULL};
    const json_t *config = json_object_get(j, "config");
    long long rank = 0, interior = 0;
    int rc = proto_check_keys(j, keys, err, "");
    if (!rc)
        rc = proto_result_integer(j, "rank", &rank, err);
    if (!rc && !json_is_object(config))
        rc = aa_error_set(err, AA_EINVAL, "config", "must be an object");
    if (!rc)
        rc = proto_check_keys(config, config_keys, err, "config");
    if (!rc)
        rc = decode_ints(json_object_get(config, "corners"), row->config.corners, 4,
                         "config.corners", err);
    if (!rc)
        rc = decode_ints(json_object_get(config, "edges"), row->config.edges, 4, "config.edges",
                         err);
    if (!rc)
        rc = proto_result_integer(config, "interior", &interior, err);
    if (!rc)
        rc = proto_result_real(j, "cost", &row->cost, err);
    if (!rc)
        rc = proto_result_real(j, "e2", &row->e2, err);
    if (!rc)
        rc = proto_result_pattern(j, "best", true, &row->best, &row->have_best, err);
    row->rank = (long)rank;
    row->config.interior = (int)interior;
    return rc;
}

int proto_decode_family_sweep_result(const json_t *j, proto_family_sweep_result *r, aa_error *err)
{
    static const char *const keys[] = {
        "cost",     "configurations", "seeds_per_config", "ranked", "best", "e2",
        "executor", "shards",         "reproducible",     "acuity", NULL};
    memset(r, 0, sizeof *r);
    long long configurations = 0, per_config = 0;
    const json_t *ranked = json_object_get(j, "ranked");
    int rc = proto_check_keys(j, keys, err, "");
    if (!rc)
        rc = proto_result_real(j, "cost", &r->cost, err);
    if (!rc)
        rc = proto_result_integer(j, "configurations", &configurations, err);
    if (!rc)
        rc = proto_result_integer(j, "seeds_per_config", &per_config, err);
    if (!rc && !json_is_array(ranked))
        rc = aa_error_set(err, AA_EINVAL, "ranked", "must be an array");
    r->configurations = (long)configurations;
    r->seeds_per_config = (long)per_config;
    size_t n = json_array_size(ranked);
    if (!rc && n && !(r->ranked = calloc(n, sizeof *r->ranked)))
        rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t i = 0; !rc && i < n; i++) {
        rc = decode_row(json_array_get(ranked, i), &r->ranked[i], err);
        r->ranked_count = i + 1;
        if (rc) {
            char at[32];
            snprintf(at, sizeof at, "ranked[%zu]", i);
            proto_prefix_error(err, at);
        }
    }
    if (!rc)
        rc = proto_run_info_decode(j, &r->run, err);
    if (rc)
        proto_family_sweep_result_free(r);
    return rc;
}

void proto_family_sweep_result_free(proto_family_sweep_result *r)
{
    for (size_t i = 0; i < r->ranked_count; i++)
        aa_pattern_free(&r->ranked[i].best);
    free(r->ranked);
    r->ranked = NULL;
    r->ranked_count = 0;
}
