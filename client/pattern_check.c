/* Local pattern check with the shared codec (proto/codec.h): the client accepts exactly the
 * files the daemon accepts and names the same JSON path ("pattern.kernels[0][1][2]"). */
#include "pattern_source.h"

#include <stdio.h>
#include <string.h>

#include "codec.h"

int pattern_check(const json_t *pattern, char *err, size_t errcap)
{
    aa_pattern p;
    aa_error e = {0};
    /* --set all (analyze): the daemon reads every set; set 0 here stands for the file. */
    const json_t *form = json_object_get(pattern, "points");
    json_t *copy = NULL;
    if (json_is_string(json_object_get(form, "set"))) {
        copy = json_deep_copy(pattern);
        json_object_set_new(json_object_get(copy, "points"), "set", json_integer(0));
        pattern = copy;
    }
    int rc = proto_decode_pattern(pattern, 0, &p, "pattern", &e);
    json_decref(copy);
    if (rc == AA_OK) {
        aa_pattern_free(&p);
        return 0;
    }
    return pattern_check_refusal(rc, &e, err, errcap);
}

int pattern_check_refusal(int rc, const struct aa_error *e, char *err, size_t errcap)
{
    if (e->field[0])
        snprintf(err, errcap, "field %s: %s", e->field,
                 e->message[0] ? e->message : aa_strerror(rc));
    else
        snprintf(err, errcap, "%s", e->message[0] ? e->message : aa_strerror(rc));
    return -1;
}
