/* Pieces both temporal kinds print: the blend of a sequence, a long list of numbers on a few
 * lines, and a sequence's offsets. */
#include "view_temporal.h"

#include <stdio.h>

#include "../cli.h"

const char *view_blend_text(char *buf, size_t cap, const json_t *blend)
{
    const char *kind = json_string_value(json_object_get(blend, "kind"));
    const json_t *alpha = json_object_get(blend, "alpha");
    if (!kind)
        snprintf(buf, cap, "-");
    else if (json_is_number(alpha))
        snprintf(buf, cap, "%s, alpha %.4g", kind, json_number_value(alpha));
    else
        snprintf(buf, cap, "%s", kind);
    return buf;
}

void view_number_lines(FILE *out, const char *label, const json_t *values, int first, int decimals)
{
    /* At most 4 lines of 10: a longer list is shown every stride-th value, which the heading
     * says, so `aalab job ID` stays short (issue 34: at most 60 lines). */
    enum { PER_LINE = 10, MAX_SHOWN = 40 };
    size_t n = json_array_size(values);
    size_t stride = (n + MAX_SHOWN - 1) / MAX_SHOWN;
    if (stride < 1)
        stride = 1;
    if (stride == 1)
        fprintf(out, "%s (%zu values, from %d)\n", label, n, first);
    else
        fprintf(out, "%s (%zu values, one every %zu from %d)\n", label, n, stride, first);
    size_t shown = 0;
    for (size_t i = 0; i < n; i += stride) {
        char v[32];
        if (shown % PER_LINE == 0)
            fputs(shown ? "\n " : " ", out);
        fprintf(out, " %8s", fmt_number(v, sizeof v, json_array_get(values, i), decimals));
        shown++;
    }
    fputc('\n', out);
}

void view_sequence(FILE *out, const json_t *temporal, bool full)
{
    const json_t *jitter = json_object_get(temporal, "jitter");
    size_t n = json_array_size(jitter);
    char blend[96], range[32];
    fprintf(out, "best sequence  T(%zu), blend %s, jitter_range %s\n", n,
            view_blend_text(blend, sizeof blend, json_object_get(temporal, "blend")),
            fmt_number(range, sizeof range, json_object_get(temporal, "jitter_range"), 4));
    /* Compactly: the first 8 offsets, 4 to a line; --pattern: all of them, one a line. */
    size_t shown = full ? n : (n < 8 ? n : 8);
    if (full)
        fputs("frame           x           y\n", out);
    for (size_t i = 0; i < shown; i++) {
        const json_t *o = json_array_get(jitter, i);
        double x = json_number_value(json_array_get(o, 0));
        double y = json_number_value(json_array_get(o, 1));
        if (full)
            fprintf(out, "%5zu  %10.6f  %10.6f\n", i, x, y);
        else
            fprintf(out, "%s%2zu (%+.4f, %+.4f)", i % 4 == 0 ? (i ? "\n  " : "  ") : "  ", i, x, y);
    }
    if (!full) {
        fputc('\n', out);
        if (shown < n)
            fprintf(out, "  ... %zu more ('aalab job ID --pattern' lists all %zu)\n", n - shown, n);
    }
}
