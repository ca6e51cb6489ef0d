/* Derived pattern keys: strip before writing, re-derive after reading (job_derived.h). */
#include "job_derived.h"

#include <math.h>
#include <string.h>

#include "codec.h"

static const char *const forms[] = {"kernels", "mirrored", "tile"};

/* An object proto_encode_pattern made: "form" names one of the forms and that key is there. */
static bool is_encoded_pattern(const json_t *v)
{
    const char *form = json_string_value(json_object_get(v, "form"));
    if (!form)
        return false;
    for (size_t i = 0; i < sizeof forms / sizeof forms[0]; i++)
        if (!strcmp(form, forms[i]))
            return json_object_get(v, forms[i]) != NULL;
    return false;
}

static bool has_derived(const json_t *v)
{
    if (json_is_object(v)) {
        if (is_encoded_pattern(v) && json_object_get(v, "kernels_expanded"))
            return true;
        const char *k;
        json_t *m;
        json_object_foreach((json_t *)v, k, m)
        {
            if (has_derived(m))
                return true;
        }
    } else if (json_is_array(v)) {
        for (size_t i = 0; i < json_array_size(v); i++)
            if (has_derived(json_array_get(v, i)))
                return true;
    }
    return false;
}

static void strip(json_t *v)
{
    if (json_is_object(v)) {
        if (is_encoded_pattern(v)) {
            json_object_del(v, "kernels_expanded");
            return;
        }
        const char *k;
        json_t *m;
        json_object_foreach(v, k, m) strip(m);
    } else if (json_is_array(v)) {
        for (size_t i = 0; i < json_array_size(v); i++)
            strip(json_array_get(v, i));
    }
}

json_t *job_derived_stripped(const json_t *v)
{
    if (!v || !has_derived(v))
        return NULL;
    json_t *c = json_deep_copy(v);
    strip(c);
    return c;
}

void job_derived_restore(json_t *v)
{
    if (json_is_object(v)) {
        if (is_encoded_pattern(v)) {
            if (json_object_get(v, "kernels_expanded"))
                return;
            aa_pattern p;
            aa_error err = {0};
            if (proto_decode_pattern(v, 0, &p, "", &err) != AA_OK)
                return;
            json_t *enc = proto_encode_pattern(&p);
            aa_pattern_free(&p);
            json_t *k = json_object_get(enc, "kernels_expanded");
            if (k)
                json_object_set(v, "kernels_expanded", k);
            json_decref(enc);
            return;
        }
        const char *key;
        json_t *m;
        json_object_foreach(v, key, m) job_derived_restore(m);
    } else if (json_is_array(v)) {
        for (size_t i = 0; i < json_array_size(v); i++)
            job_derived_restore(json_array_get(v, i));
    }
}

double job_derived_best_e2(const json_t *best)
{
    const json_t *e2 = json_is_object(best) ? json_object_get(best, "e2") : NULL;
    return json_is_number(e2) ? json_number_value(e2) : NAN;
}

const char *job_derived_family(const json_t *best)
{
    const json_t *p = json_is_object(best) ? json_object_get(best, "pattern") : NULL;
    return json_is_object(p) ? json_string_value(json_object_get(p, "family")) : NULL;
}
