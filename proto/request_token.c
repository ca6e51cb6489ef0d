/* The token request's decoder (request_token.h). */
#include "request_token.h"

#include <string.h>

#include "codec.h"

static const char *const token_keys[] = {"label", NULL};

int proto_decode_token_request(const json_t *body, proto_token_request *out, aa_error *err)
{
    out->label = NULL;
    int rc = proto_check_keys(body, token_keys, err, "");
    if (rc)
        return rc;
    json_t *lj = json_object_get(body, "label");
    if (lj && (!json_is_string(lj) || json_string_length(lj) > PROTO_TOKEN_LABEL_MAX ||
               strlen(json_string_value(lj)) != json_string_length(lj)))
        return aa_error_set(err, AA_EINVAL, "label", "label must be a string of at most %d bytes",
                            PROTO_TOKEN_LABEL_MAX);
    out->label = lj ? json_string_value(lj) : NULL;
    return AA_OK;
}
