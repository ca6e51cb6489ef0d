/* aalab eval --temporal PRESET|FILE.json|JSON|GENERATOR [--alpha A] [--blend box|exponential|A]
 *                      [--cut-frames K] [--resolve FILTER] [--frame-pattern NAME|FILE] */
#define _POSIX_C_SOURCE 200809L
#include "eval_temporal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../cli.h"
#include "../pattern_source.h"
#include "../table.h"
#include "../views/view_kv.h"
#include "codec_temporal.h"
#include "commands.h"

/* After-cut values per line of the text view. */
#define CURVE_PER_LINE 8

/* The temporal object of a loaded document: the object itself, {"temporal": T}, or a request
 * {"pattern": {"temporal": T}, ...} whose other members go to *extras. Steals doc. */
static int temporal_from_document(const char *what, json_t *doc, json_t **temporal, json_t **extras,
                                  char *err, size_t errcap)
{
    if (!json_is_object(doc)) {
        snprintf(err, errcap, "%s: a temporal pattern is a JSON object", what);
        json_decref(doc);
        return -1;
    }
    json_t *pattern = json_object_get(doc, "pattern");
    if (pattern) {
        json_t *t = json_object_get(pattern, "temporal");
        if (!json_is_object(pattern) || !t) {
            snprintf(err, errcap, "%s: field pattern: expected {\"temporal\": {...}}", what);
            json_decref(doc);
            return -1;
        }
        *temporal = json_incref(t);
        json_object_del(doc, "pattern");
        if (extras && json_object_size(doc) > 0)
            *extras = json_incref(doc);
        json_decref(doc);
        return 0;
    }
    json_t *t = json_object_get(doc, "temporal");
    if (t) {
        if (json_object_size(doc) != 1) {
            snprintf(err, errcap, "%s: a {\"temporal\": ...} pattern has no other keys", what);
            json_decref(doc);
            return -1;
        }
        *temporal = json_incref(t);
        json_decref(doc);
        return 0;
    }
    *temporal = doc;
    return 0;
}

/* NAME:N[:START] of the halton and r2 generators. */
static int counted_generator(const char *name, const char *rest, json_t **out, char *err,
                             size_t errcap)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%s", rest ? rest : "");
    char *colon = strchr(buf, ':');
    if (colon)
        *colon = '\0';
    long count, start = 1;
    if (parse_long(buf, 1, 1024, &count) || (colon && parse_long(colon + 1, 0, 1L << 30, &start))) {
        snprintf(err, errcap, "--temporal %s:N[:START] wants N in 1..1024 and START >= 0", name);
        return -1;
    }
    json_t *g = json_pack("{s:s,s:I,s:I}", "generator", name, "count", (json_int_t)count, "start",
                          (json_int_t)start);
    *out = json_pack("{s:o}", "jitter", g);
    return *out ? 0 : -1;
}

/* A generator argument, or 1 when arg is not one. */
static int generator_argument(const char *arg, json_t **out, char *err, size_t errcap)
{
    const char *colon = strchr(arg, ':');
    size_t n = colon ? (size_t)(colon - arg) : strlen(arg);
    const char *rest = colon ? colon + 1 : NULL;
    if (n == 6 && !strncmp(arg, "halton", n))
        return counted_generator("halton", rest, out, err, errcap);
    if (n == 2 && !strncmp(arg, "r2", n))
        return counted_generator("r2", rest, out, err, errcap);
    if (n == 5 && !strncmp(arg, "rgss4", n) && !rest) {
        *out = json_pack("{s:{s:s}}", "jitter", "generator", "rgss4");
        return *out ? 0 : -1;
    }
    if (n == 4 && !strncmp(arg, "fsr2", n)) {
        double scale;
        if (parse_double(rest ? rest : "", 1, 1e6, &scale)) {
            snprintf(err, errcap, "--temporal fsr2:SCALE wants the display/render ratio >= 1");
            return -1;
        }
        *out = json_pack("{s:{s:s,s:f}}", "jitter", "generator", "fsr2", "scale", scale);
        return *out ? 0 : -1;
    }
    if (n == 9 && !strncmp(arg, "positions", n)) {
        if (!rest || !*rest) {
            snprintf(err, errcap, "--temporal positions:PRESET wants a spatial preset's name");
            return -1;
        }
        *out = json_pack("{s:{s:s,s:s}}", "jitter", "generator", "preset", "preset", rest);
        return *out ? 0 : -1;
    }
    return 1;
}

int temporal_argument(const char *arg, json_t **temporal, json_t **extras, char *err, size_t errcap)
{
    *temporal = NULL;
    if (extras)
        *extras = NULL;
    json_error_t jerr;
    if (arg[0] == '{') {
        json_t *doc = json_loads(arg, JSON_REJECT_DUPLICATES, &jerr);
        if (!doc) {
            snprintf(err, errcap, "--temporal: invalid JSON (%s)", jerr.text);
            return -1;
        }
        return temporal_from_document("--temporal", doc, temporal, extras, err, errcap);
    }
    if (pattern_argument_is_file(arg)) {
        json_t *doc = pattern_json_file(arg, err, errcap);
        if (!doc)
            return -1;
        return temporal_from_document(arg, doc, temporal, extras, err, errcap);
    }
    int g = generator_argument(arg, temporal, err, errcap);
    if (g <= 0)
        return g;
    *temporal = json_pack("{s:s}", "preset", arg);
    return *temporal ? 0 : -1;
}

/* A FILE.json (the eval argument) whose pattern is temporal. */
static bool file_is_temporal(const char *arg)
{
    size_t n = strlen(arg);
    if (n <= 5 || strcmp(arg + n - 5, ".json"))
        return false;
    json_t *doc = json_load_file(arg, JSON_REJECT_DUPLICATES, NULL);
    json_t *pattern = json_object_get(doc, "pattern");
    bool yes = json_object_get(doc, "temporal") || json_object_get(pattern, "temporal");
    json_decref(doc);
    return yes;
}

bool eval_is_temporal(const cli_args *a)
{
    return a->temporal || (a->target && file_is_temporal(a->target));
}

/* The daemon's codec on {"temporal": T}: a typo is named by its field before anything is sent. */
static int temporal_check(const json_t *temporal, char *err, size_t errcap)
{
    json_t *wrapped = json_pack("{s:O}", "temporal", temporal);
    proto_temporal spec = {0};
    aa_error e = {0};
    int rc = wrapped ? proto_decode_temporal(wrapped, &spec, "pattern", &e) : AA_ENOMEM;
    proto_temporal_free(&spec);
    json_decref(wrapped);
    return rc == AA_OK ? 0 : pattern_check_refusal(rc, &e, err, errcap);
}

/* --alpha and --blend over the temporal object's blend. */
static int apply_blend(const cli_args *a, json_t *t, char *err, size_t errcap)
{
    const char *kind = a->blend_text;
    if (!kind && !a->has_alpha)
        return 0;
    if (kind && !strcmp(kind, "box")) {
        if (a->has_alpha) {
            snprintf(err, errcap, "--alpha is the exponential blend's; --blend box has none");
            return -1;
        }
        json_object_set_new(t, "blend", json_pack("{s:s}", "kind", "box"));
        return 0;
    }
    double alpha = 0.1; /* the schema's default blend */
    if (kind && strcmp(kind, "exponential"))
        alpha = a->blend; /* --blend A (args.c checked it) */
    else {
        /* --alpha alone, or --blend exponential: keep a preset's own alpha unless given */
        json_t *old = json_object_get(json_object_get(t, "blend"), "alpha");
        if (json_is_number(old))
            alpha = json_number_value(old);
    }
    if (kind && strcmp(kind, "exponential") && strcmp(kind, "box") && a->has_alpha &&
        a->alpha != a->blend) {
        snprintf(err, errcap, "--blend %s and --alpha %g disagree: give one", kind, a->alpha);
        return -1;
    }
    if (a->has_alpha)
        alpha = a->alpha;
    json_object_set_new(t, "blend", json_pack("{s:s,s:f}", "kind", "exponential", "alpha", alpha));
    return 0;
}

/* The flags over the temporal object (t is modified). */
static int apply_temporal_flags(const cli_args *a, json_t *t, char *err, size_t errcap)
{
    if (apply_blend(a, t, err, errcap))
        return -1;
    if (a->cut_frames)
        json_object_set_new(t, "cut_frames", json_integer(a->cut_frames));
    if (a->resolve) {
        json_t *filter;
        if (filter_argument(a->resolve, &filter, err, errcap))
            return -1;
        json_object_set_new(t, "resolve", json_pack("{s:o}", "filter", filter));
    }
    if (a->frame_pattern) {
        json_t *frame, *extras;
        if (pattern_argument_load(a->frame_pattern, NULL, &frame, &extras, err, errcap))
            return -1;
        json_decref(extras);
        json_object_set_new(t, "frame_pattern", frame);
    }
    return 0;
}

int eval_temporal_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *t, *extras;
    *req = NULL;
    if (temporal_argument(a->temporal ? a->temporal : a->target, &t, &extras, err, errcap))
        return -1;
    if (!json_is_object(t)) {
        snprintf(err, errcap, "the temporal pattern is a JSON object");
        goto fail_t;
    }
    if (apply_temporal_flags(a, t, err, errcap))
        goto fail_t;
    if (temporal_check(t, err, errcap))
        goto fail_t;
    json_t *r = extras ? extras : json_object();
    json_object_set_new(r, "pattern", json_pack("{s:o}", "temporal", t));
    json_t *v;
    if (a->filter) {
        if (filter_argument(a->filter, &v, err, errcap))
            goto fail_r;
        json_object_set_new(r, "filter", v);
    }
    if (a->acuity) {
        if (acuity_argument(a->acuity, &v, err, errcap))
            goto fail_r;
        json_object_set_new(r, "acuity", v);
    }
    if (a->angles) {
        if (angles_argument(a->angles, &v, err, errcap))
            goto fail_r;
        json_object_set_new(r, "angles", v);
    }
    *req = r;
    return 0;
fail_r:
    json_decref(r);
    return -1;
fail_t:
    json_decref(t);
    json_decref(extras);
    return -1;
}

bool eval_answer_is_temporal(const json_t *resp)
{
    return json_is_array(json_object_get(resp, "phases"));
}

/* The angle (index) of a phase's largest W·E1 over its groups; -1 if it has none. */
static long phase_argmax_angle(const json_t *phase, const json_t *weights)
{
    double best = -1;
    long arg = -1;
    size_t g, i;
    json_t *row, *e1;
    json_array_foreach(json_object_get(phase, "e1"), g, row)
    {
        json_array_foreach(row, i, e1)
        {
            double v = json_number_value(e1) * json_number_value(json_array_get(weights, i));
            if (v > best) {
                best = v;
                arg = (long)i;
            }
        }
    }
    return arg;
}

static const char *fmt_double(char *buf, size_t cap, double v, int decimals)
{
    json_t *j = json_real(v);
    fmt_number(buf, cap, j, decimals);
    json_decref(j);
    return buf;
}

static void print_phases(FILE *out, const json_t *resp, bool csv)
{
    static const char *const headers[] = {"phase",      "newest_x", "newest_y",
                                          "age_weight", "e2",       "argmax_angle_deg"};
    table *t = table_new(6, headers);
    if (!t)
        return;
    const json_t *phases = json_object_get(resp, "phases");
    const json_t *jitter = json_object_get(resp, "jitter");
    const json_t *angles = json_object_get(resp, "angles_deg");
    const json_t *weights = json_object_get(resp, "weights");
    size_t p;
    json_t *phase;
    double sum = 0;
    json_array_foreach(phases, p, phase)
    {
        /* Phase p's newest frame is the one with offset p (docs/temporal.md §1). */
        const json_t *o = json_array_get(jitter, p);
        long arg = phase_argmax_angle(phase, weights);
        char c[6][40];
        const char *cells[6] = {
            fmt_number(c[0], sizeof c[0], json_object_get(phase, "phase"), 0),
            fmt_number(c[1], sizeof c[1], json_array_get(o, 0), fmt_decimals(csv, 4)),
            fmt_number(c[2], sizeof c[2], json_array_get(o, 1), fmt_decimals(csv, 4)),
            fmt_number(c[3], sizeof c[3], json_object_get(phase, "age_weight"),
                       fmt_decimals(csv, 4)),
            fmt_number(c[4], sizeof c[4], json_object_get(phase, "e2"), fmt_decimals(csv, 6)),
            arg < 0 ? NULL : fmt_number(c[5], sizeof c[5], json_array_get(angles, (size_t)arg), 1)};
        table_add_row(t, cells);
        sum += json_number_value(json_object_get(phase, "e2"));
    }
    if (!csv && json_array_size(phases) > 0) {
        const json_t *argmax = json_object_get(resp, "argmax");
        char worst[40], wangle[40], wphase[48], mean[40];
        snprintf(wphase, sizeof wphase, "worst (%lld)",
                 (long long)json_integer_value(json_object_get(argmax, "phase")));
        const char *wrow[6] = {
            wphase,
            NULL,
            NULL,
            NULL,
            fmt_number(worst, sizeof worst, json_object_get(resp, "e2"), 6),
            fmt_number(wangle, sizeof wangle, json_object_get(argmax, "angle_deg"), 1)};
        table_add_row(t, wrow);
        /* The daemon's mean when given; otherwise the mean of the rows above. */
        const json_t *m = json_object_get(resp, "mean_phase_e2");
        const char *mrow[6] = {
            "mean",
            NULL,
            NULL,
            NULL,
            json_is_number(m)
                ? fmt_number(mean, sizeof mean, m, 6)
                : fmt_double(mean, sizeof mean, sum / (double)json_array_size(phases), 6),
            NULL};
        table_add_row(t, mrow);
    }
    table_write(t, out, csv);
    table_free(t);
}

/* Per angle: W, the largest E1 over phases and groups, the mean over phases (of each phase's
 * largest over groups), the largest F1 over groups and W·F1. */
static void print_angles(FILE *out, const json_t *resp, bool csv)
{
    static const char *const headers[] = {"angle_deg", "weight", "e1_worst",
                                          "e1_mean",   "f1",     "weighted_f1"};
    table *t = table_new(6, headers);
    if (!t)
        return;
    const json_t *phases = json_object_get(resp, "phases");
    const json_t *weights = json_object_get(resp, "weights");
    const json_t *f1 = json_object_get(resp, "f1");
    size_t a, p, g;
    json_t *angle, *phase, *row;
    json_array_foreach(json_object_get(resp, "angles_deg"), a, angle)
    {
        double worst = 0, mean = 0, flick = 0;
        json_array_foreach(phases, p, phase)
        {
            double top = 0;
            json_array_foreach(json_object_get(phase, "e1"), g, row) top =
                fmax(top, json_number_value(json_array_get(row, a)));
            worst = fmax(worst, top);
            mean += top;
        }
        if (json_array_size(phases))
            mean /= (double)json_array_size(phases);
        json_array_foreach(f1, g, row) flick =
            fmax(flick, json_number_value(json_array_get(row, a)));
        double w = json_number_value(json_array_get(weights, a));
        char c[6][40];
        const char *cells[6] = {
            fmt_number(c[0], sizeof c[0], angle, 1),
            fmt_number(c[1], sizeof c[1], json_array_get(weights, a), fmt_decimals(csv, 4)),
            fmt_double(c[2], sizeof c[2], worst, fmt_decimals(csv, 6)),
            fmt_double(c[3], sizeof c[3], mean, fmt_decimals(csv, 6)),
            fmt_double(c[4], sizeof c[4], flick, fmt_decimals(csv, 6)),
            fmt_double(c[5], sizeof c[5], w * flick, fmt_decimals(csv, 6))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}

/* "k  1-8    1.3985  1.2217 ..." lines, CURVE_PER_LINE values each. */
static void print_after_cut(FILE *out, const json_t *resp)
{
    const json_t *curve = json_object_get(resp, "after_cut");
    size_t n = json_array_size(curve);
    if (!n)
        return;
    const json_t *settle = json_object_get(resp, "frames_to_5pct");
    char e2[40];
    fmt_number(e2, sizeof e2, json_object_get(resp, "e2"), 6);
    if (json_is_integer(settle))
        fprintf(out,
                "\nafter a cut: E2 after k frames (within 5 %% of the steady state from k = "
                "%lld)\n",
                (long long)json_integer_value(settle));
    else
        fprintf(out,
                "\nafter a cut: E2 after k frames (not within 5 %% of the steady state by "
                "k = %zu)\n",
                n);
    for (size_t i = 0; i < n; i += CURVE_PER_LINE) {
        size_t last = i + CURVE_PER_LINE < n ? i + CURVE_PER_LINE : n;
        char range[32];
        snprintf(range, sizeof range, "%zu-%zu", i + 1, last);
        fprintf(out, "  k %-9s", range);
        for (size_t k = i; k < last; k++) {
            char v[40];
            fprintf(out, " %7s", fmt_number(v, sizeof v, json_array_get(curve, k), 4));
        }
        fputc('\n', out);
    }
}

static void print_summary(FILE *out, const json_t *resp)
{
    view_kv kv = {0};
    const json_t *preset = json_object_get(resp, "preset");
    const json_t *blend = json_object_get(resp, "blend");
    const json_t *argmax = json_object_get(resp, "argmax");
    const json_t *f2arg = json_object_get(resp, "f2_argmax");
    const json_t *settle = json_object_get(resp, "frames_to_5pct");
    char a[40], b[40];
    if (preset)
        view_kv_add(&kv, "preset", "%s", view_str(json_object_get(preset, "name")));
    view_kv_add(&kv, "family", "%s", view_str(json_object_get(resp, "family")));
    view_kv_number(&kv, "phases", json_object_get(resp, "phase_count"), 0);
    if (json_is_string(json_object_get(blend, "kind")) &&
        !strcmp(json_string_value(json_object_get(blend, "kind")), "exponential"))
        view_kv_add(&kv, "blend", "exponential, alpha %s",
                    fmt_number(a, sizeof a, json_object_get(blend, "alpha"), FMT_FULL));
    else
        view_kv_add(&kv, "blend", "%s", view_str(json_object_get(blend, "kind")));
    view_kv_number(&kv, "effective samples", json_object_get(resp, "effective_samples"), 2);
    view_kv_number(&kv, "cost_spp", json_object_get(resp, "cost_spp"), 4);
    view_kv_number(&kv, "E2 (worst phase)", json_object_get(resp, "e2"), 6);
    view_kv_add(&kv, "argmax", "phase %s, angle_deg %s",
                fmt_number(a, sizeof a, json_object_get(argmax, "phase"), 0),
                fmt_number(b, sizeof b, json_object_get(argmax, "angle_deg"), 1));
    view_kv_number(&kv, "mean over phases", json_object_get(resp, "mean_phase_e2"), 6);
    view_kv_number(&kv, "F2", json_object_get(resp, "f2"), 6);
    if (f2arg)
        view_kv_number(&kv, "F2 argmax angle", json_object_get(f2arg, "angle_deg"), 1);
    if (json_is_integer(settle))
        view_kv_add(&kv, "frames to 5 %", "%lld", (long long)json_integer_value(settle));
    else
        view_kv_add(&kv, "frames to 5 %", "none within %zu",
                    json_array_size(json_object_get(resp, "after_cut")));
    view_kv_acuity(&kv, resp);
    view_kv_print(out, &kv);
    const char *source = json_string_value(json_object_get(preset, "source"));
    if (source)
        fprintf(out, "source: %s\n", source);
}

void eval_temporal_print(FILE *out, const json_t *resp, bool detail, bool csv)
{
    if (csv) {
        if (detail)
            print_angles(out, resp, true);
        else
            print_phases(out, resp, true);
        return;
    }
    print_summary(out, resp);
    fputc('\n', out);
    print_phases(out, resp, false);
    print_after_cut(out, resp);
    if (detail) {
        fputc('\n', out);
        print_angles(out, resp, false);
    }
}
