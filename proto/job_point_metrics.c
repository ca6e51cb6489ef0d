#include "job_point_metrics.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"
#include "job_result_util.h"

static int names_error(aa_error *err, const char *field, const char *what)
{
    char list[320] = "";
    for (int m = 0; m < AA_PM_COUNT; m++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", m ? ", " : "",
                 aa_point_metric_name((aa_point_metric)m));
    return aa_error_set(err, AA_EINVAL, field, "%s: %.150s", what, list);
}

int proto_spec_point_metrics(const json_t *spec, const aa_family *family, size_t patterns,
                             proto_point_metrics_spec *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    const json_t *list = json_object_get(spec, "metrics");
    if (!list)
        return AA_OK;
    if (!json_is_array(list) || !json_array_size(list))
        return names_error(err, "metrics", "must be a non-empty array of figure names");
    if (json_array_size(list) > AA_PM_COUNT)
        return aa_error_set(err, AA_EINVAL, "metrics", "at most %d names (each once)", AA_PM_COUNT);
    size_t i;
    const json_t *v;
    json_array_foreach(list, i, v)
    {
        char field[32];
        snprintf(field, sizeof field, "metrics[%zu]", i);
        aa_point_metric m;
        if (!json_is_string(v) || aa_point_metric_parse(json_string_value(v), &m))
            return names_error(err, field, "must be one of");
        for (size_t j = 0; j < out->count; j++)
            if (out->which[j] == m)
                return aa_error_set(err, AA_EINVAL, field, "%s is already listed",
                                    aa_point_metric_name(m));
        out->which[out->count++] = m;
    }
    long points = lround(family->cost * family->tile * family->tile);
    if (points < 2 || points > AA_POINT_SET_MAX)
        return aa_error_set(err, AA_EINVAL, "metrics",
                            "point-set figures need 2 to %d tile points; %s has %ld",
                            AA_POINT_SET_MAX, family->label, points);
    if (patterns > PROTO_POINT_METRICS_MAX_PATTERNS)
        return aa_error_set(err, AA_EINVAL, "metrics",
                            "figures are kept per pattern: at most %d random patterns per job "
                            "with metrics, this spec draws %zu",
                            PROTO_POINT_METRICS_MAX_PATTERNS, patterns);
    return AA_OK;
}

int proto_point_metrics_init(proto_point_metrics *pm, const proto_point_metrics_spec *spec,
                             size_t capacity, aa_error *err)
{
    memset(pm, 0, sizeof *pm);
    pm->spec = *spec;
    pm->capacity = capacity;
    size_t cells = (capacity ? capacity : 1) * (spec->count + 1);
    pm->e2 = malloc(cells * sizeof *pm->e2);
    if (!pm->e2)
        return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    pm->values = pm->e2 + capacity;
    for (int m = 0; m < AA_PM_COUNT; m++)
        pm->rho[m] = (aa_spearman_result){0, NAN, NAN};
    return AA_OK;
}

void proto_point_metrics_free(proto_point_metrics *pm)
{
    free(pm->e2);
    pm->e2 = pm->values = NULL;
    pm->n = pm->capacity = 0;
}

json_t *proto_point_metrics_columns(const proto_point_metrics *pm)
{
    json_t *o = json_object();
    if (!o || json_object_set_new(o, "e2", proto_real_array(pm->e2, pm->n))) {
        json_decref(o);
        return NULL;
    }
    for (size_t k = 0; k < pm->spec.count; k++)
        if (json_object_set_new(o, aa_point_metric_name(pm->spec.which[k]),
                                proto_real_array(pm->values + k * pm->capacity, pm->n))) {
            json_decref(o);
            return NULL;
        }
    return o;
}

/* A column's numbers (null: NaN) into out[0..count). */
static int read_column(const json_t *a, size_t count, double *out, const char *field,
                       const char *name, aa_error *err)
{
    if (json_array_size(a) != count)
        return aa_error_set(err, AA_EINVAL, field, "%s: expected %zu values", name, count);
    for (size_t i = 0; i < count; i++) {
        const json_t *v = json_array_get(a, i);
        if (!json_is_number(v) && !json_is_null(v))
            return aa_error_set(err, AA_EINVAL, field, "%s[%zu]: must be a number or null", name,
                                i);
        out[i] = json_is_number(v) ? json_number_value(v) : NAN;
    }
    return AA_OK;
}

int proto_point_metrics_append(proto_point_metrics *pm, const json_t *columns, const char *field,
                               aa_error *err)
{
    const json_t *e2 = json_object_get(columns, "e2");
    size_t count = json_array_size(e2);
    if (!json_is_object(columns) || !json_is_array(e2) ||
        json_object_size(columns) != pm->spec.count + 1)
        return aa_error_set(err, AA_EINVAL, field,
                            "expected {\"e2\": [...]} and a list per figure");
    if (count > pm->capacity - pm->n)
        return aa_error_set(err, AA_EINVAL, field, "more than %zu patterns", pm->capacity);
    int rc = read_column(e2, count, pm->e2 + pm->n, field, "e2", err);
    for (size_t k = 0; !rc && k < pm->spec.count; k++) {
        const char *name = aa_point_metric_name(pm->spec.which[k]);
        rc = read_column(json_object_get(columns, name), count,
                         pm->values + k * pm->capacity + pm->n, field, name, err);
    }
    if (!rc)
        pm->n += count;
    return rc;
}

int proto_point_metrics_visit(void *user, size_t i, const aa_pattern *p, double e2, aa_error *err)
{
    proto_point_metrics *pm = user;
    double v[AA_PM_COUNT];
    if (i >= pm->capacity)
        return aa_error_set(err, AA_EINVAL, "metrics", "more than %zu patterns", pm->capacity);
    int rc = aa_point_metrics_of(p, pm->spec.which, pm->spec.count, v, err);
    if (rc)
        return rc;
    pm->e2[i] = e2;
    for (size_t k = 0; k < pm->spec.count; k++)
        pm->values[k * pm->capacity + i] = v[k];
    pm->n = i + 1;
    return AA_OK;
}

int proto_point_metrics_rank(proto_point_metrics *pm, aa_error *err)
{
    for (size_t k = 0; k < pm->spec.count; k++)
        if (aa_spearman_of(pm->values + k * pm->capacity, pm->e2, pm->n, &pm->rho[k]))
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
    return AA_OK;
}

json_t *proto_encode_point_metrics(const proto_point_metrics *pm)
{
    json_t *names = json_array(), *rho = json_array();
    for (size_t k = 0; names && rho && k < pm->spec.count; k++) {
        const char *name = aa_point_metric_name(pm->spec.which[k]);
        json_array_append_new(names, json_string(name));
        json_array_append_new(rho,
                              json_pack("{s:s,s:o,s:I,s:o}", "metric", name, "rho",
                                        proto_real(pm->rho[k].rho), "n", (json_int_t)pm->rho[k].n,
                                        "p_value", proto_real(pm->rho[k].p_value)));
    }
    json_t *cols = proto_point_metrics_columns(pm);
    if (!names || !rho || !cols || json_array_size(rho) != pm->spec.count) {
        json_decref(names);
        json_decref(rho);
        json_decref(cols);
        return NULL;
    }
    return json_pack("{s:o,s:i,s:o,s:o}", "metrics", names, "spectrum_radius",
                     AA_PM_SPECTRUM_RADIUS, "spearman", rho, "patterns", cols);
}

int proto_decode_point_metrics(const json_t *j, const char *field, proto_point_metrics *pm,
                               aa_error *err)
{
    static const char *const keys[] = {"metrics", "spectrum_radius", "spearman", "patterns", NULL};
    memset(pm, 0, sizeof *pm);
    if (!json_is_object(j))
        return aa_error_set(err, AA_EINVAL, field, "must be an object");
    int rc = proto_check_keys(j, keys, err, field);
    proto_point_metrics_spec spec;
    memset(&spec, 0, sizeof spec);
    const json_t *names = json_object_get(j, "metrics"), *rho = json_object_get(j, "spearman");
    const json_t *cols = json_object_get(j, "patterns");
    if (!rc && (!json_is_array(names) || json_array_size(names) > AA_PM_COUNT ||
                !json_is_array(rho) || json_array_size(rho) != json_array_size(names)))
        rc = aa_error_set(err, AA_EINVAL, field,
                          "expected \"metrics\" and a \"spearman\" entry "
                          "for each");
    for (size_t k = 0; !rc && k < json_array_size(names); k++)
        if (aa_point_metric_parse(json_string_value(json_array_get(names, k)), &spec.which[k]))
            rc = aa_error_set(err, AA_EINVAL, field, "metrics[%zu]: unknown figure", k);
        else
            spec.count++;
    if (!rc)
        rc = proto_point_metrics_init(pm, &spec, json_array_size(json_object_get(cols, "e2")), err);
    if (!rc)
        rc = proto_point_metrics_append(pm, cols, field, err);
    for (size_t k = 0; !rc && k < spec.count; k++) {
        const json_t *r = json_array_get(rho, k);
        long long n = 0;
        rc = proto_result_real(r, "rho", &pm->rho[k].rho, err);
        if (!rc)
            rc = proto_result_real(r, "p_value", &pm->rho[k].p_value, err);
        if (!rc)
            rc = proto_result_integer(r, "n", &n, err);
        pm->rho[k].n = (size_t)n;
        const char *metric = json_string_value(json_object_get(r, "metric"));
        if (!rc && (!metric || strcmp(metric, aa_point_metric_name(spec.which[k]))))
            rc = aa_error_set(err, AA_EINVAL, field, "spearman[%zu]: expected metric %s", k,
                              aa_point_metric_name(spec.which[k]));
    }
    if (rc)
        proto_point_metrics_free(pm);
    return rc;
}
