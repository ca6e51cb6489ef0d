#include "job_family_sweep.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "enumerate.h"

static const char *const kind_keys[] = {"family", "cost", "seeds_per_config", "distributions",
                                        NULL};

int proto_decode_family_sweep_spec(const json_t *spec, proto_family_sweep_spec *s, aa_error *err)
{
    memset(s, 0, sizeof *s);
    int rc = proto_optimizer_spec_decode(spec, kind_keys, PROTO_OPT_MODE | PROTO_OPT_GRID, 60,
                                         &s->common, err);
    if (rc)
        return rc;
    bool have_family = false;
    aa_family fam;
    double cost = NAN;
    rc = proto_spec_family(spec, false, &have_family, &fam, err);
    if (!rc)
        rc = proto_spec_number(spec, "cost", 0.25, AA_ENUMERATE_MAX_COST, &cost, err);
    if (!rc && have_family == !isnan(cost))
        rc = aa_error_set(err, AA_EINVAL, "family", "give exactly one of family and cost");
    if (!rc && have_family) {
        if (!fam.mirrored)
            rc = aa_error_set(err, AA_EINVAL, "family", "the sweep enumerates P(4,1+,n)");
        cost = fam.cost;
        snprintf(s->family, sizeof s->family, "%s", fam.label);
    }
    if (!rc) {
        aa_mirrored_config *list;
        size_t n;
        rc = aa_enumerate_mirrored(cost, &list, &n, err); /* validates the cost ("cost") */
        if (!rc)
            free(list);
    }
    s->cost = cost;
    json_int_t k = 8;
    if (!rc)
        rc = proto_spec_integer(spec, "seeds_per_config", 1, 10000, &k, err);
    s->per_config = (size_t)k;
    if (!rc)
        rc = proto_spec_distributions(spec, s->kinds, &s->kind_count, err);
    if (rc)
        proto_family_sweep_spec_free(s);
    return rc;
}

void proto_family_sweep_spec_free(proto_family_sweep_spec *s)
{
    proto_optimizer_spec_free(&s->common);
}
