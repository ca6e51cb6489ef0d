#include "render_spec.h"

#include <string.h>

#include "codec.h"

static int check_keys(const json_t *spec, const char *const *kind_keys, unsigned fields,
                      aa_error *err)
{
    static const char *const shared[] = {"scene", "size", "reference", NULL};
    static const char *const acuity[] = {"acuity", NULL}, *const tiles[] = {"tiles", NULL};
    static const char *const none[] = {NULL};
    const char *const *const lists[] = {shared, fields & RENDER_SPEC_ACUITY ? acuity : none,
                                        fields & RENDER_SPEC_TILES ? tiles : none, kind_keys, NULL};
    return proto_check_keys_in(spec, lists, err, "");
}

int render_spec_decode(const json_t *spec, const char *const *kind_keys, unsigned fields,
                       render_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    s->tiles = true;
    int rc = check_keys(spec, kind_keys, fields, err);
    if (!rc)
        rc = tile_decode_scene_request(spec, &s->scene, err);
    if (!rc)
        rc = tile_decode_reference(json_object_get(spec, "reference"), &s->ref, "reference", err);
    if (!rc)
        rc = proto_decode_acuity(json_object_get(spec, "acuity"), &s->acuity, "acuity", err);
    json_t *tiles = json_object_get(spec, "tiles");
    if (!rc && tiles) {
        if (!json_is_boolean(tiles))
            rc = aa_error_set(err, AA_EINVAL, "tiles", "must be true or false");
        else
            s->tiles = json_is_true(tiles);
    }
    return rc;
}
