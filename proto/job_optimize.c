#include "job_optimize.h"

#include <string.h>

#include "codec.h"

static const char *const kind_keys[] = {"family", "pattern", "seeds", "distributions", NULL};

int proto_decode_optimize_spec(const json_t *spec, proto_optimize_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, PROTO_OPT_MODE | PROTO_OPT_GRID, 30,
                                         &s->common, err);
    if (rc)
        return rc;
    json_t *pattern = json_object_get(spec, "pattern");
    rc = proto_spec_family(spec, false, &s->have_family, &s->family, err);
    if (!rc && s->have_family == (pattern != NULL))
        rc = aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and pattern");
    if (!rc && pattern)
        rc = proto_decode_pattern(pattern, 0, &s->pattern, "pattern", err);
    json_int_t seeds = s->have_family ? 64 : 1;
    if (!rc)
        rc = proto_spec_integer(spec, "seeds", 1, 100000, &seeds, err);
    if (!rc && !s->have_family && seeds != 1)
        rc = aa_error_set(err, AA_EINVAL, "seeds", "a given pattern is one seed");
    s->seeds = (size_t)seeds;
    if (!rc)
        rc = proto_spec_distributions(spec, s->kinds, &s->kind_count, err);
    if (rc)
        proto_optimize_spec_free(s);
    return rc;
}

void proto_optimize_spec_free(proto_optimize_spec *s)
{
    proto_optimizer_spec_free(&s->common);
    aa_pattern_free(&s->pattern);
}
