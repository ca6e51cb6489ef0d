/* Filter and acuity wire forms, angle lists. */
#define _POSIX_C_SOURCE 200809L
#include "codec_internal.h"

#include <assert.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool is_mitchell_family(const char *name)
{
    return !strcmp(name, "mitchell") || !strcmp(name, "catmull-rom") || !strcmp(name, "bspline") ||
           !strcmp(name, "notch");
}

/* Which numeric parameters a named filter takes (others are rejected as not applicable). */
static bool filter_takes(const char *name, const char *param)
{
    if (!strcmp(param, "radius"))
        return strcmp(name, "lanczos") != 0;
    if (!strcmp(param, "B") || !strcmp(param, "C"))
        return is_mitchell_family(name); /* fixed for the named members: checked below */
    if (!strcmp(param, "sigma"))
        return !strcmp(name, "gaussian");
    if (!strcmp(param, "a"))
        return !strcmp(name, "lanczos");
    return false;
}

/* Building a filter's Chebyshev table costs tens of microseconds; the named filters with their
 * default parameters are built once (read-only afterwards) and copied out. */
#define NAMED_FILTER_MAX 16
static aa_filter named_filters[NAMED_FILTER_MAX];
static size_t named_filter_count;
static pthread_once_t named_filters_once = PTHREAD_ONCE_INIT;

static void build_named_filters(void)
{
    for (size_t i = 0; aa_filter_names[i] && named_filter_count < NAMED_FILTER_MAX; i++)
        if (aa_filter_by_name(&named_filters[named_filter_count], aa_filter_names[i], NULL, NULL) ==
            AA_OK)
            named_filter_count++;
}

static bool copy_named_filter(const char *name, aa_filter *out)
{
    pthread_once(&named_filters_once, build_named_filters);
    for (size_t i = 0; i < named_filter_count; i++) {
        if (!strcmp(named_filters[i].name, name)) {
            memcpy(out, &named_filters[i], sizeof *out);
            return true;
        }
    }
    return false;
}

int proto_decode_filter(const json_t *j, aa_filter *out, const char *field_prefix, aa_error *err)
{
    const char *prefix = field_prefix ? field_prefix : "";
    if (!j || json_is_null(j)) {
        if (!copy_named_filter("mitchell", out))
            aa_filter_default(out);
        return AA_OK;
    }
    if (!json_is_object(j))
        return proto_fail(err, AA_EINVAL, prefix, "", "a filter is an object {\"name\": ...}");
    /* cdf_error_bound and default are informational (GET /v1/filters) and ignored. */
    static const char *const keys[] = {
        "name", "B", "C", "radius", "sigma", "a", "cdf_error_bound", "default", NULL};
    int rc = proto_check_keys(j, keys, err, prefix);
    if (rc)
        return rc;
    const json_t *n = json_object_get(j, "name");
    const char *name = "mitchell";
    if (n) {
        if (!json_is_string(n))
            return proto_fail(err, AA_EINVAL, prefix, "name", "must be a filter name");
        name = json_string_value(n);
        bool known = false;
        for (size_t i = 0; aa_filter_names[i] && !known; i++)
            known = !strcmp(aa_filter_names[i], name);
        if (!known)
            return proto_fail(err, AA_EINVAL, prefix, "name", "unknown filter");
    }
    aa_filter_params p = aa_filter_params_default();
    bool defaults = true;
    struct {
        const char *key;
        double *dst;
    } params[] = {
        {"B", &p.B}, {"C", &p.C}, {"radius", &p.radius}, {"sigma", &p.sigma}, {"a", &p.a}};
    for (size_t i = 0; i < sizeof params / sizeof params[0]; i++) {
        const json_t *v = json_object_get(j, params[i].key);
        if (!v)
            continue;
        if (!filter_takes(name, params[i].key))
            return proto_fail(err, AA_EINVAL, prefix, params[i].key,
                              "not a parameter of this filter");
        if ((rc = proto_number(v, params[i].dst, err, prefix, params[i].key)))
            return rc;
        defaults = false;
    }
    /* catmull-rom, bspline and notch fix B and C (the encoder writes them): only the fixed
     * values are accepted, other values need "mitchell". */
    static const struct {
        const char *name;
        double B, C;
    } fixed[] = {{"catmull-rom", 0, 0.5}, {"bspline", 1, 0}, {"notch", 1.5, -0.25}};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++) {
        if (strcmp(name, fixed[i].name))
            continue;
        if (!isnan(p.B) && fabs(p.B - fixed[i].B) > 1e-12)
            return proto_fail(err, AA_EINVAL, prefix, "B",
                              "this filter fixes B; use name \"mitchell\" for other values");
        if (!isnan(p.C) && fabs(p.C - fixed[i].C) > 1e-12)
            return proto_fail(err, AA_EINVAL, prefix, "C",
                              "this filter fixes C; use name \"mitchell\" for other values");
        p.B = p.C = NAN;
    }
    if (isnan(p.B) && isnan(p.C) && isnan(p.radius) && isnan(p.sigma) && isnan(p.a))
        defaults = true;
    if (defaults && copy_named_filter(name, out))
        return AA_OK;
    rc = aa_filter_by_name(out, name, &p, err);
    if (rc)
        proto_prefix_error(err, prefix);
    return rc;
}

int proto_decode_acuity(const json_t *j, aa_acuity *out, const char *field_prefix, aa_error *err)
{
    const char *prefix = field_prefix ? field_prefix : "";
    if (!j || json_is_null(j)) {
        aa_acuity_naiman(out);
        return AA_OK;
    }
    if (!json_is_object(j))
        return proto_fail(err, AA_EINVAL, prefix, "",
                          "an acuity table is {\"name\": ...} or {\"knots\": [[deg, W], ...]}");
    static const char *const keys[] = {"name", "knots", NULL};
    int rc = proto_check_keys(j, keys, err, prefix);
    if (rc)
        return rc;
    const json_t *name = json_object_get(j, "name");
    const json_t *knots = json_object_get(j, "knots");
    if (name && knots)
        return proto_fail(err, AA_EINVAL, prefix, "knots", "give either name or knots");
    if (name) {
        if (!json_is_string(name))
            return proto_fail(err, AA_EINVAL, prefix, "name", "must be a table name");
        rc = aa_acuity_by_name(out, json_string_value(name), err);
        if (rc)
            proto_prefix_error(err, prefix);
        return rc;
    }
    if (!knots)
        return proto_fail(err, AA_EINVAL, prefix, "", "needs name or knots");
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "knots");
    if (!json_is_array(knots))
        return aa_error_set(err, AA_EINVAL, field, "must be an array of [deg, W] pairs");
    size_t n = json_array_size(knots);
    if (n == 0)
        return aa_error_set(err, AA_EINVAL, field, "needs at least one knot");
    if (n > AA_ACUITY_MAX_KNOTS)
        return aa_error_set(err, AA_ERANGE, field, "at most %d knots", AA_ACUITY_MAX_KNOTS);
    double(*k)[2] = malloc(n * sizeof *k);
    if (!k)
        return aa_error_set(err, AA_ENOMEM, field, "out of memory");
    for (size_t i = 0; i < n && !rc; i++) {
        const json_t *pair = json_array_get(knots, i);
        char kfield[PROTO_FIELD_MAX], idx[32];
        snprintf(idx, sizeof idx, "[%zu]", i);
        proto_join_field(kfield, sizeof kfield, field, idx);
        if (!json_is_array(pair) || json_array_size(pair) != 2) {
            rc = aa_error_set(err, AA_EINVAL, kfield, "a knot is [deg, W]");
            break;
        }
        rc = proto_number(json_array_get(pair, 0), &k[i][0], err, kfield, "[0]");
        if (!rc)
            rc = proto_number(json_array_get(pair, 1), &k[i][1], err, kfield, "[1]");
    }
    if (!rc) {
        rc = aa_acuity_from_knots(out, (const double(*)[2])k, n, err);
        if (rc)
            proto_prefix_error(err, prefix);
    }
    free(k);
    return rc;
}

int proto_decode_angles(const json_t *j, double **out, size_t *count, const char *field_prefix,
                        aa_error *err)
{
    const char *prefix = field_prefix ? field_prefix : "";
    *out = NULL;
    *count = 0;
    if (!j || json_is_null(j))
        return AA_OK;
    if (!json_is_array(j))
        return proto_fail(err, AA_EINVAL, prefix, "", "must be an array of angles in degrees");
    size_t n = json_array_size(j);
    if (n == 0)
        return proto_fail(err, AA_EINVAL, prefix, "", "needs at least one angle");
    if (n > PROTO_MAX_ANGLES) {
        char msg[64];
        snprintf(msg, sizeof msg, "at most %d angles", PROTO_MAX_ANGLES);
        return proto_fail(err, AA_ERANGE, prefix, "", msg);
    }
    double *a = malloc(n * sizeof *a);
    if (!a)
        return proto_fail(err, AA_ENOMEM, prefix, "", "out of memory");
    for (size_t i = 0; i < n; i++) {
        char idx[32];
        snprintf(idx, sizeof idx, "[%zu]", i);
        int rc = proto_number(json_array_get(j, i), &a[i], err, prefix, idx);
        if (rc) {
            free(a);
            return rc;
        }
    }
    *out = a;
    *count = n;
    return AA_OK;
}

json_t *proto_encode_filter(const aa_filter *f)
{
    assert(f);
    json_t *o = json_pack("{s:s,s:o}", "name", f->name, "radius", proto_real(f->radius));
    if (!o)
        return NULL;
    if (f->formula == AA_FILTER_MITCHELL || is_mitchell_family(f->name)) {
        json_object_set_new(o, "B", proto_real(f->B));
        json_object_set_new(o, "C", proto_real(f->C));
    } else if (f->formula == AA_FILTER_GAUSSIAN) {
        json_object_set_new(o, "sigma", proto_real(f->sigma));
    } else if (f->formula == AA_FILTER_LANCZOS) {
        json_object_set_new(o, "a", proto_real(f->lanczos_a));
        json_object_del(o, "radius");
    }
    if (f->cdf_error_bound > 0)
        json_object_set_new(o, "cdf_error_bound", proto_real(f->cdf_error_bound));
    return o;
}

json_t *proto_encode_acuity(const aa_acuity *a)
{
    json_t *knots = json_array();
    for (size_t i = 0; knots && i < a->count; i++)
        json_array_append_new(knots, json_pack("[ff]", a->angle_deg[i], a->weight[i]));
    return json_pack("{s:s,s:b,s:o}", "name", a->name, "folded", a->folded, "knots", knots);
}

json_t *proto_encode_acuity_ref(const aa_acuity *a)
{
    if (a->version <= 0)
        return json_pack("{s:s}", "name", "custom");
    return json_pack("{s:s,s:i}", "name", a->name, "version", a->version);
}

int proto_acuity_ref_decode(const json_t *obj, char *name, size_t cap, int *version, aa_error *err)
{
    const json_t *a = json_object_get(obj, "acuity");
    const char *n = json_string_value(json_object_get(a, "name"));
    const json_t *v = json_object_get(a, "version");
    name[0] = 0;
    *version = 0;
    if (!a)
        return AA_OK;
    static const char *const keys[] = {"name", "version", NULL};
    if (!json_is_object(a) || !n || proto_check_keys(a, keys, NULL, "acuity"))
        return aa_error_set(err, AA_EINVAL, "acuity", "expected {\"name\", \"version\"}");
    if (v && (!json_is_integer(v) || json_integer_value(v) < 1 || json_integer_value(v) > 1000))
        return aa_error_set(err, AA_EINVAL, "acuity.version", "must be a positive integer");
    if (!v != !strcmp(n, "custom"))
        return aa_error_set(err, AA_EINVAL, "acuity.version",
                            "a named table has a version, a custom one none");
    snprintf(name, cap, "%s", n);
    *version = v ? (int)json_integer_value(v) : 0;
    return AA_OK;
}

bool proto_acuity_ref_encode(json_t *obj, const char *name, int version)
{
    return !name[0] || !json_object_set_new(
                           obj, "acuity",
                           version > 0 ? json_pack("{s:s,s:i}", "name", name, "version", version)
                                       : json_pack("{s:s}", "name", "custom"));
}

void proto_acuity_ref_set(const aa_acuity *acuity, char *name, size_t cap, int *version)
{
    snprintf(name, cap, "%s", acuity->version > 0 ? acuity->name : "custom");
    *version = acuity->version > 0 ? acuity->version : 0;
}

json_t *proto_encode_evaluation(const aa_evaluation *e, const aa_pattern *p, bool detail)
{
    json_t *o =
        json_pack("{s:o,s:{s:I,s:o},s:o,s:I,s:I}", "e2", proto_real(e->e2), "argmax", "kernel",
                  (json_int_t)e->argmax_kernel, "angle_deg", proto_real(e->argmax_angle_deg),
                  "mean", proto_real(e->mean), "kernel_count", (json_int_t)e->kernel_count,
                  "angle_count", (json_int_t)e->angle_count);
    if (!o)
        return NULL;
    if (!isnan(e->lp_norm))
        json_object_set_new(o, "lp_norm", proto_real(e->lp_norm));
    if (p) {
        json_object_set_new(o, "family", json_string(p->family));
        json_object_set_new(o, "cost_spp", proto_real(p->cost_spp));
    }
    if (detail) {
        json_t *kernels = json_array();
        for (size_t k = 0; k < e->kernel_count; k++) {
            json_t *angles = json_array();
            for (size_t i = 0; i < e->angle_count; i++) {
                double e1 = e->e1[k * e->angle_count + i];
                json_array_append_new(angles,
                                      json_pack("{s:o,s:o,s:o,s:o}", "angle_deg",
                                                proto_real(e->angles_deg[i]), "weight",
                                                proto_real(e->weight[i]), "e1", proto_real(e1),
                                                "weighted", proto_real(e->weight[i] * e1)));
            }
            json_array_append_new(
                kernels, json_pack("{s:I,s:o}", "kernel", (json_int_t)k, "angles", angles));
        }
        json_object_set_new(o, "detail", kernels);
    }
    return o;
}
