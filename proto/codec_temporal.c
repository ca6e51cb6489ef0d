/* The temporal pattern form (codec_temporal.h). */
#include "codec_temporal.h"
#include "codec_internal.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void proto_temporal_free(proto_temporal *t)
{
    free(t->jitter);
    if (t->has_frame)
        aa_pattern_free(&t->frame);
    memset(t, 0, sizeof *t);
}

aa_temporal_spec proto_temporal_spec(const proto_temporal *t)
{
    return (aa_temporal_spec){.count = t->count,
                              .jitter = t->jitter,
                              .frame = t->has_frame ? &t->frame : NULL,
                              .resolve = t->has_resolve ? &t->resolve : NULL,
                              .blend = t->blend};
}

int proto_temporal_build(const proto_temporal *t, const char *field_prefix, aa_temporal *out,
                         aa_error *err)
{
    aa_temporal_spec ts = proto_temporal_spec(t);
    int rc = aa_temporal_build(out, &ts, err);
    if (rc)
        proto_prefix_error(err, field_prefix);
    return rc;
}

/* An integer in [lo, hi] at prefix.sub. */
static int decode_count(const json_t *j, long lo, long hi, long *out, const char *prefix,
                        const char *sub, aa_error *err)
{
    if (!json_is_integer(j) || json_integer_value(j) < lo || json_integer_value(j) > hi) {
        char msg[96];
        snprintf(msg, sizeof msg, "must be an integer in [%ld, %ld]", lo, hi);
        return proto_fail(err, AA_EINVAL, prefix, sub, msg);
    }
    *out = (long)json_integer_value(j);
    return AA_OK;
}

static int alloc_jitter(proto_temporal *t, size_t n, aa_error *err)
{
    t->jitter = malloc(n * sizeof *t->jitter);
    t->count = n;
    return t->jitter ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
}

/* Offsets given or taken from a preset must lie in the jitter square. */
static int check_in_range(const proto_temporal *t, const char *prefix, aa_error *err)
{
    double h = t->jitter_range / 2 + 1e-12;
    for (size_t f = 0; f < t->count; f++) {
        if (fabs(t->jitter[f].x) > h || fabs(t->jitter[f].y) > h) {
            char sub[32];
            snprintf(sub, sizeof sub, "[%zu]", f);
            return proto_fail(err, AA_EINVAL, prefix, sub,
                              "an offset must lie in [-jitter_range/2, jitter_range/2]^2");
        }
    }
    return AA_OK;
}

static int decode_generator(const json_t *j, proto_temporal *t, const char *prefix, aa_error *err)
{
    const json_t *g = json_object_get(j, "generator");
    if (!json_is_string(g))
        return proto_fail(err, AA_EINVAL, prefix, "generator",
                          "must be one of halton, r2, rgss4, fsr2, preset");
    const char *name = json_string_value(g);
    int rc;
    long count = 0, start = 1;
    if (!strcmp(name, "halton") || !strcmp(name, "r2")) {
        static const char *const hk[] = {"generator", "bases", "start", "count", NULL};
        static const char *const rk[] = {"generator", "start", "count", NULL};
        bool halton = !strcmp(name, "halton");
        rc = proto_check_keys(j, halton ? hk : rk, err, prefix);
        if (!rc)
            rc = decode_count(json_object_get(j, "count"), 1, AA_TEMPORAL_MAX_PHASES, &count,
                              prefix, "count", err);
        if (!rc && json_object_get(j, "start"))
            rc = decode_count(json_object_get(j, "start"), 0, AA_JITTER_MAX_INDEX - 2048, &start,
                              prefix, "start", err);
        long bx = 2, by = 3;
        const json_t *bases = json_object_get(j, "bases");
        if (!rc && bases) {
            if (!json_is_array(bases) || json_array_size(bases) != 2)
                return proto_fail(err, AA_EINVAL, prefix, "bases", "must be two integer bases");
            rc = decode_count(json_array_get(bases, 0), 2, 1000, &bx, prefix, "bases[0]", err);
            if (!rc)
                rc = decode_count(json_array_get(bases, 1), 2, 1000, &by, prefix, "bases[1]", err);
        }
        if (!rc)
            rc = alloc_jitter(t, (size_t)count, err);
        if (!rc)
            rc = halton ? aa_jitter_halton(t->jitter, t->count, (unsigned)bx, (unsigned)by,
                                           (unsigned long)start, t->jitter_range, err)
                        : aa_jitter_r2(t->jitter, t->count, (unsigned long)start, t->jitter_range,
                                       err);
        return rc;
    }
    if (!strcmp(name, "rgss4")) {
        static const char *const keys[] = {"generator", NULL};
        rc = proto_check_keys(j, keys, err, prefix);
        if (!rc)
            rc = alloc_jitter(t, AA_JITTER_RGSS4_COUNT, err);
        if (!rc)
            aa_jitter_rgss4(t->jitter, t->jitter_range);
        return rc;
    }
    if (!strcmp(name, "fsr2")) {
        static const char *const keys[] = {"generator", "scale", NULL};
        rc = proto_check_keys(j, keys, err, prefix);
        double scale = 0;
        if (!rc)
            rc = proto_number(json_object_get(j, "scale"), &scale, err, prefix, "scale");
        int n = rc ? 0 : aa_jitter_fsr2_phase_count(scale);
        if (!rc && (scale < 1 || n < 1 || n > AA_TEMPORAL_MAX_PHASES))
            return proto_fail(err, AA_EINVAL, prefix, "scale",
                              "scale (display / render width) must be in [1, 11.3]");
        if (!rc)
            rc = alloc_jitter(t, (size_t)n, err);
        if (!rc)
            rc = aa_jitter_halton(t->jitter, t->count, 2, 3, 1, t->jitter_range, err);
        return rc;
    }
    if (!strcmp(name, "preset")) {
        static const char *const keys[] = {"generator", "preset", NULL};
        rc = proto_check_keys(j, keys, err, prefix);
        if (rc)
            return rc;
        const json_t *pv = json_object_get(j, "preset");
        const aa_preset *pr = json_is_string(pv) ? aa_preset_find(json_string_value(pv)) : NULL;
        if (!pr)
            return proto_fail(err, AA_EINVAL, prefix, "preset", "unknown preset");
        if (pr->form != AA_FORM_KERNELS || pr->kernel_count != 1)
            return proto_fail(err, AA_EINVAL, prefix, "preset",
                              "a sequence takes the positions of a one-kernel preset");
        rc = alloc_jitter(t, pr->sample_count, err);
        for (size_t f = 0; !rc && f < pr->sample_count; f++)
            t->jitter[f] = (aa_point){pr->samples[f].x, pr->samples[f].y};
        return rc ? rc : check_in_range(t, prefix, err);
    }
    return proto_fail(err, AA_EINVAL, prefix, "generator",
                      "must be one of halton, r2, rgss4, fsr2, preset");
}

static int decode_jitter(const json_t *j, proto_temporal *t, const char *prefix, aa_error *err)
{
    if (json_is_object(j))
        return decode_generator(j, t, prefix, err);
    if (!json_is_array(j) || json_array_size(j) == 0 ||
        json_array_size(j) > AA_TEMPORAL_MAX_PHASES) {
        char msg[128];
        snprintf(msg, sizeof msg, "must be 1 to %d offsets [x, y] or a generator object",
                 AA_TEMPORAL_MAX_PHASES);
        return proto_fail(err, AA_EINVAL, prefix, "", msg);
    }
    int rc = alloc_jitter(t, json_array_size(j), err);
    for (size_t f = 0; !rc && f < t->count; f++) {
        const json_t *o = json_array_get(j, f);
        char sub[32];
        snprintf(sub, sizeof sub, "[%zu]", f);
        if (!json_is_array(o) || json_array_size(o) != 2)
            return proto_fail(err, AA_EINVAL, prefix, sub, "an offset is [x, y]");
        char field[PROTO_FIELD_MAX];
        proto_join_field(field, sizeof field, prefix, sub);
        rc = proto_number(json_array_get(o, 0), &t->jitter[f].x, err, field, "[0]");
        if (!rc)
            rc = proto_number(json_array_get(o, 1), &t->jitter[f].y, err, field, "[1]");
    }
    return rc ? rc : check_in_range(t, prefix, err);
}

static int decode_blend(const json_t *j, aa_blend *b, const char *prefix, aa_error *err)
{
    *b = (aa_blend){AA_BLEND_EXPONENTIAL, 0.1};
    if (!j)
        return AA_OK;
    if (!json_is_object(j))
        return proto_fail(err, AA_EINVAL, prefix, "", "a blend is {\"kind\", \"alpha\"}");
    static const char *const keys[] = {"kind", "alpha", NULL};
    int rc = proto_check_keys(j, keys, err, prefix);
    if (rc)
        return rc;
    const json_t *k = json_object_get(j, "kind");
    const char *kind = json_is_string(k) ? json_string_value(k) : "";
    if (!strcmp(kind, "box")) {
        if (json_object_get(j, "alpha"))
            return proto_fail(err, AA_EINVAL, prefix, "alpha", "a box blend takes no alpha");
        b->kind = AA_BLEND_BOX;
        return AA_OK;
    }
    if (strcmp(kind, "exponential"))
        return proto_fail(err, AA_EINVAL, prefix, "kind", "must be exponential or box");
    rc = proto_number(json_object_get(j, "alpha"), &b->alpha, err, prefix, "alpha");
    if (!rc && !(b->alpha >= AA_TEMPORAL_MIN_ALPHA && b->alpha <= 1))
        return proto_fail(err, AA_EINVAL, prefix, "alpha", "alpha must be in [1e-6, 1]");
    return rc;
}

static int decode_resolve(const json_t *j, proto_temporal *t, const char *prefix, aa_error *err)
{
    if (!json_is_object(j))
        return proto_fail(err, AA_EINVAL, prefix, "", "a resolve is {\"filter\", \"radius\"}");
    static const char *const keys[] = {"filter", "radius", NULL};
    int rc = proto_check_keys(j, keys, err, prefix);
    if (rc)
        return rc;
    const json_t *f = json_object_get(j, "filter");
    if (!f)
        return proto_fail(err, AA_EINVAL, prefix, "filter", "a resolve needs a filter");
    char field[PROTO_FIELD_MAX];
    proto_join_field(field, sizeof field, prefix, "filter");
    rc = proto_decode_filter(f, &t->resolve.filter, field, err);
    long radius = 1;
    if (!rc && json_object_get(j, "radius"))
        rc = decode_count(json_object_get(j, "radius"), 0, AA_TEMPORAL_MAX_RESOLVE_RADIUS, &radius,
                          prefix, "radius", err);
    t->resolve.radius = (int)radius;
    t->has_resolve = !rc;
    return rc;
}

static const proto_temporal_preset *find_preset(const char *name)
{
    for (size_t i = 0; i < proto_temporal_preset_count(); i++)
        if (!strcmp(proto_temporal_preset_at(i)->name, name))
            return proto_temporal_preset_at(i);
    return NULL;
}

static int decode_object(const json_t *v, proto_temporal *out, const char *prefix, aa_error *err)
{
    char field[PROTO_FIELD_MAX];
    int rc = AA_OK;
    const json_t *range = json_object_get(v, "jitter_range");
    out->jitter_range = 1;
    if (range) {
        rc = proto_number(range, &out->jitter_range, err, prefix, "jitter_range");
        if (!rc && !(out->jitter_range > 0 && out->jitter_range <= 16))
            return proto_fail(err, AA_EINVAL, prefix, "jitter_range",
                              "must be a number in (0, 16] pixels");
    }
    const json_t *jit = json_object_get(v, "jitter");
    if (!rc && !jit)
        return proto_fail(err, AA_EINVAL, prefix, "jitter", "a temporal pattern needs jitter");
    proto_join_field(field, sizeof field, prefix, "jitter");
    if (!rc)
        rc = decode_jitter(jit, out, field, err);
    proto_join_field(field, sizeof field, prefix, "blend");
    if (!rc)
        rc = decode_blend(json_object_get(v, "blend"), &out->blend, field, err);
    const json_t *fp = json_object_get(v, "frame_pattern");
    if (!rc && fp) {
        proto_join_field(field, sizeof field, prefix, "frame_pattern");
        rc = proto_decode_pattern(fp, 0, &out->frame, field, err);
        out->has_frame = !rc;
    }
    const json_t *rs = json_object_get(v, "resolve");
    if (!rc && rs) {
        proto_join_field(field, sizeof field, prefix, "resolve");
        rc = decode_resolve(rs, out, field, err);
    }
    long cut = 0;
    if (!rc && json_object_get(v, "cut_frames"))
        rc = decode_count(json_object_get(v, "cut_frames"), 1, AA_TEMPORAL_MAX_CUT_FRAMES, &cut,
                          prefix, "cut_frames", err);
    out->cut_frames = (size_t)cut;
    return rc;
}

int proto_decode_temporal_object(const json_t *v, proto_temporal *out, const char *field_prefix,
                                 aa_error *err)
{
    memset(out, 0, sizeof *out);
    const char *prefix = field_prefix ? field_prefix : "";
    if (!json_is_object(v))
        return proto_fail(err, AA_EINVAL, prefix, "", "a temporal pattern is an object");
    static const char *const keys[] = {"jitter",  "jitter_range", "blend", "frame_pattern",
                                       "resolve", "cut_frames",   NULL};
    int rc = proto_check_keys(v, keys, err, prefix);
    if (!rc)
        rc = decode_object(v, out, prefix, err);
    if (rc)
        proto_temporal_free(out);
    return rc;
}

int proto_temporal_copy(const proto_temporal *t, proto_temporal *out, aa_error *err)
{
    *out = *t;
    out->jitter = NULL;
    out->has_frame = false;
    int rc = alloc_jitter(out, t->count, err);
    if (!rc)
        memcpy(out->jitter, t->jitter, t->count * sizeof *t->jitter);
    if (!rc && t->has_frame) {
        if (aa_pattern_copy(&out->frame, &t->frame))
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        out->has_frame = !rc;
    }
    if (rc)
        proto_temporal_free(out);
    return rc;
}

json_t *proto_encode_temporal(const proto_temporal *t)
{
    json_t *jit = json_array();
    for (size_t f = 0; jit && f < t->count; f++)
        json_array_append_new(
            jit, json_pack("[o,o]", proto_real(t->jitter[f].x), proto_real(t->jitter[f].y)));
    json_t *blend = t->blend.kind == AA_BLEND_BOX ? json_pack("{s:s}", "kind", "box")
                                                  : json_pack("{s:s,s:o}", "kind", "exponential",
                                                              "alpha", proto_real(t->blend.alpha));
    json_t *v = json_pack("{s:o,s:o,s:o}", "jitter", jit, "jitter_range",
                          proto_real(t->jitter_range), "blend", blend);
    if (v && t->has_frame)
        json_object_set_new(v, "frame_pattern", proto_encode_pattern(&t->frame));
    if (v && t->has_resolve)
        json_object_set_new(v, "resolve",
                            json_pack("{s:o,s:I}", "filter",
                                      proto_encode_filter(&t->resolve.filter), "radius",
                                      (json_int_t)t->resolve.radius));
    if (v && t->cut_frames)
        json_object_set_new(v, "cut_frames", json_integer((json_int_t)t->cut_frames));
    return v ? json_pack("{s:o}", "temporal", v) : NULL;
}

int proto_decode_temporal(const json_t *j, proto_temporal *out, const char *field_prefix,
                          aa_error *err)
{
    memset(out, 0, sizeof *out);
    const char *base = field_prefix ? field_prefix : "";
    static const char *const outer[] = {"temporal", NULL};
    int rc = proto_check_keys(j, outer, err, base);
    if (rc)
        return rc;
    char prefix[PROTO_FIELD_MAX];
    proto_join_field(prefix, sizeof prefix, base, "temporal");
    const json_t *v = json_object_get(j, "temporal");
    if (!json_is_object(v))
        return proto_fail(err, AA_EINVAL, prefix, "", "a temporal pattern is an object");
    static const char *const keys[] = {"preset",        "jitter",  "jitter_range", "blend",
                                       "frame_pattern", "resolve", "cut_frames",   NULL};
    rc = proto_check_keys(v, keys, err, prefix);
    if (rc)
        return rc;
    const json_t *pv = json_object_get(v, "preset");
    if (!pv) {
        rc = decode_object(v, out, prefix, err);
    } else {
        const proto_temporal_preset *pr =
            json_is_string(pv) ? find_preset(json_string_value(pv)) : NULL;
        if (!pr)
            return proto_fail(err, AA_EINVAL, prefix, "preset", "unknown temporal preset");
        /* The preset's keys, overridden by the ones given beside it. */
        json_t *merged = json_loads(pr->spec, JSON_REJECT_DUPLICATES, NULL);
        if (!merged)
            return aa_error_set(err, AA_ENOMEM, "", "out of memory");
        json_object_update(merged, (json_t *)v);
        json_object_del(merged, "preset");
        rc = decode_object(merged, out, prefix, err);
        json_decref(merged);
        out->preset = pr->name;
        out->source = pr->source;
    }
    if (rc)
        proto_temporal_free(out);
    return rc;
}

json_t *proto_encode_temporal_evaluation(const aa_temporal_evaluation *e, const aa_temporal *t,
                                         const proto_temporal *spec)
{
    size_t N = e->phase_count, G = e->group_count, A = e->angle_count;
    json_t *o =
        json_pack("{s:o,s:o,s:{s:I,s:I,s:o},s:I,s:I,s:I,s:o,s:o,s:o}", "e2", proto_real(e->e2),
                  "mean_phase_e2", proto_real(e->mean_phase_e2), "argmax", "phase",
                  (json_int_t)e->argmax_phase, "group", (json_int_t)e->argmax_group, "angle_deg",
                  proto_real(e->argmax_angle_deg), "phase_count", (json_int_t)N, "group_count",
                  (json_int_t)G, "angle_count", (json_int_t)A, "cost_spp", proto_real(t->cost_spp),
                  "effective_samples", proto_real(e->effective_samples), "f2", proto_real(e->f2));
    if (!o)
        return NULL;
    char family[32];
    snprintf(family, sizeof family, "T(%zu)", N);
    json_object_set_new(o, "family", json_string(family));
    json_object_set_new(o, "f2_argmax",
                        json_pack("{s:I,s:o}", "group", (json_int_t)e->f2_group, "angle_deg",
                                  proto_real(e->f2_angle_deg)));
    json_object_set_new(o, "angles_deg", proto_real_array(e->angles_deg, A));
    json_object_set_new(o, "weights", proto_real_array(e->weight, A));
    json_t *phases = json_array();
    for (size_t p = 0; phases && p < N; p++) {
        json_t *e1 = json_array();
        for (size_t g = 0; e1 && g < G; g++)
            json_array_append_new(e1, proto_real_array(e->e1 + (p * G + g) * A, A));
        json_array_append_new(phases, json_pack("{s:I,s:o,s:o,s:o}", "phase", (json_int_t)p, "e2",
                                                proto_real(e->phase_e2[p]), "age_weight",
                                                proto_real(t->age_weight[p]), "e1", e1));
    }
    json_object_set_new(o, "phases", phases);
    json_t *f1 = json_array();
    for (size_t g = 0; f1 && g < G; g++)
        json_array_append_new(f1, proto_real_array(e->f1 + g * A, A));
    json_object_set_new(o, "f1", f1);
    json_object_set_new(o, "after_cut", proto_real_array(e->after_cut, e->cut_count));
    json_object_set_new(o, "frames_to_5pct",
                        e->frames_to_settle > 0 ? json_integer(e->frames_to_settle) : json_null());
    json_t *jit = json_array();
    for (size_t f = 0; jit && f < spec->count; f++)
        json_array_append_new(jit, json_pack("[ff]", spec->jitter[f].x, spec->jitter[f].y));
    json_object_set_new(o, "jitter", jit);
    json_object_set_new(
        o, "blend",
        t->blend.kind == AA_BLEND_BOX
            ? json_pack("{s:s}", "kind", "box")
            : json_pack("{s:s,s:o}", "kind", "exponential", "alpha", proto_real(t->blend.alpha)));
    if (spec->preset)
        json_object_set_new(o, "preset",
                            json_pack("{s:s,s:s}", "name", spec->preset, "source", spec->source));
    return o;
}
