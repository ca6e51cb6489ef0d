#include "enumerate_encode.h"

#include <assert.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "codec.h"

/* A short human label, e.g. "1 corner, 2 edges (bottom, right)". */
static void describe(const aa_mirrored_config *c, char *out, size_t cap)
{
    static const char *const edge_names[4] = {"bottom", "right", "top", "left"};
    int corners = 0, edges = 0;
    for (int i = 0; i < 4; i++) {
        corners += c->corners[i];
        edges += c->edges[i];
    }
    size_t n = (size_t)snprintf(out, cap, "%d corner%s, %d edge sample%s", corners,
                                corners == 1 ? "" : "s", edges, edges == 1 ? "" : "s");
    if (edges && n < cap) {
        n += (size_t)snprintf(out + n, cap - n, " (");
        bool first = true;
        for (int i = 0; i < 4 && n < cap; i++) {
            if (!c->edges[i])
                continue;
            n += (size_t)snprintf(out + n, cap - n, "%s%s%s", first ? "" : ", ", edge_names[i],
                                  c->edges[i] > 1 ? " x2+" : "");
            first = false;
        }
        if (n < cap)
            n += (size_t)snprintf(out + n, cap - n, ")");
    }
    if (c->interior && n < cap)
        snprintf(out + n, cap - n, ", %d interior", c->interior);
}

json_t *enumerate_encode(double cost, const aa_mirrored_config *configs, size_t count)
{
    assert(configs || !count);
    json_t *list = json_array();
    if (!list)
        return NULL;
    for (size_t i = 0; i < count; i++) {
        const aa_mirrored_config *c = &configs[i];
        int samples = c->interior;
        for (int k = 0; k < 4; k++)
            samples += c->corners[k] + c->edges[k];
        char label[128];
        describe(c, label, sizeof label);
        json_t *o = json_pack(
            "{s:[I,I,I,I],s:[I,I,I,I],s:I,s:I,s:s}", "corners", (json_int_t)c->corners[0],
            (json_int_t)c->corners[1], (json_int_t)c->corners[2], (json_int_t)c->corners[3],
            "edges", (json_int_t)c->edges[0], (json_int_t)c->edges[1], (json_int_t)c->edges[2],
            (json_int_t)c->edges[3], "interior", (json_int_t)c->interior, "samples",
            (json_int_t)samples, "label", label);
        if (!o || json_array_append_new(list, o)) {
            json_decref(list);
            return NULL;
        }
    }
    char family[48];
    snprintf(family, sizeof family, "P(4,1+,%g)", cost);
    return json_pack("{s:s,s:o,s:I,s:o,s:s}", "family", family, "cost", proto_real(cost), "count",
                     (json_int_t)count, "configurations", list, "index",
                     "corners/edges counted counterclockwise from the bottom-left corner / "
                     "bottom edge");
}
