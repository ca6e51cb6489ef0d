/* aalab presets [NAME] */
#include "commands.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../exit_codes.h"
#include "../table.h"
#include "view_util.h"

/* published_e2 is a number, or {"laine-aila-table-2": 0.439} naming its source. */
static const json_t *published_e2(const json_t *preset)
{
    const json_t *v = json_object_get(preset, "published_e2");
    if (json_is_object(v)) {
        const char *key;
        json_t *inner;
        json_object_foreach((json_t *)v, key, inner)
        {
            if (json_is_number(inner))
                return inner;
        }
        return NULL;
    }
    return v;
}

void presets_print(FILE *out, const json_t *resp, bool csv)
{
    const char *headers[] = {"name", "family", "cost_spp", "published_e2", "source"};
    table *t = table_new(5, headers);
    if (!t)
        return;
    size_t i;
    json_t *p;
    json_array_foreach(list_member(resp, "presets"), i, p)
    {
        char cost[32], e2[32];
        const char *cells[] = {fmt_string(json_object_get(p, "name")),
                               fmt_string(json_object_get(p, "family")),
                               fmt_number(cost, sizeof cost, json_object_get(p, "cost_spp"), 2),
                               fmt_number(e2, sizeof e2, published_e2(p), 3),
                               fmt_string(json_object_get(p, "source"))};
        table_add_row(t, cells);
    }
    table_write(t, out, csv);
    table_free(t);
}

int cmd_presets(cli_session *s)
{
    char path[256];
    const char *name = s->args->target;
    if (name) {
        char *escaped = url_escape_segment(name);
        if (!escaped)
            return EXIT_USAGE;
        snprintf(path, sizeof path, "/v1/presets/%s", escaped);
        free(escaped);
    } else {
        snprintf(path, sizeof path, "/v1/presets");
    }
    return cli_show(s, "GET", path, NULL, name ? print_flat_as : presets_print);
}
