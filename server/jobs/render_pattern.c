/* The pattern of a render job: a preset name, or a pattern object (render_pattern.h). */
#include "render_pattern.h"

#include "codec.h"
#include "preset_suggest.h"
#include "aa_pattern.h"
#include "tile_render.h"

int render_pattern_decode(const json_t *j, aa_pattern *out, const char *field, aa_error *err)
{
    if (json_is_string(j) && !aa_preset_find(json_string_value(j)))
        return proto_unknown_preset(err, field, json_string_value(j));
    int rc = proto_pattern_from_preset_name(j, out, field, err);
    if (rc == 1)
        rc = proto_decode_pattern(j, 0, out, field, err);
    return rc;
}
