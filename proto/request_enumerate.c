/* The enumerate request's decoder (request_enumerate.h). */
#include "request_enumerate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"

static const char *const enumerate_keys[] = {"family", "cost", NULL};

/* "P(4,1+,n)" or "P(4,1+,X)" with X a number (then the cost is X). */
static int parse_family(const json_t *f, double *cost_from_family, aa_error *err)
{
    *cost_from_family = NAN;
    if (!json_is_string(f))
        return aa_error_set(err, AA_EINVAL, "family", "must be a string like \"P(4,1+,n)\"");
    const char *s = json_string_value(f);
    if (strlen(s) != json_string_length(f) || strncmp(s, "P(4,1+,", 7))
        return aa_error_set(err, AA_EINVAL, "family",
                            "only the mirrored family P(4,1+,n) can be enumerated");
    const char *n = s + 7;
    if (!strcmp(n, "n)"))
        return AA_OK;
    char *end;
    double v = strtod(n, &end);
    if (end == n || strcmp(end, ")") || !isfinite(v))
        return aa_error_set(err, AA_EINVAL, "family", "expected P(4,1+,n) or P(4,1+,<cost>)");
    *cost_from_family = v;
    return AA_OK;
}

static int check_cost(double c, const char *field, aa_error *err)
{
    if (!(c > 0) || c > AA_ENUMERATE_MAX_COST)
        return aa_error_set(err, AA_ERANGE, field, "cost must be in (0, %g] samples per pixel",
                            AA_ENUMERATE_MAX_COST);
    if (fabs(c * 4 - round(c * 4)) > 1e-9)
        return aa_error_set(err, AA_EINVAL, field,
                            "mirrored costs are multiples of 0.25 (corner 1/4, edge 1/2, "
                            "interior 1)");
    return AA_OK;
}

int proto_decode_enumerate_request(const json_t *body, proto_enumerate_request *out, aa_error *err)
{
    double fam_cost = NAN, cost = NAN;
    int rc = proto_check_keys(body, enumerate_keys, err, "");
    if (rc)
        return rc;
    const json_t *fj = json_object_get(body, "family");
    const json_t *cj = json_object_get(body, "cost");
    if (!fj)
        rc = aa_error_set(err, AA_EINVAL, "family", "family is required");
    if (!rc)
        rc = parse_family(fj, &fam_cost, err);
    if (!rc && cj) {
        if (!json_is_number(cj))
            rc = aa_error_set(err, AA_EINVAL, "cost", "must be a number");
        else
            cost = json_number_value(cj);
    }
    if (!rc && isnan(cost) && isnan(fam_cost))
        rc = aa_error_set(err, AA_EINVAL, "cost", "cost is required with P(4,1+,n)");
    if (!rc && !isnan(cost))
        rc = check_cost(cost, "cost", err);
    if (!rc && !isnan(fam_cost))
        rc = check_cost(fam_cost, "family", err);
    if (!rc && !isnan(cost) && !isnan(fam_cost) && fabs(cost - fam_cost) > 1e-9)
        rc = aa_error_set(err, AA_EINVAL, "cost", "cost disagrees with the family's n");
    if (!rc)
        out->cost = isnan(cost) ? fam_cost : cost;
    return rc;
}
