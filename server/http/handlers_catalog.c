/* GET /v1/presets, /v1/presets/{name}, /v1/filters, /v1/acuity: the built-in catalogue. */
#include <math.h>
#include <string.h>

#include "codec.h"
#include "handlers.h"
#include "aa_pattern.h"

static json_t *preset_json(const aa_preset *pr, bool full)
{
    json_t *o = json_pack("{s:s,s:s,s:o,s:s}", "name", pr->name, "family", pr->family, "cost_spp",
                          proto_real(pr->cost_spp), "source", pr->source);
    if (pr->note)
        json_object_set_new(o, "note", json_string(pr->note));
    json_object_set_new(o, "published_e2",
                        isnan(pr->published_e2) ? json_null() : json_real(pr->published_e2));
    if (!full)
        return o;
    aa_pattern p;
    aa_error err = {0};
    if (aa_pattern_from_preset(&p, pr, &err) == AA_OK) {
        json_object_set_new(o, "pattern", proto_encode_pattern(&p));
        aa_filter f;
        aa_acuity a;
        aa_filter_default(&f);
        aa_acuity_naiman(&a);
        aa_metric_params mp = {.filter = &f, .acuity = &a};
        aa_evaluation ev;
        if (aa_evaluate(&p, &mp, &ev, &err) == AA_OK) {
            json_object_set_new(o, "e2", proto_real(ev.e2));
            json_object_set_new(o, "argmax",
                                json_pack("{s:I,s:f}", "kernel", (json_int_t)ev.argmax_kernel,
                                          "angle_deg", ev.argmax_angle_deg));
            aa_evaluation_free(&ev);
        }
        aa_pattern_free(&p);
    }
    return o;
}

void handle_presets_list(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *a = json_array();
    for (size_t i = 0; i < aa_preset_count(); i++)
        json_array_append_new(a, preset_json(aa_preset_at(i), false));
    api_reply_json(resp, 200, json_pack("{s:o}", "presets", a));
}

void handle_preset_get(api_context *ctx, const api_request *req, api_response *resp,
                       const char *name)
{
    const aa_preset *pr = aa_preset_find(name);
    if (!pr) {
        api_reply_wire(resp, WIRE_NOT_FOUND, "name", "no preset named '%.60s'", name);
        return;
    }
    api_reply_json(resp, 200, preset_json(pr, true));
}

void handle_filters(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *a = json_array();
    for (size_t i = 0; aa_filter_names[i]; i++) {
        aa_filter f;
        if (aa_filter_by_name(&f, aa_filter_names[i], NULL, NULL) == AA_OK) {
            json_t *o = proto_encode_filter(&f);
            json_object_set_new(o, "default", json_boolean(!strcmp(f.name, "mitchell")));
            json_array_append_new(a, o);
        }
    }
    api_reply_json(resp, 200, json_pack("{s:o}", "filters", a));
}

/* One sentence per named table (aa_acuity_names): what the dashboard and the client show. */
static const char *acuity_description(const char *name)
{
    if (!strcmp(name, "naiman"))
        return "Version 2 of the Naiman acuity reconstructed from the published E2 values "
               "(the default): W(0°) = 3.93 and W(45°) = 2.50 pinned, the knots in "
               "between lowered so that L&A Table 3 is reproduced as well as every fixed pattern.";
    if (!strcmp(name, "naiman-envelope"))
        return "Version 1 of that reconstruction: the knots between 0° and 45° just "
               "under the largest values the published fixed patterns allow (same fixed-pattern "
               "E2, P(16,16,4) optima about 5-8 % above L&A Table 3).";
    return "W = 1 at every angle: the plain, unweighted E1.";
}

void handle_acuity(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *tables = json_array();
    for (size_t t = 0; aa_acuity_names[t]; t++) {
        aa_acuity a;
        if (aa_acuity_by_name(&a, aa_acuity_names[t], NULL))
            continue;
        json_t *o = proto_encode_acuity(&a);
        json_object_set_new(o, "version", json_integer(a.version));
        json_object_set_new(o, "description", json_string(acuity_description(a.name)));
        if (t == 0) {
            double angles[AA_MAX_ANGLES];
            size_t count = aa_acuity_default_angles(&a, angles, AA_MAX_ANGLES);
            json_t *defaults = json_array();
            for (size_t i = 0; i < count; i++)
                json_array_append_new(defaults, json_real(angles[i]));
            json_object_set_new(o, "default_angles", defaults);
            json_object_set_new(o, "default", json_true());
        }
        json_array_append_new(tables, o);
    }
    api_reply_json(resp, 200,
                   json_pack("{s:o,s:s}", "tables", tables, "default", aa_acuity_names[0]));
}
