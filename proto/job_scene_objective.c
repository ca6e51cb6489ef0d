#include "job_scene_objective.h"

#include <string.h>

#include "codec.h"
#include "codec_internal.h"
#include "codec_scene.h"
#include "job_result_util.h"

int proto_decode_scene_objective(const json_t *spec, proto_scene_objective *out, aa_error *err)
{
    static const char *const keys[] = {"scene", "size", "blend", NULL};
    memset(out, 0, sizeof *out);
    const json_t *o = json_object_get(spec, "objective");
    if (!o)
        return AA_OK;
    if (!json_is_object(o))
        return aa_error_set(err, AA_EINVAL, "objective",
                            "an object {\"scene\": ..., \"blend\": ...}");
    int rc = proto_check_keys(o, keys, err, "objective");
    if (rc)
        return rc;
    if (!json_object_get(o, "scene"))
        return aa_error_set(err, AA_EINVAL, "objective.scene", "required");
    if ((rc = proto_decode_scene_request(o, &out->scene, err))) {
        proto_prefix_error(err, "objective");
        return rc;
    }
    if (aa_scene_shape_is_animation(out->scene.shape))
        return aa_error_set(err, AA_EINVAL, "objective.scene",
                            "an animation has one histogram per frame: give a still scene");
    const json_t *b = json_object_get(o, "blend");
    out->blend = 0;
    if (b) {
        if (!json_is_number(b) || !(json_number_value(b) >= 0 && json_number_value(b) <= 1))
            return aa_error_set(err, AA_EINVAL, "objective.blend", "a number in [0, 1]");
        out->blend = json_number_value(b);
    }
    out->enabled = true;
    return AA_OK;
}

json_t *proto_encode_scene_objective_result(const proto_scene_objective_result *r)
{
    return json_pack(
        "{s:o,s:o,s:o,s:o,s:o,s:{s:o,s:o}}", "scene", proto_encode_scene(&r->spec.scene), "blend",
        proto_real(r->spec.blend), "objective", proto_real(r->objective), "predicted_rmse",
        proto_real(r->predicted_rmse), "e2", proto_real(r->e2), "e2_optimum", "predicted_rmse",
        proto_real(r->optimum_predicted_rmse), "e2", proto_real(r->optimum_e2));
}

int proto_decode_scene_objective_result(const json_t *j, proto_scene_objective_result *out,
                                        aa_error *err)
{
    static const char *const keys[] = {"scene", "blend",      "objective", "predicted_rmse",
                                       "e2",    "e2_optimum", NULL};
    static const char *const opt_keys[] = {"predicted_rmse", "e2", NULL};
    memset(out, 0, sizeof *out);
    int rc = proto_check_keys(j, keys, err, "scene_objective");
    if (!rc)
        rc = proto_decode_scene(json_object_get(j, "scene"), &out->spec.scene,
                                "scene_objective.scene", err);
    if (!rc)
        rc = proto_result_real(j, "blend", &out->spec.blend, err);
    if (!rc)
        rc = proto_result_real(j, "objective", &out->objective, err);
    if (!rc)
        rc = proto_result_real(j, "predicted_rmse", &out->predicted_rmse, err);
    if (!rc)
        rc = proto_result_real(j, "e2", &out->e2, err);
    const json_t *opt = json_object_get(j, "e2_optimum");
    if (!rc && !json_is_object(opt))
        rc = aa_error_set(err, AA_EINVAL, "scene_objective.e2_optimum", "an object");
    if (!rc)
        rc = proto_check_keys(opt, opt_keys, err, "scene_objective.e2_optimum");
    if (!rc)
        rc = proto_result_real(opt, "predicted_rmse", &out->optimum_predicted_rmse, err);
    if (!rc)
        rc = proto_result_real(opt, "e2", &out->optimum_e2, err);
    out->spec.enabled = !rc;
    return rc;
}
