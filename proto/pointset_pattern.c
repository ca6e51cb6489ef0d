/* Point sets <-> patterns (pointset.h): the tile a point set describes, with its weights from
 * the file, the aalab header, the filter or equal; and a pattern's point set with the header
 * that restores it exactly. */
#include "pointset.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"

#define HEADER_VERSION 1
/* The points of a header's pattern must match the file's to this (unit-square units). */
#define HEADER_POINT_TOLERANCE 1e-9

bool proto_weights_rule_parse(const char *name, proto_weights_rule *out)
{
    static const char *const names[] = {"file", "filter", "equal"};
    for (int i = 0; name && i < 3; i++) {
        if (!strcmp(name, names[i])) {
            *out = (proto_weights_rule)i;
            return true;
        }
    }
    return false;
}

const char *proto_weights_rule_name(proto_weights_rule r)
{
    return r == PROTO_WEIGHTS_FILTER ? "filter" : r == PROTO_WEIGHTS_EQUAL ? "equal" : "file";
}

proto_points_options proto_points_options_default(void)
{
    return (proto_points_options){0, 0, -1, PROTO_WEIGHTS_FILE, NULL, 0};
}

/* "line 3: " / "point 3: " / "" (data: the index is in the field) for point i. */
static void point_where(const proto_pointset *ps, size_t i, const char *points_field, char *field,
                        size_t fcap, char *where, size_t wcap)
{
    if (ps->by_index) {
        char idx[32];
        snprintf(idx, sizeof idx, "[%zu]", ps->where[i]);
        proto_join_field(field, fcap, points_field, idx);
        where[0] = 0;
    } else {
        proto_join_field(field, fcap, points_field, "");
        snprintf(where, wcap, "%s %zu: ", ps->by_line ? "line" : "point", ps->where[i]);
    }
}

/* An engine error about the tile built from the points, re-addressed to what the user wrote. */
static int readdress(aa_error *err, const proto_pointset *ps, int T, bool header_weights,
                     const char *options_field, const char *points_field)
{
    aa_error e = *err;
    size_t i;
    char field[PROTO_FIELD_MAX], where[48];
    if (sscanf(e.field, "tile.samples[%zu]", &i) == 1 && i < ps->count) {
        point_where(ps, i, points_field, field, sizeof field, where, sizeof where);
        return aa_error_set(err, e.code, field, "%s%s", where, e.message);
    }
    if (sscanf(e.field, "tile.weights[%zu]", &i) == 1 && T > 0) {
        proto_join_field(field, sizeof field, points_field, "");
        if (header_weights)
            return aa_error_set(err, e.code, field,
                                "line %zu: aalab-pattern header: weights of pixel (%zu, %zu): %s",
                                ps->header_line, i % (size_t)T, i / (size_t)T, e.message);
        return aa_error_set(err, e.code, field, "pixel (%zu, %zu) of the tile: %s", i % (size_t)T,
                            i / (size_t)T, e.message);
    }
    proto_join_field(field, sizeof field, options_field, e.field);
    return aa_error_set(err, e.code, field, "%s", e.message);
}

/* Header errors name the points field with the header's line. */
static int header_error(aa_error *err, const proto_pointset *ps, const char *points_field,
                        const char *msg)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, points_field, "");
    if (ps->header_line)
        return aa_error_set(err, AA_EINVAL, field, "line %zu: aalab-pattern header: %s",
                            ps->header_line, msg);
    return aa_error_set(err, AA_EINVAL, field, "aalab: %s", msg);
}

static int header_int(const json_t *h, const char *key, int lo, int hi, int def, int *out)
{
    const json_t *v = json_object_get(h, key);
    if (!v) {
        *out = def;
        return def >= lo ? AA_OK : AA_EINVAL;
    }
    if (!json_is_integer(v) || json_integer_value(v) < lo || json_integer_value(v) > hi)
        return AA_EINVAL;
    *out = (int)json_integer_value(v);
    return AA_OK;
}

/* A stated option that differs from the header's value. */
static int disagree(aa_error *err, const char *options_field, const char *key, int stated,
                    int header)
{
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, options_field, key);
    return aa_error_set(err, AA_EINVAL, field,
                        "is %d but the file's aalab-pattern header says %d (omit %s, or remove "
                        "the header line to use your own)",
                        stated, header, key);
}

static int cmp_point_yx(const void *pa, const void *pb)
{
    const proto_point *a = pa, *b = pb;
    if (a->y != b->y)
        return (a->y > b->y) - (a->y < b->y);
    return (a->x > b->x) - (a->x < b->x);
}

/* Do the file's points equal those of the pattern (as sets, to the tolerance)? */
static bool same_points(const proto_pointset *ps, const aa_pattern *p)
{
    proto_pointset mine;
    aa_error e = {0};
    if (proto_pointset_of_pattern(p, &mine, &e))
        return false;
    bool same = mine.count == ps->count;
    proto_point *theirs = same ? malloc(ps->count * sizeof *theirs) : NULL;
    if (theirs) {
        memcpy(theirs, ps->points, ps->count * sizeof *theirs);
        qsort(theirs, ps->count, sizeof *theirs, cmp_point_yx);
        qsort(mine.points, mine.count, sizeof *mine.points, cmp_point_yx);
        for (size_t i = 0; i < ps->count && same; i++)
            same = fabs(theirs[i].x - mine.points[i].x) <= HEADER_POINT_TOLERANCE &&
                   fabs(theirs[i].y - mine.points[i].y) <= HEADER_POINT_TOLERANCE;
    }
    free(theirs);
    proto_pointset_free(&mine);
    return same && theirs;
}

/* A header holding the wire form (kernels, mirrored): that pattern, if the points are its. */
static int from_header_pattern(const proto_pointset *ps, const proto_points_options *o,
                               aa_pattern *out, const char *options_field, const char *points_field,
                               aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    if (o->weights != PROTO_WEIGHTS_FILE) {
        proto_join_field(field, sizeof field, options_field, "weights");
        return aa_error_set(err, AA_EINVAL, field,
                            "the file's aalab-pattern header holds a pattern with its own weights "
                            "(form %s); remove the header line to weight the points yourself",
                            json_object_get(json_object_get(ps->header, "pattern"), "mirrored")
                                ? "mirrored"
                                : "kernels");
    }
    /* The wire form of a pattern, not another point set or a job: no recursion, no lookup. */
    const json_t *wire = json_object_get(ps->header, "pattern");
    if (!json_is_object(wire) || json_object_get(wire, "points") || json_object_get(wire, "job"))
        return header_error(err, ps, points_field,
                            "pattern must be a preset, kernels, mirrored or tile pattern");
    aa_error e = {0};
    int rc = proto_decode_pattern(wire, o->flags, out, "pattern", &e);
    if (rc) {
        char msg[sizeof e.message + sizeof e.field + 8];
        snprintf(msg, sizeof msg, "%s: %s", e.field, e.message);
        return header_error(err, ps, points_field, msg);
    }
    if (o->tile > 0 && o->tile != out->tile)
        rc = disagree(err, options_field, "tile", o->tile, out->tile);
    else if (o->kernel > 0 && o->kernel != out->kernel_size)
        rc = disagree(err, options_field, "kernel", o->kernel, out->kernel_size);
    else if (!same_points(ps, out))
        rc = header_error(err, ps, points_field,
                          "the points are not those of the header's pattern (edited?); remove "
                          "the header line to read the points alone");
    if (rc)
        aa_pattern_free(out);
    return rc;
}

/* Per-kernel weight lists from the header ("weights": [[w, ...], ...], one per pixel). */
static int header_weights(const proto_pointset *ps, int T, double ***w, size_t **wc,
                          const char *points_field, aa_error *err)
{
    const json_t *a = json_object_get(ps->header, "weights");
    size_t kc = (size_t)T * (size_t)T;
    if (!json_is_array(a) || json_array_size(a) != kc) {
        char msg[96];
        snprintf(msg, sizeof msg, "weights must be %zu lists of numbers (one per pixel)", kc);
        return header_error(err, ps, points_field, msg);
    }
    *w = calloc(kc, sizeof **w);
    *wc = calloc(kc, sizeof **wc);
    if (!*w || !*wc)
        return aa_error_set(err, AA_ENOMEM, points_field, "out of memory");
    for (size_t k = 0; k < kc; k++) {
        const json_t *list = json_array_get(a, k);
        size_t n = json_is_array(list) ? json_array_size(list) : 0;
        (*w)[k] = malloc((n ? n : 1) * sizeof ***w);
        if (!(*w)[k])
            return aa_error_set(err, AA_ENOMEM, points_field, "out of memory");
        (*wc)[k] = n;
        if (!json_is_array(list) || n > AA_MAX_KERNEL_SAMPLES)
            return header_error(err, ps, points_field, "weights[k] must be a list of numbers");
        for (size_t m = 0; m < n; m++) {
            const json_t *v = json_array_get(list, m);
            if (!json_is_number(v) || !isfinite(json_number_value(v)))
                return header_error(err, ps, points_field, "weights hold a non-number");
            (*w)[k][m] = json_number_value(v);
        }
    }
    return AA_OK;
}

static void free_weights(double **w, size_t *wc, size_t kc)
{
    for (size_t k = 0; w && k < kc; k++)
        free(w[k]);
    free(w);
    free(wc);
}

/* A filter whose normalised weights are equal over any kernel block (K <= 8 reads |x| <= 4):
 * builds the tile's structure when the weights come from elsewhere. */
static void flat_filter(aa_filter *f)
{
    aa_filter_box(f, 16, NULL);
}

int proto_pattern_from_pointset(const proto_pointset *ps, const proto_points_options *o,
                                aa_pattern *out, const char *options_field,
                                const char *points_field, aa_error *err)
{
    memset(out, 0, sizeof *out);
    char field[PROTO_FIELD_MAX], where[48];
    const json_t *h = ps->header;
    if (h) {
        static const char *const keys[] = {"version", "family",  "cost_spp", "tile", "kernel",
                                           "border",  "weights", "pattern",  NULL};
        aa_error e = {0};
        if (proto_check_keys(h, keys, &e, "")) {
            char msg[sizeof e.field + 32];
            snprintf(msg, sizeof msg, "unknown key '%s'", e.field);
            return header_error(err, ps, points_field, msg);
        }
        const json_t *ver = json_object_get(h, "version");
        if (ver && !(json_is_integer(ver) && json_integer_value(ver) == HEADER_VERSION))
            return header_error(err, ps, points_field, "version must be 1");
        if (json_object_get(h, "pattern"))
            return from_header_pattern(ps, o, out, options_field, points_field, err);
    }
    int T, K, border;
    if (h) {
        if (header_int(h, "tile", 1, AA_MAX_TILE, 0, &T))
            return header_error(err, ps, points_field, "tile must be an integer 1..16");
        if (header_int(h, "kernel", 1, AA_MAX_KERNEL_SIZE, 1, &K))
            return header_error(err, ps, points_field, "kernel must be an integer 1..8");
        const json_t *b = json_object_get(h, "border");
        if (b && !json_is_boolean(b))
            return header_error(err, ps, points_field, "border must be true or false");
        border = b && json_is_true(b);
        if (o->tile > 0 && o->tile != T)
            return disagree(err, options_field, "tile", o->tile, T);
        if (o->kernel > 0 && o->kernel != K)
            return disagree(err, options_field, "kernel", o->kernel, K);
        if (o->border >= 0 && o->border != border)
            return disagree(err, options_field, "border", o->border, border);
    } else {
        T = o->tile > 0 ? o->tile : 1;
        K = o->kernel > 0 ? o->kernel : 1;
        border = o->border > 0;
        if (o->weights == PROTO_WEIGHTS_FILE && !ps->has_weights) {
            proto_join_field(field, sizeof field, options_field, "weights");
            return aa_error_set(err, AA_EINVAL, field,
                                "the points have no weights; choose filter or equal");
        }
        if (o->weights == PROTO_WEIGHTS_FILE && K != 1) {
            proto_join_field(field, sizeof field, options_field, "weights");
            return aa_error_set(err, AA_EINVAL, field,
                                "weights from the file are per sample and need kernel 1 (one "
                                "pixel per kernel); with kernel %d choose filter or equal",
                                K);
        }
    }
    /* The file's points in tile coordinates. */
    aa_point *pts = malloc((ps->count ? ps->count : 1) * sizeof *pts);
    if (!pts)
        return aa_error_set(err, AA_ENOMEM, points_field, "out of memory");
    for (size_t i = 0; i < ps->count; i++) {
        const proto_point *q = &ps->points[i];
        if (!(q->x >= 0 && q->x <= 1 && q->y >= 0 && q->y <= 1)) {
            point_where(ps, i, points_field, field, sizeof field, where, sizeof where);
            free(pts);
            return aa_error_set(err, AA_EINVAL, field,
                                "%s(%.17g, %.17g) lies outside the unit square [0, 1) of the "
                                "tile",
                                where, q->x, q->y);
        }
        pts[i] = (aa_point){q->x * T, q->y * T};
    }
    aa_tile_spec spec = {
        .tile = T, .kernel_size = K, .border = border, .count = ps->count, .samples = pts};
    size_t kc = (size_t)T * (size_t)T;
    double **w = NULL;
    size_t *wc = NULL;
    int rc = AA_OK;
    bool use_header = h && o->weights == PROTO_WEIGHTS_FILE;
    aa_filter filter;
    if (use_header) {
        rc = header_weights(ps, T, &w, &wc, points_field, err);
        spec.weights = (const double *const *)w;
        spec.weight_counts = wc;
    } else if (o->weights == PROTO_WEIGHTS_FILTER) {
        if (o->filter)
            filter = *o->filter;
        else
            aa_filter_default(&filter);
        spec.weight_filter = &filter;
    } else {
        flat_filter(&filter);
        spec.weight_filter = &filter;
    }
    if (!rc) {
        rc = aa_pattern_from_tile(out, &spec, o->flags, err);
        if (rc)
            readdress(err, ps, T, use_header, options_field, points_field);
    }
    if (!rc && !use_header && o->weights != PROTO_WEIGHTS_FILTER) {
        /* Equal or per-sample weights on the structure just built, checked by the engine. */
        w = calloc(kc, sizeof *w);
        wc = calloc(kc, sizeof *wc);
        rc = w && wc ? AA_OK : aa_error_set(err, AA_ENOMEM, points_field, "out of memory");
        for (size_t k = 0; k < kc && !rc; k++) {
            const aa_kernel *ker = &out->kernels[k];
            wc[k] = ker->count;
            w[k] = malloc(ker->count * sizeof **w);
            if (!w[k]) {
                rc = aa_error_set(err, AA_ENOMEM, points_field, "out of memory");
                break;
            }
            for (size_t m = 0; m < ker->count; m++)
                w[k][m] = o->weights == PROTO_WEIGHTS_EQUAL ? 1.0 / (double)ker->count
                                                            : ps->points[ker->tile_index[m]].w;
        }
        aa_pattern_free(out);
        if (!rc) {
            spec.weight_filter = NULL;
            spec.weights = (const double *const *)w;
            spec.weight_counts = wc;
            rc = aa_pattern_from_tile(out, &spec, o->flags, err);
            if (rc)
                readdress(err, ps, T, false, options_field, points_field);
        }
    }
    free_weights(w, wc, kc);
    free(pts);
    return rc;
}

/* --- pattern -> point set ------------------------------------------------------------------- */

/* The wire form alone (no informational keys), for the header of a non-tile pattern. */
static json_t *wire_form(const aa_pattern *p)
{
    json_t *enc = proto_encode_pattern(p);
    if (!enc)
        return NULL;
    const char *key = p->form == AA_FORM_MIRRORED ? "mirrored" : "kernels";
    json_t *o = json_pack("{s:O}", key, json_object_get(enc, key));
    json_decref(enc);
    return o;
}

static json_t *kernel_weights(const aa_pattern *p)
{
    json_t *a = json_array();
    for (size_t k = 0; a && k < p->kernel_count; k++) {
        json_t *w = json_array();
        for (size_t m = 0; w && m < p->kernels[k].count; m++)
            json_array_append_new(w, json_real(p->kernels[k].samples[m].w));
        json_array_append_new(a, w);
    }
    return a;
}

int proto_pointset_of_pattern(const aa_pattern *p, proto_pointset *out, aa_error *err)
{
    memset(out, 0, sizeof *out);
    bool tiled = p->tile > 0;
    size_t n = tiled ? p->tile_count : p->kernels[0].count;
    out->points = calloc(n ? n : 1, sizeof *out->points);
    out->where = calloc(n ? n : 1, sizeof *out->where);
    out->header = json_pack("{s:i,s:s,s:o}", "version", HEADER_VERSION, "family", p->family,
                            "cost_spp", proto_real(p->cost_spp));
    if (!out->points || !out->where || !out->header)
        goto nomem;
    out->count = n;
    for (size_t i = 0; i < n; i++)
        out->where[i] = i;
    out->by_index = true;
    if (tiled) {
        double T = p->tile;
        for (size_t i = 0; i < n; i++)
            out->points[i] = (proto_point){p->tile_samples[i].x / T, p->tile_samples[i].y / T, NAN};
        /* A w per point where every kernel reading the sample weighs it the same. */
        out->has_weights = true;
        for (size_t k = 0; k < p->kernel_count && out->has_weights; k++) {
            const aa_kernel *ker = &p->kernels[k];
            for (size_t m = 0; m < ker->count && out->has_weights; m++) {
                proto_point *q = &out->points[ker->tile_index[m]];
                if (isnan(q->w))
                    q->w = ker->samples[m].w;
                else if (q->w != ker->samples[m].w)
                    out->has_weights = false;
            }
        }
        for (size_t i = 0; i < n; i++) {
            if (isnan(out->points[i].w))
                out->has_weights = false;
            if (!out->has_weights)
                out->points[i].w = 0;
        }
    } else {
        for (size_t i = 0; i < n; i++) {
            const aa_sample *s = &p->kernels[0].samples[i];
            out->points[i] = (proto_point){s->x + 0.5, s->y + 0.5, s->w};
        }
        out->has_weights = true;
    }
    int rc = 0;
    if (p->form == AA_FORM_TILE) {
        rc |= json_object_set_new(out->header, "tile", json_integer(p->tile));
        rc |= json_object_set_new(out->header, "kernel", json_integer(p->kernel_size));
        rc |= json_object_set_new(out->header, "border", json_boolean(p->border));
        rc |= json_object_set_new(out->header, "weights", kernel_weights(p));
    } else {
        rc |= json_object_set_new(out->header, "pattern", wire_form(p));
    }
    if (!rc)
        return AA_OK;
nomem:
    proto_pointset_free(out);
    return aa_error_set(err, AA_ENOMEM, "", "out of memory");
}
