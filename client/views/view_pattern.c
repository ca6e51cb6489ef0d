/* A job's best pattern: where each kernel's samples sit and what they weigh. */
#include "job_views.h"

#include "../cli.h"
#include "../table.h"
#include "view_kv.h"

void view_pattern(FILE *out, const json_t *pattern, bool csv)
{
    char spp[32];
    const json_t *cost = json_object_get(pattern, "cost_spp");
    if (!cost)
        cost = json_object_get(pattern, "samples_per_pixel"); /* animation's {family, spp} */
    const json_t *kernels = json_object_get(pattern, "kernels_expanded");
    if (!csv) {
        const char *form = json_string_value(json_object_get(pattern, "form"));
        fprintf(out, "best pattern  %s, %s spp", view_str(json_object_get(pattern, "family")),
                fmt_number(spp, sizeof spp, cost, fmt_decimals(csv, 2)));
        if (form)
            fprintf(out, ", %s form, %zu kernels", form, json_array_size(kernels));
        fputc('\n', out);
        if (!json_is_array(kernels))
            return;
    }
    const char *headers[] = {"kernel", "sample", "x", "y", "weight"};
    table *t = table_new(5, headers);
    if (!t)
        return;
    size_t k, i;
    json_t *kernel, *s;
    json_array_foreach(kernels, k, kernel)
    {
        json_array_foreach(kernel, i, s)
        {
            char kb[32], ib[32], x[32], y[32], w[32];
            snprintf(kb, sizeof kb, "%zu", k);
            snprintf(ib, sizeof ib, "%zu", i);
            const char *cells[] = {
                kb, ib, fmt_number(x, sizeof x, json_array_get(s, 0), fmt_decimals(csv, 6)),
                fmt_number(y, sizeof y, json_array_get(s, 1), fmt_decimals(csv, 6)),
                fmt_number(w, sizeof w, json_array_get(s, 2), fmt_decimals(csv, 6))};
            table_add_row(t, cells);
        }
    }
    table_write(t, out, csv);
    table_free(t);
}
