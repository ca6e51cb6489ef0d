/* Exports of a temporal pattern (export_temporal.h). */
#define _POSIX_C_SOURCE 200809L
#include "export_temporal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec_internal.h"

bool proto_jitter_format_parse(const char *name, bool *hlsl)
{
    if (!name)
        return false;
    if (!strcmp(name, "jitter-c") || !strcmp(name, "jitter-hlsl")) {
        *hlsl = !strcmp(name, "jitter-hlsl");
        return true;
    }
    return false;
}

/* A float literal with 9 significant digits (a float reads back exactly; the exact doubles are
 * in the first line's wire form), always with a decimal point ("0.0", not "0"), and C's f
 * suffix when asked. */
static const char *literal(char buf[48], double v, bool suffix)
{
    int n = snprintf(buf, 32, "%.9g", v);
    if (!strpbrk(buf, ".e"))
        n += snprintf(buf + n, 8, ".0");
    if (suffix)
        snprintf(buf + n, 8, "f");
    return buf;
}

static void write_table(FILE *f, const proto_temporal *t, const double *age, bool hlsl)
{
    size_t n = t->count;
    bool box = t->blend.kind == AA_BLEND_BOX;
    char a[48], b[48];
    if (hlsl) {
        fprintf(f, "static const uint AalabJitterCount = %zu;\n", n);
        fprintf(f, "static const float2 AalabJitter[%zu] = {\n", n);
        for (size_t i = 0; i < n; i++)
            fprintf(f, "    float2(%s, %s),\n", literal(a, t->jitter[i].x, false),
                    literal(b, t->jitter[i].y, false));
        fprintf(f, "};\n");
        if (box)
            fprintf(f, "static const bool AalabBlendBox = true; /* 1/N each over the period */\n");
        else
            fprintf(f, "static const float AalabBlendAlpha = %s;\n",
                    literal(a, t->blend.alpha, false));
        fprintf(f, "static const float AalabAgeWeight[%zu] = {\n", n);
        for (size_t j = 0; j < n; j++)
            fprintf(f, "    %s,\n", literal(a, age[j], false));
        fprintf(f, "};\n");
        return;
    }
    fprintf(f, "#define AALAB_JITTER_COUNT %zu\n", n);
    fprintf(f, "static const float aalab_jitter[AALAB_JITTER_COUNT][2] = {\n");
    for (size_t i = 0; i < n; i++)
        fprintf(f, "    {%s, %s},\n", literal(a, t->jitter[i].x, true),
                literal(b, t->jitter[i].y, true));
    fprintf(f, "};\n");
    if (box)
        fprintf(f, "#define AALAB_BLEND_BOX 1 /* 1/N each over the period */\n");
    else
        fprintf(f, "static const float aalab_blend_alpha = %s;\n",
                literal(a, t->blend.alpha, true));
    fprintf(f, "static const float aalab_age_weight[AALAB_JITTER_COUNT] = {\n");
    for (size_t j = 0; j < n; j++)
        fprintf(f, "    %s,\n", literal(a, age[j], true));
    fprintf(f, "};\n");
}

char *proto_export_jitter_text(const proto_temporal *t, bool hlsl, size_t *len, aa_error *err)
{
    double *age = malloc(t->count * sizeof *age);
    if (!age) {
        aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    int rc = aa_blend_weights(&t->blend, t->count, age, err);
    json_t *wire = rc ? NULL : proto_encode_temporal(t);
    char *json = wire ? json_dumps(wire, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
    json_decref(wire);
    char *text = NULL;
    size_t size = 0;
    FILE *f = json ? open_memstream(&text, &size) : NULL;
    if (f) {
        fprintf(f, "// aalab-temporal %s\n", json);
        fprintf(f,
                "// A TAA jitter sequence (docs/temporal.md): frame t offsets the projection by "
                "jitter[t mod N] pixels\n"
                "// from the pixel centre (aalab's pattern coordinates), the history blends "
                "%s.\n"
                "// AgeWeight[j]: steady-state weight of the frame j frames old.\n",
                t->blend.kind == AA_BLEND_BOX ? "1/N of each of the last N frames"
                                              : "alpha * frame + (1 - alpha) * history");
        if (t->has_frame || t->has_resolve)
            fprintf(f,
                    "// Each frame also takes the frame pattern's samples%s (in the first "
                    "line's wire form).\n",
                    t->has_resolve ? " and resolves them with the resolve filter" : "");
        write_table(f, t, age, hlsl);
        if (fclose(f)) {
            free(text);
            text = NULL;
        }
    }
    free(age);
    free(json);
    if (!text) {
        if (!rc)
            aa_error_set(err, AA_ENOMEM, "", "out of memory");
        return NULL;
    }
    *len = size;
    return text;
}

int proto_temporal_phase_pattern(const proto_temporal *t, size_t phase, aa_pattern *out,
                                 aa_error *err)
{
    memset(out, 0, sizeof *out);
    if (phase >= t->count)
        return aa_error_set(err, AA_EINVAL, "phase", "must be 0 to %zu (N - 1)", t->count - 1);
    aa_temporal built;
    aa_temporal_spec ts = proto_temporal_spec(t);
    int rc = aa_temporal_build(&built, &ts, err);
    if (rc)
        return rc;
    size_t G = built.group_count;
    aa_sample **kernels = calloc(G, sizeof *kernels);
    size_t *counts = calloc(G, sizeof *counts);
    rc = kernels && counts ? AA_OK : aa_error_set(err, AA_ENOMEM, "", "out of memory");
    for (size_t g = 0; !rc && g < G; g++) {
        kernels[g] = malloc(built.groups[g].count * sizeof **kernels);
        if (!kernels[g])
            rc = aa_error_set(err, AA_ENOMEM, "", "out of memory");
        else
            counts[g] = aa_temporal_phase_kernel(&built, g, phase, kernels[g]);
    }
    /* The phase weights sum to 1 up to rounding: normalised like any kernel within 1e-9. */
    if (!rc)
        rc = aa_pattern_from_kernels(out, (const aa_sample *const *)kernels, counts, G,
                                     AA_PATTERN_NORMALIZE, err);
    for (size_t g = 0; kernels && g < G; g++)
        free(kernels[g]);
    free(kernels);
    free(counts);
    aa_temporal_free(&built);
    return rc;
}
