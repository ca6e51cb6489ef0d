/* POST /v1/families/enumerate {"family":"P(4,1+,n)","cost":1.25}: the mirrored configurations
 * of a cost (the optimizer's aa_enumerate_mirrored, server/engine/pattern/enumerate.h). The request is
 * validated here. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "handlers.h"

#include "aa_pattern.h"
#include "eval_cache.h"
#include "enumerate_encode.h"

#define ENUMERATE_MAX_COST 16.0

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
    if (!(c > 0) || c > ENUMERATE_MAX_COST)
        return aa_error_set(err, AA_ERANGE, field, "cost must be in (0, %g] samples per pixel",
                            ENUMERATE_MAX_COST);
    if (fabs(c * 4 - round(c * 4)) > 1e-9)
        return aa_error_set(err, AA_EINVAL, field,
                            "mirrored costs are multiples of 0.25 (corner 1/4, edge 1/2, "
                            "interior 1)");
    return AA_OK;
}

void handle_enumerate(api_context *ctx, const api_request *req, api_response *resp)
{
    json_t *body = api_parse_body(req, resp);
    if (!body)
        return;
    aa_error err = {0};
    double fam_cost = NAN, cost = NAN;
    int rc = api_reject_unknown(body, enumerate_keys, "", resp);
    if (rc) {
        json_decref(body);
        return;
    }
    const json_t *fj = json_object_get(body, "family");
    const json_t *cj = json_object_get(body, "cost");
    if (!fj)
        rc = aa_error_set(&err, AA_EINVAL, "family", "family is required");
    if (!rc)
        rc = parse_family(fj, &fam_cost, &err);
    if (!rc && cj) {
        if (!json_is_number(cj))
            rc = aa_error_set(&err, AA_EINVAL, "cost", "must be a number");
        else
            cost = json_number_value(cj);
    }
    if (!rc && isnan(cost) && isnan(fam_cost))
        rc = aa_error_set(&err, AA_EINVAL, "cost", "cost is required with P(4,1+,n)");
    if (!rc && !isnan(cost))
        rc = check_cost(cost, "cost", &err);
    if (!rc && !isnan(fam_cost))
        rc = check_cost(fam_cost, "family", &err);
    if (!rc && !isnan(cost) && !isnan(fam_cost) && fabs(cost - fam_cost) > 1e-9)
        rc = aa_error_set(&err, AA_EINVAL, "cost", "cost disagrees with the family's n");
    json_decref(body);
    if (rc) {
        api_reply_aa_error(resp, &err);
        return;
    }
    if (isnan(cost))
        cost = fam_cost;
    /* The answer depends on the cost alone; at cost 16 it is 29,529 configurations (4.4 MB,
     * 0.17 s to enumerate and encode), so it is kept in the answer cache. */
    char key[64];
    int key_len = snprintf(key, sizeof key, "enumerate P(4,1+,n) %.2f", cost);
    eval_cache *cache = api_context_eval_cache(ctx);
    char *hit = NULL;
    size_t hit_len = 0;
    if (eval_cache_get(cache, key, (size_t)key_len, &hit, &hit_len)) {
        api_reply_owned(resp, 200, hit, hit_len);
        return;
    }
    aa_mirrored_config *configs = NULL;
    size_t count = 0;
    rc = aa_enumerate_mirrored(cost, &configs, &count, &err);
    if (rc) {
        api_reply_aa_error(resp, &err);
        return;
    }
    api_reply_json(resp, 200, enumerate_encode(cost, configs, count));
    free(configs);
    if (resp->status == 200)
        eval_cache_put(cache, key, (size_t)key_len, resp->body, resp->body_len);
}
