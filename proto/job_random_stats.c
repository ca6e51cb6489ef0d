#include "job_random_stats.h"

#include <string.h>

static const char *const kind_keys[] = {"family", "count", "distribution", NULL};

int proto_decode_random_stats_spec(const json_t *spec, proto_random_stats_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, 0, 30, &s->common, err);
    if (rc)
        return rc;
    rc = proto_spec_family(spec, true, NULL, &s->family, err);
    /* A random pattern must give every pixel's kernel a sample; when a kernel reads only part
     * of the tile (r < s) random positions can leave it empty, and the job would fail late. */
    if (!rc && !s->family.mirrored && s->family.kernel_size < s->family.tile)
        rc = aa_error_set(err, AA_EINVAL, "family",
                          "random patterns of %s can leave a pixel's kernel without samples "
                          "(r < s): use r >= s, e.g. P(%d,%d,n)",
                          s->family.label, s->family.tile * s->family.tile,
                          s->family.tile * s->family.tile);
    json_int_t n = 1000;
    if (!rc)
        rc = proto_spec_integer(spec, "count", 1, 1000000, &n, err);
    s->count = (size_t)n;
    const char *dist = "uniform";
    if (!rc)
        rc = proto_spec_string(spec, "distribution", &dist, err);
    if (!rc && aa_seed_kind_parse(dist, &s->kind))
        rc = aa_error_set(err, AA_EINVAL, "distribution",
                          "must be uniform, jittered, n-rooks, poisson or lloyd");
    if (rc)
        proto_random_stats_spec_free(s);
    return rc;
}

void proto_random_stats_spec_free(proto_random_stats_spec *s)
{
    proto_optimizer_spec_free(&s->common);
}
