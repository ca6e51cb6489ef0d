/* aalab optimize --family F | --pattern FILE [--seeds N] [--max-seconds S]
 *                [--max-iterations N] [--rng-seed K] [--mode weights|positions|both]
 *                [--method NAME] [--executor local|slurm] [--wait]
 *                [--scene S [--size WxH] [--angle DEG] [--blend A]]: optimise for a scene */
#define _POSIX_C_SOURCE 200809L
#include "commands.h"

#include "../exit_codes.h"
#include "../pattern_source.h"
#include "view_util.h"

int optimize_request(const cli_args *a, json_t **req, char *err, size_t errcap)
{
    json_t *r = json_pack("{s:s}", "kind", "optimize");
    if (!r)
        return -1;
    if (a->family) {
        json_object_set_new(r, "family", json_string(a->family));
    } else {
        json_t *pattern;
        if (pattern_argument_load(a->pattern, a, &pattern, NULL, err, errcap)) {
            json_decref(r);
            return -1;
        }
        json_object_set_new(r, "pattern", pattern);
    }
    if (a->has_seeds)
        json_object_set_new(r, "seeds", json_integer(a->seeds));
    if (a->has_max_seconds)
        json_object_set_new(r, "max_seconds", json_real(a->max_seconds));
    if (a->has_max_iterations)
        json_object_set_new(r, "max_iterations", json_integer(a->max_iterations));
    if (a->executor)
        json_object_set_new(r, "executor", json_string(a->executor));
    if (a->has_rng_seed)
        json_object_set_new(r, "rng_seed", json_integer(a->rng_seed));
    if (a->mode)
        json_object_set_new(r, "mode", json_string(a->mode));
    if (a->method)
        json_object_set_new(r, "method", json_string(a->method));
    if (!a->scene && (a->has_blend || a->has_angle || a->width)) {
        snprintf(err, errcap, "--blend, --angle and --size go with --scene");
        json_decref(r);
        return -1;
    }
    if (a->scene) {
        /* The scene objective (proto/job_scene_objective.h): the forms of aalab predict. */
        json_t *o = json_object();
        json_object_set_new(o, "scene",
                            a->has_angle
                                ? json_pack("{s:s, s:f}", "name", a->scene, "angle", a->angle)
                                : json_string(a->scene));
        if (a->width)
            json_object_set_new(o, "size", json_pack("[ii]", a->width, a->height));
        if (a->has_blend)
            json_object_set_new(o, "blend", json_real(a->blend));
        json_object_set_new(r, "objective", o);
    }
    *req = r;
    return 0;
}

int cmd_optimize(cli_session *s)
{
    return job_submit_built(s, "optimize", optimize_request);
}
