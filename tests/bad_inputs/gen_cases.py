import json
import os
C = []
EV = "/v1/evaluate"
JT = {"Content-Type": "application/json"}
def case(name, status, field=None, method="POST", path=EV, body=None, body_json=None, headers=None,
         gen=None, via=None, setup=None, check=None, forbid_body=None, body_hex=None, raw=None):
    c = {"name": name, "method": method, "path": path}
    h = dict(JT) if method in ("POST", "PUT") and headers is None else (headers or {})
    if h: c["headers"] = h
    if body is not None: c["body"] = body
    if body_json is not None: c["body_json"] = body_json
    if body_hex is not None: c["body_hex"] = body_hex
    if gen is not None: c["gen"] = gen
    if raw is not None: c["raw"] = raw
    if via: c["via"] = via
    if setup: c["setup"] = setup
    if check: c["check"] = check
    if forbid_body: c["forbid_body"] = forbid_body
    c["status"] = status
    c["field"] = field
    assert name not in [x["name"] for x in C], name
    C.append(c)

def ev(name, status, field, pattern=None, **extra):
    b = {"pattern": pattern if pattern is not None else {"preset": "rgss"}}
    b.update(extra)
    case(name, status, field, body_json=b)
def evp(name, status, field, pattern): ev(name, status, field, pattern=pattern)
OK = {"e2_finite": True}

# --- malformed / truncated JSON
for n, b in [("empty_body", ""), ("whitespace_only", "   \n\t "), ("lone_brace", "{"),
             ("truncated_after_key", '{"pattern":'), ("truncated_in_object", '{"pattern":{"preset":"rgss"}'),
             ("truncated_in_string", '{"pattern":{"preset":"rgs'), ("trailing_garbage", '{"pattern":{"preset":"rgss"}} junk'),
             ("two_documents", '{"pattern":{"preset":"rgss"}}{"pattern":{"preset":"rgss"}}'),
             ("extra_closing_brace", '{"pattern":{"preset":"rgss"}}}'), ("single_quotes", "{'pattern':{'preset':'rgss'}}"),
             ("unquoted_key", '{pattern:{"preset":"rgss"}}'), ("trailing_comma", '{"pattern":{"preset":"rgss",}}'),
             ("comment", '/* c */ {"pattern":{"preset":"rgss"}}'), ("missing_colon", '{"pattern" {"preset":"rgss"}}'),
             ("bare_word", "pattern"), ("bom_prefix", '\ufeff{"pattern":{"preset":"rgss"}}'),
             ("lone_surrogate_escape", '{"pattern":{"preset":"\\ud800"}}'), ("bad_escape", '{"pattern":{"preset":"\\q"}}'),
             ("control_char_in_string", '{"pattern":{"preset":"rg\tss"}}'), ("leading_zero_number", '{"pattern":{"kernels":[[[00,0,1]]]}}'),
             ("plus_sign_number", '{"pattern":{"kernels":[[[+1,0,1]]]}}'), ("hex_number", '{"pattern":{"kernels":[[[0x1,0,1]]]}}'),
             ("dot_number", '{"pattern":{"kernels":[[[.5,0,1]]]}}')]:
    case("json_" + n, 400, None, body=b)
case("json_invalid_utf8", 400, None, body_hex="7b227061747465726e223a7b22707265736574223a22ff fe227d7d".replace(" ", ""))
case("json_deep_nesting_100k", 400, None, gen={"kind": "nest", "depth": 100000})
# --- top level not an object
for n, b in [("array", "[]"), ("null", "null"), ("true", "true"), ("number", "1"), ("string", '"pattern"'),
             ("array_of_request", '[{"pattern":{"preset":"rgss"}}]')]:
    case("toplevel_" + n, 400, None, body=b)
# --- duplicate keys
case("dup_toplevel_pattern", 400, [None, "pattern"], body='{"pattern":{"preset":"rgss"},"pattern":{"preset":"quincunx"}}')
case("dup_preset", 400, [None, "pattern.preset"], body='{"pattern":{"preset":"rgss","preset":"quincunx"}}')
case("dup_filter_B", 400, [None, "filter.B"], body='{"pattern":{"preset":"rgss"},"filter":{"name":"mitchell","B":0.3,"B":0.5}}')
case("dup_job_kind", 400, [None, "kind"], path="/v1/jobs", body='{"kind":"sleep","kind":"optimize","seconds":0}')
# --- unknown fields
ev("unknown_toplevel", 400, "bogus", bogus=1)
ev("unknown_toplevel_case", 400, "Pattern", Pattern={"preset": "rgss"})
evp("unknown_in_pattern", 400, "pattern.bogus", {"preset": "rgss", "bogus": True})
ev("unknown_in_filter", 400, "filter.bogus", filter={"name": "mitchell", "bogus": 1})
ev("unknown_in_acuity", 400, "acuity.bogus", acuity={"name": "naiman", "bogus": 1})
evp("two_pattern_forms", 400, ["pattern", "pattern.kernels", "pattern.preset"], {"preset": "rgss", "kernels": [[[0, 0, 1]]]})
evp("empty_pattern_object", 400, "pattern", {})
case("missing_pattern", 400, "pattern", body_json={})
case("unknown_in_job", 400, "bogus", path="/v1/jobs", body_json={"kind": "sleep", "seconds": 0, "bogus": 1})
case("unknown_in_render", 400, "bogus", path="/v1/render", body_json={"pattern": {"preset": "rgss"}, "scene": "siemens-star", "size": [16, 16], "bogus": 1})
case("unknown_in_enumerate", 400, "bogus", path="/v1/families/enumerate", body_json={"family": "P(4,1+,n)", "cost": 1.25, "bogus": 1})
# --- wrong types
ev("type_pattern_string", 400, "pattern", pattern="rgss")
ev("type_pattern_array", 400, "pattern", pattern=[])
ev("type_pattern_null", 400, "pattern", pattern=None) if False else case("type_pattern_null", 400, "pattern", body='{"pattern":null}')
evp("type_preset_number", 400, "pattern.preset", {"preset": 5})
evp("type_kernels_object", 400, "pattern.kernels", {"kernels": {}})
evp("type_sample_coord_string", 400, "pattern.kernels[0][0][0]", {"kernels": [[["a", 0, 1]]]})
evp("type_sample_coord_null", 400, "pattern.kernels[0][0][1]", {"kernels": [[[0, None, 1]]]})
evp("type_sample_weight_bool", 400, "pattern.kernels[0][0][2]", {"kernels": [[[0, 0, True]]]})
evp("sample_two_elements", 400, "pattern.kernels[0][0]", {"kernels": [[[0, 0]]]})
evp("sample_four_elements", 400, "pattern.kernels[0][0]", {"kernels": [[[0, 0, 1, 2]]]})
evp("sample_empty_array", 400, "pattern.kernels[0][0]", {"kernels": [[[]]]})
evp("kernel_not_nested", 400, "pattern.kernels[0][0]", {"kernels": [[0, 0, 1]]})
evp("type_sample_object", 400, "pattern.kernels[0][0]", {"kernels": [[{"x": 0, "y": 0, "w": 1}]]})
evp("type_mirrored_string", 400, "pattern.mirrored", {"mirrored": "x"})
evp("type_mirrored_weight_string", 400, "pattern.mirrored[0][2]", {"mirrored": [[0, 0, "1"]]})
ev("type_filter_number", 400, "filter", filter=5)
ev("type_filter_name_number", 400, "filter.name", filter={"name": 3})
ev("type_filter_B_string", 400, "filter.B", filter={"name": "mitchell", "B": "0.3"})
ev("type_acuity_array", 400, "acuity", acuity=[])
ev("type_acuity_knots_string", 400, "acuity.knots", acuity={"knots": "x"})
ev("acuity_knot_one_element", 400, "acuity.knots[0]", acuity={"knots": [[0]]})
ev("type_angles_string", 400, "angles", angles="0,45")
ev("type_angle_string", 400, "angles[1]", angles=[0, "45"])
ev("type_angle_null", 400, "angles[0]", angles=[None])
ev("type_detail_string", 400, "detail", detail="yes")
ev("type_detail_number", 400, "detail", detail=1)
case("type_job_kind_number", 400, "kind", path="/v1/jobs", body_json={"kind": 5})
case("type_job_seeds_string", 400, "seeds", path="/v1/jobs", body_json={"kind": "optimize", "family": "P(4,1+,2)", "seeds": "10", "max_seconds": 1})
case("type_job_seeds_fraction", 400, "seeds", path="/v1/jobs", body_json={"kind": "optimize", "family": "P(4,1+,2)", "seeds": 1.5, "max_seconds": 1})
case("type_job_max_seconds_string", 400, "max_seconds", path="/v1/jobs", body_json={"kind": "optimize", "family": "P(4,1+,2)", "seeds": 1, "max_seconds": "1"})
case("type_render_size_string", 400, "size", path="/v1/render", body_json={"pattern": {"preset": "rgss"}, "scene": "siemens-star", "size": "64x64"})
case("type_render_scene_number", 400, "scene", path="/v1/render", body_json={"pattern": {"preset": "rgss"}, "scene": 7, "size": [16, 16]})
case("type_enumerate_cost_string", 400, "cost", path="/v1/families/enumerate", body_json={"family": "P(4,1+,n)", "cost": "1.25"})
case("type_enumerate_family_number", 400, "family", path="/v1/families/enumerate", body_json={"family": 4, "cost": 1.25})
# --- NaN / Infinity / overflow
for n, b in [("nan_coord", '{"pattern":{"kernels":[[[NaN,0,1]]]}}'), ("infinity_coord", '{"pattern":{"kernels":[[[Infinity,0,1]]]}}'),
             ("neg_infinity_weight", '{"pattern":{"kernels":[[[0,0,-Infinity]]]}}'), ("nan_angle", '{"pattern":{"preset":"rgss"},"angles":[NaN]}'),
             ("nan_lowercase_filter_B", '{"pattern":{"preset":"rgss"},"filter":{"name":"mitchell","B":nan}}'),
             ("double_overflow_coord", '{"pattern":{"kernels":[[[1e999,0,1]]]}}'), ("double_overflow_neg_weight", '{"pattern":{"kernels":[[[0,0,-1e999]]]}}'),
             ("double_overflow_angle", '{"pattern":{"preset":"rgss"},"angles":[1e400]}')]:
    case(n, 400, None, body=b)
case("int64_overflow_seeds", 400, [None, "seeds"], path="/v1/jobs", body='{"kind":"optimize","family":"P(4,1+,2)","seeds":99999999999999999999,"max_seconds":1}')
case("int64_overflow_coord", 400, [None, "pattern.kernels[0][0][0]"], body='{"pattern":{"kernels":[[[99999999999999999999999,0,1]]]}}')
case("int64_max_seeds", 400, "seeds", path="/v1/jobs", body_json={"kind": "optimize", "family": "P(4,1+,2)", "seeds": 9223372036854775807, "max_seconds": 1})
case("int64_min_seeds", 400, "seeds", path="/v1/jobs", body_json={"kind": "optimize", "family": "P(4,1+,2)", "seeds": -9223372036854775808, "max_seconds": 1})
evp("coord_1e308_beyond_limit", 400, "pattern.kernels[0][0][0]", {"kernels": [[[1e308, 0, 1]]]})
# Accepted weights whose metric overflows: either refused naming the kernel, or a finite E2.
case("weights_1e308_cancel", [200, 400], "pattern.kernels[0][0][2]", body_json={"pattern": {"kernels": [[[0, 0, 1e308], [0.1, 0, -1e308], [0.2, 0, 1]]]}}, check=OK)
case("underflow_coord_ok", 200, None, body='{"pattern":{"kernels":[[[1e-99999,0,1]]]}}', check=OK)
case("denormal_angle_ok", 200, None, body='{"pattern":{"preset":"rgss"},"angles":[4.9e-324]}', check=OK)
case("angle_1e308", [200, 400], "angles[0]", body_json={"pattern": {"preset": "rgss"}, "angles": [1e308]}, check=OK)
# --- strings with NUL
case("nul_escape_in_preset", 400, [None, "pattern.preset"], body='{"pattern":{"preset":"rgss\\u0000x"}}')
case("nul_escape_in_filter_name", 400, [None, "filter.name"], body='{"pattern":{"preset":"rgss"},"filter":{"name":"mitchell\\u0000"}}')
case("nul_escape_in_key", 400, [None, "pattern\u0000x", "pattern\\u0000x"], body='{"pattern\\u0000x":{"preset":"rgss"}}')
case("nul_escape_in_kind", 400, [None, "kind"], path="/v1/jobs", body='{"kind":"sleep\\u0000","seconds":0}')
case("raw_nul_in_string", 400, None, body='{"pattern":{"preset":"rg\u0000ss"}}')
case("raw_nul_after_document", 400, None, body='{"pattern":{"preset":"rgss"}}\u0000garbage')
case("raw_nul_first_byte", 400, None, body='\u0000{"pattern":{"preset":"rgss"}}')
# --- empty and huge arrays
evp("kernels_empty", 400, "pattern.kernels", {"kernels": []})
evp("kernel_empty", 400, "pattern.kernels[0]", {"kernels": [[]]})
evp("second_kernel_empty", 400, "pattern.kernels[1]", {"kernels": [[[0, 0, 1]], []]})
evp("mirrored_empty", 400, "pattern.mirrored", {"mirrored": []})
ev("angles_empty", 400, "angles", angles=[])
ev("acuity_knots_empty", 400, "acuity.knots", acuity={"knots": []})
case("kernel_4096_samples_ok", 200, None, gen={"kind": "kernels", "kernels": 1, "samples": 4096}, check=OK)
case("kernel_4097_samples", 400, "pattern.kernels[0]", gen={"kind": "kernels", "kernels": 1, "samples": 4097})
case("kernels_256_ok", 200, None, gen={"kind": "kernels", "kernels": 256, "samples": 1}, check=OK)
case("kernels_257", 400, "pattern.kernels", gen={"kind": "kernels", "kernels": 257, "samples": 1})
case("mirrored_4097", 400, "pattern.mirrored", gen={"kind": "mirrored", "samples": 4097})
case("angles_4096_ok", 200, None, gen={"kind": "angles", "angles": 4096}, check=OK)
case("angles_4097", 400, "angles", gen={"kind": "angles", "angles": 4097})
case("acuity_knots_362", 400, "acuity.knots", gen={"kind": "knots", "knots": 362})
case("kernels_256x4096_oversized", 413, None, gen={"kind": "kernels", "kernels": 256, "samples": 4096})
case("angles_1m", [400, 413], [None, "angles"], gen={"kind": "angles", "angles": 1000000})
# --- weights
evp("weights_sum_zero", 400, "pattern.kernels[0]", {"kernels": [[[0, 0, 1], [0.1, 0, -1]]]})
evp("weights_all_zero", 400, "pattern.kernels[0]", {"kernels": [[[0, 0, 0]]]})
evp("weights_sum_two", 400, "pattern.kernels[0]", {"kernels": [[[0, 0, 1], [0.1, 0, 1]]]})
evp("weights_sum_off_1e-6", 400, "pattern.kernels[0]", {"kernels": [[[0, 0, 0.5], [0.1, 0, 0.500001]]]})
evp("weights_second_kernel_bad", 400, "pattern.kernels[1]", {"kernels": [[[0, 0, 1]], [[0, 0, 0.5]]]})
evp("weights_sum_within_tolerance_ok", 200, None, {"kernels": [[[0, 0, 0.5], [0.1, 0, 0.5000000000001]]]})
evp("mirrored_weights_half", 400, "pattern.mirrored", {"mirrored": [[0, 0, 0.25], [0.25, 0.25, 0.25]]})
case("negative_weights_ok", 200, None, body_json={"pattern": {"kernels": [[[-0.25, 0, -0.5], [0.25, 0, 1.5]]]}}, check=OK)
case("negative_weights_mirrored_ok", 200, None, body_json={"pattern": {"mirrored": [[-0.25, -0.25, -0.5], [0.25, 0.25, 1.5]]}}, check=OK)
case("negative_weights_huge_ok", 200, None, body_json={"pattern": {"kernels": [[[0, 0, 1000000], [0.1, 0, -999999]]]}}, check=OK)
# --- coincident samples / positions
case("coincident_kernel_samples_ok", 200, None, body_json={"pattern": {"kernels": [[[0, 0, 0.5], [0, 0, 0.5]]]}}, check=OK)
evp("coincident_mirrored", 400, "pattern.mirrored[1]", {"mirrored": [[0.1, 0.1, 0.5], [0.1, 0.1, 0.5]]})
evp("nearly_coincident_mirrored", 400, "pattern.mirrored[1]", {"mirrored": [[0.1, 0.1, 0.5], [0.1 + 1e-12, 0.1, 0.5]]})
evp("coincident_tile", 400, "pattern.tile.samples[1]", {"tile": {"size": 1, "kernel": 1, "border": False, "samples": [[0.5, 0.5], [0.5, 0.5]], "weights": [[0.5, 0.5]]}})
evp("position_x_1e7", 400, "pattern.kernels[0][0][0]", {"kernels": [[[1e7, 0, 1]]]})
evp("position_y_neg_1e7", 400, "pattern.kernels[0][0][1]", {"kernels": [[[0, -1e7, 1]]]})
case("position_far_but_allowed", 200, None, body_json={"pattern": {"kernels": [[[1000, 0, 0.5], [-1000, 0, 0.5]]]}}, check=OK)
evp("mirrored_x_outside_pixel", 400, "pattern.mirrored[0][0]", {"mirrored": [[0.6, 0, 1]]})
evp("mirrored_y_outside_pixel", 400, "pattern.mirrored[0][1]", {"mirrored": [[0, -0.7, 1]]})
evp("tile_size_zero", 400, "pattern.tile.size", {"tile": {"size": 0, "kernel": 1, "border": False, "samples": [[0.5, 0.5]], "weights": [[1]]}})
evp("tile_size_huge", 400, "pattern.tile.size", {"tile": {"size": 1000000, "kernel": 1, "border": False, "samples": [[0.5, 0.5]], "weights": [[1]]}})
evp("tile_kernel_zero", 400, "pattern.tile.kernel", {"tile": {"size": 1, "kernel": 0, "border": False, "samples": [[0.5, 0.5]], "weights": [[1]]}})
evp("tile_sample_nan_string", 400, "pattern.tile.samples[0][0]", {"tile": {"size": 1, "kernel": 1, "border": False, "samples": [["x", 0.5]], "weights": [[1]]}})
# --- family strings and costs
FE = "/v1/families/enumerate"
for n, f in [("empty", ""), ("unclosed", "P(4,1+"), ("wrong_letter", "Q(4,1+,n)"), ("negative_s", "P(-4,1+,n)"),
             ("huge_s", "P(99999999999999999999,1,n)"), ("garbage_suffix", "P(4,1+,n)garbage"), ("no_commas", "P(41+n)"),
             ("unsupported_family", "P(7,3,n)")]:
    case("family_" + n, 400, "family", path=FE, body_json={"family": f, "cost": 1.25})
case("family_nul_escape", 400, [None, "family"], path=FE, body='{"family":"P(4,1+,n)\\u0000","cost":1.25}')
for n, c in [("not_quarter", 1.3), ("zero", 0), ("negative", -1), ("huge", 1e9), ("tiny", 0.1)]:
    case("cost_" + n, 400, "cost", path=FE, body_json={"family": "P(4,1+,n)", "cost": c})
OPT = {"kind": "optimize", "seeds": 1, "max_seconds": 1}
for n, f in [("cost_not_quarter", "P(4,1+,1.3)"), ("cost_zero", "P(4,1+,0)"), ("cost_letters", "P(4,1+,zz)"), ("garbage", "P(4,1+,2)x")]:
    case("optimize_family_" + n, 400, "family", path="/v1/jobs", body_json=dict(OPT, family=f))
case("optimize_no_family_no_pattern", 400, ["family", "pattern"], path="/v1/jobs", body_json=dict(OPT))
case("optimize_seeds_zero", 400, "seeds", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", seeds=0))
case("optimize_seeds_negative", 400, "seeds", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", seeds=-1))
case("optimize_seeds_absurd", 400, "seeds", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", seeds=1000000000))
case("optimize_max_seconds_negative", 400, "max_seconds", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", max_seconds=-5))
case("optimize_max_seconds_huge", 400, "max_seconds", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", max_seconds=1e300))
case("optimize_method_unknown", 400, "method", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", method="newton"))
case("optimize_method_number", 400, "method", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", method=1))
case("optimize_method_case", 400, "method", path="/v1/jobs", body_json=dict(OPT, family="P(4,1+,2)", method="Smooth"))
case("random_stats_method_unknown", 400, "method", path="/v1/jobs", body_json={"kind": "random-stats", "family": "P(1,4,2)", "count": 10, "max_seconds": 1, "method": "bfgs"})
case("optimize_bad_pattern", 400, "pattern.kernels[0]", path="/v1/jobs", body_json={"kind": "optimize", "pattern": {"kernels": [[[0, 0, 2]]]}, "seeds": 1, "max_seconds": 1})
case("job_kind_unknown", 400, "kind", path="/v1/jobs", body_json={"kind": "nope"})
case("job_kind_missing", 400, "kind", path="/v1/jobs", body_json={"seeds": 1})
case("sleep_seconds_negative", 400, "seconds", path="/v1/jobs", body_json={"kind": "sleep", "seconds": -1})
case("sleep_seconds_string", 400, "seconds", path="/v1/jobs", body_json={"kind": "sleep", "seconds": "1"})
# --- unknown presets / filters / acuity / scenes
evp("preset_unknown", 400, "pattern.preset", {"preset": "nope"})
evp("preset_empty", 400, "pattern.preset", {"preset": ""})
evp("preset_traversal", 400, "pattern.preset", {"preset": "../../etc/passwd"})
case("preset_long", [400, 413], [None, "pattern.preset"], gen={"kind": "long_preset", "bytes": 100000})
case("get_preset_unknown", 404, [None, "name"], method="GET", path="/v1/presets/nope")
case("get_preset_dotdot", [400, 404], [None, "name"], method="GET", path="/v1/presets/%2e%2e")
case("get_preset_encoded_slash", [400, 404], [None, "name"], method="GET", path="/v1/presets/..%2f..%2fetc%2fpasswd")
ev("filter_unknown", 400, "filter.name", filter={"name": "sinc"})
ev("filter_empty_name", 400, "filter.name", filter={"name": ""})
ev("acuity_unknown", 400, "acuity.name", acuity={"name": "nope"})
RB = {"pattern": {"preset": "rgss"}, "scene": "siemens-star", "size": [16, 16]}
case("scene_unknown", 400, "scene", path="/v1/render", body_json=dict(RB, scene="nope"))
case("scene_empty", 400, "scene", path="/v1/render", body_json=dict(RB, scene=""))
case("render_bad_preset", 400, "pattern.preset", path="/v1/render", body_json=dict(RB, pattern={"preset": "nope"}))
# --- degenerate filters / acuity
for n, f, fld in [("mitchell_radius_zero", {"name": "mitchell", "radius": 0}, "filter.radius"),
                  ("mitchell_radius_negative", {"name": "mitchell", "radius": -1}, "filter.radius"),
                  ("mitchell_radius_huge", {"name": "mitchell", "radius": 65}, "filter.radius"),
                  ("box_radius_zero", {"name": "box", "radius": 0}, "filter.radius"),
                  ("tent_radius_negative_zero", {"name": "tent", "radius": -0.0}, "filter.radius"),
                  ("gaussian_sigma_zero", {"name": "gaussian", "sigma": 0}, "filter.sigma"),
                  ("gaussian_sigma_tiny", {"name": "gaussian", "sigma": 1e-9}, "filter.sigma"),
                  ("gaussian_sigma_negative", {"name": "gaussian", "sigma": -0.5}, "filter.sigma"),
                  ("lanczos_a_zero", {"name": "lanczos", "a": 0}, "filter.a"),
                  ("lanczos_a_fraction", {"name": "lanczos", "a": 2.5}, "filter.a"),
                  ("lanczos_a_huge", {"name": "lanczos", "a": 17}, "filter.a")]:
    ev("filter_" + n, 400, fld, filter=f)
case("filter_B_1e308", [200, 400], "filter.B", body_json={"pattern": {"preset": "rgss"}, "filter": {"name": "mitchell", "B": 1e308, "C": 0}}, check=OK)
case("filter_C_1e300", [200, 400], "filter.C", body_json={"pattern": {"preset": "rgss"}, "filter": {"name": "mitchell", "B": 0, "C": -1e300}}, check=OK)
ev("acuity_knot_negative_weight", 400, "acuity.knots[0][1]", acuity={"knots": [[0, -1]]})
ev("acuity_knot_angle_180", 400, "acuity.knots[0][0]", acuity={"knots": [[180, 1]]})
ev("acuity_knot_duplicate_angle", 400, ["acuity.knots[1][0]", "acuity.knots[0][0]"], acuity={"knots": [[10, 1], [10, 0.5]]})
case("acuity_all_zero_ok", 200, None, body_json={"pattern": {"preset": "rgss"}, "acuity": {"knots": [[0, 0]]}}, check=OK)
# --- zero / absurd sizes
for n, s, fld in [("zero_w", [0, 16], "size[0]"), ("zero_h", [16, 0], "size[1]"), ("negative", [-1, 16], "size[0]"),
                  ("absurd", [1000000, 1000000], "size[0]"), ("fraction", [16.5, 16], ["size", "size[0]"]), ("three", [16, 16, 16], "size"),
                  ("empty", [], "size")]:
    case("render_size_" + n, 400, fld, path="/v1/render", body_json=dict(RB, size=s))
# --- bad job ids, cancelling finished jobs
for n, m, p, st in [("get_missing", "GET", "/v1/jobs/999999999", 404), ("get_zero", "GET", "/v1/jobs/0", 404),
                    ("get_alpha", "GET", "/v1/jobs/abc", [400, 404]), ("get_negative", "GET", "/v1/jobs/-1", [400, 404]),
                    ("get_overflow", "GET", "/v1/jobs/99999999999999999999999999", [400, 404]),
                    ("get_encoded_nul", "GET", "/v1/jobs/1%00", [400, 404]), ("get_dotdot", "GET", "/v1/jobs/1/../../etc", [400, 404]),
                    ("get_space", "GET", "/v1/jobs/1%201", [400, 404]),
                    ("delete_missing", "DELETE", "/v1/jobs/999999999", 404), ("delete_alpha", "DELETE", "/v1/jobs/abc", [400, 404]),
                    ("export_missing_job", "GET", "/v1/patterns/999999999/export?format=json", 404),
                    ("tile_bad_id", "GET", "/v1/tiles/999999999.png", [400, 404]),
                    ("tile_missing", "GET", "/v1/tiles/" + "0" * 32 + ".png", 404), ("tile_traversal", "GET", "/v1/tiles/..%2f..%2fetc%2fpasswd.png", [400, 404])]:
    case("jobid_" + n, st, [None, "id"], method=m, path=p)
case("cancel_done_job", 409, None, method="DELETE", path="/v1/jobs/{job}", setup="done_job")
case("cancel_cancelled_job", 409, None, method="DELETE", path="/v1/jobs/{job}", setup="cancelled_job")
case("done_job_still_done", 200, None, method="GET", path="/v1/jobs/{job}", setup="done_job", check={"state": "done"})
for n, q in [("bad_format", "format=bmp"), ("empty_format", "format="), ("nul_format", "format=%00"),
             ("long_query", "x=" + "a" * 4000 + "&format=bmp")]:
    case("export_" + n, 400, "format", method="GET", path="/v1/patterns/{job}/export?" + q, setup="pattern_job")
case("export_job_without_pattern", 409, "id", method="GET", path="/v1/patterns/{job}/export?format=json", setup="done_job")
case("export_utk_ok", 200, None, method="GET", path="/v1/patterns/{job}/export?format=utk", setup="pattern_job")
case("sleep_bad_pattern", 400, "pattern.preset", path="/v1/jobs", body_json={"kind": "sleep", "seconds": 0, "pattern": {"preset": "nope"}})
case("sleep_seconds_too_long", 400, "seconds", path="/v1/jobs", body_json={"kind": "sleep", "seconds": 3601})
case("sleep_fail_not_bool", 400, "fail", path="/v1/jobs", body_json={"kind": "sleep", "seconds": 0, "fail": "yes"})
# --- oversized bodies and headers, content type, methods
case("body_20MiB", 413, None, gen={"kind": "spaces", "bytes": 20 << 20})
case("content_length_lies_huge", 413, None, raw={"content_length": 10 << 30, "send": '{"pattern":'})
case("chunked_20MiB", 413, None, gen={"kind": "spaces", "bytes": 20 << 20, "chunked": True})
case("header_100KiB", [400, 413, 431], "*", method="GET", path="/v1/health", raw={"header_bytes": 100000})
case("headers_2000", [400, 413, 431], "*", method="GET", path="/v1/health", raw={"header_count": 2000})
case("url_100KiB", [400, 404, 413, 414, 431], "*", method="GET", path="/v1/presets/", raw={"path_bytes": 100000})
for n, ct, st in [("text_plain", "text/plain", 415), ("form", "application/x-www-form-urlencoded", 415),
                  ("multipart", "multipart/form-data; boundary=x", 415), ("jsonx", "application/jsonx", 415),
                  ("json_charset_ok", "application/json; charset=utf-8", 200), ("json_uppercase_ok", "Application/JSON", 200)]:
    case("ctype_" + n, st, None, headers={"Content-Type": ct}, body_json={"pattern": {"preset": "rgss"}})
case("ctype_missing", [200, 415], None, headers={}, body_json={"pattern": {"preset": "rgss"}})
for n, m, p in [("put_evaluate", "PUT", EV), ("get_evaluate", "GET", EV), ("delete_health", "DELETE", "/v1/health"),
                ("post_health", "POST", "/v1/health"), ("patch_jobs", "PATCH", "/v1/jobs")]:
    case("method_" + n, 405, None, method=m, path=p, headers={"Content-Type": "application/json"} if m in ("PUT", "POST", "PATCH") else {},
         body="{}" if m in ("PUT", "POST", "PATCH") else None)
case("route_unknown", 404, None, method="GET", path="/v1/nope")
case("route_v2", 404, None, method="GET", path="/v2/health")
case("route_double_slash", [400, 404], None, method="GET", path="//v1/health")
# --- static files over TCP: traversal, symlinks, host, token
S = "SECRET-MARKER"
for n, p in [("dotdot", "/../secret.txt"), ("encoded_dotdot", "/%2e%2e/secret.txt"), ("encoded_slash", "/..%2fsecret.txt"),
             ("double_encoded", "/%252e%252e/secret.txt"), ("deep", "/a/b/../../../secret.txt"), ("backslash", "/..\\secret.txt"),
             ("absolute_etc", "/../../../../../../etc/passwd"), ("nul_suffix", "/index.html%00.png"), ("symlink_out", "/escape.txt"),
             ("dot_segment_dir", "/./../secret.txt")]:
    case("static_" + n, [400, 403, 404], "*", method="GET", path=p, via="tcp", forbid_body=[S, "root:x:0:0"])
case("static_index_ok", 200, None, method="GET", path="/", via="tcp", check={"content_type_prefix": "text/html"})
case("tcp_bad_host", [400, 403, 421], "*", method="GET", path="/v1/health", via="tcp", headers={"Host": "evil.example"})
case("tcp_post_job_no_token", 401, None, path="/v1/jobs", via="tcp", body_json={"kind": "sleep", "seconds": 0})
case("tcp_post_job_wrong_token", 401, None, path="/v1/jobs", via="tcp", headers={"Content-Type": "application/json", "Authorization": "Bearer wrong"}, body_json={"kind": "sleep", "seconds": 0})
case("tcp_delete_no_token", 401, None, method="DELETE", path="/v1/jobs/1", via="tcp")
# every API read over TCP needs a token too; tokens are issued on the Unix socket only
for n, p in [("health", "/v1/health"), ("jobs", "/v1/jobs"), ("job", "/v1/jobs/1"), ("presets", "/v1/presets"),
             ("export", "/v1/patterns/1/export"), ("tile", "/v1/tiles/0123456789abcdef0123456789abcdef.png"),
             ("tokens", "/v1/tokens"), ("unknown", "/v1/nope")]:
    case("tcp_get_%s_no_token" % n, 401, None, method="GET", path=p, via="tcp")
case("tcp_get_health_forged_token", 401, None, method="GET", path="/v1/health", via="tcp",
     headers={"Authorization": "Bearer aalab_1_" + "0" * 64})
case("token_label_not_string", 400, "label", path="/v1/tokens", body_json={"label": 5})
case("token_unknown_key", 400, "uid", path="/v1/tokens", body_json={"uid": 0})
case("token_label_too_long", 400, "label", path="/v1/tokens", body_json={"label": "x" * 101})
case("token_revoke_not_id", 404, "id", method="DELETE", path="/v1/tokens/abc")
case("token_revoke_unknown", 404, "id", method="DELETE", path="/v1/tokens/999999")
case("job_visibility_bad", 400, "visibility", path="/v1/jobs", body_json={"kind": "sleep", "seconds": 0, "visibility": "public"})
case("job_visibility_not_string", 400, "visibility", path="/v1/jobs", body_json={"kind": "sleep", "seconds": 0, "visibility": 1})
case("render_visibility_bad", 400, "visibility", path="/v1/render", body_json={"pattern": {"preset": "rgss"}, "size": [8, 8], "visibility": "world"})
# --- the points form (point-set files in a request) and POST /v1/patterns/export
def pts(name, status, field, points, **extra):
    evp("points_" + name, status, field, {"points": points, **extra})
pts("no_format", 400, "pattern.points.format", {"text": "0.5 0.5\n"})
pts("format_unknown", 400, "pattern.points.format", {"format": "dat", "text": "0.5 0.5\n"})
pts("format_number", 400, "pattern.points.format", {"format": 1, "text": "0.5 0.5\n"})
pts("not_object", 400, "pattern.points", "0.5 0.5")
pts("unknown_key", 400, "pattern.points.bogus", {"format": "utk", "text": "0.5 0.5\n", "bogus": 1})
pts("text_and_data", 400, "pattern.points.data", {"format": "json", "text": "[[0.5,0.5]]", "data": [[0.5, 0.5]]})
pts("neither_text_nor_data", 400, "pattern.points", {"format": "utk"})
pts("text_not_string", 400, "pattern.points.text", {"format": "utk", "text": [0.5, 0.5]})
pts("data_with_utk", 400, "pattern.points.data", {"format": "utk", "data": [[0.5, 0.5]]})
pts("no_weights", 400, "pattern.points.weights", {"format": "utk", "text": "0.5 0.5\n"})
pts("weights_unknown", 400, "pattern.points.weights", {"format": "utk", "text": "0.5 0.5\n", "weights": "uniform"})
pts("file_weights_kernel2", 400, "pattern.points.weights", {"format": "xyw", "text": "0.5 0.5 1\n", "kernel": 2})
pts("tile_zero", 400, "pattern.points.tile", {"format": "utk", "text": "0.5 0.5\n", "tile": 0, "weights": "equal"})
pts("tile_17", 400, "pattern.points.tile", {"format": "utk", "text": "0.5 0.5\n", "tile": 17, "weights": "equal"})
pts("tile_real", 400, "pattern.points.tile", {"format": "utk", "text": "0.5 0.5\n", "tile": 2.0, "weights": "equal"})
pts("kernel_9", 400, "pattern.points.kernel", {"format": "utk", "text": "0.5 0.5\n", "kernel": 9, "weights": "equal"})
pts("border_string", 400, "pattern.points.border", {"format": "utk", "text": "0.5 0.5\n", "border": "yes", "weights": "equal"})
pts("utk_three_numbers", 400, "pattern.points.text", {"format": "utk", "text": "0.5 0.5\n0.1 0.2 0.3\n", "weights": "equal"})
pts("utk_not_a_number", 400, "pattern.points.text", {"format": "utk", "text": "0.5 zero\n", "weights": "equal"})
pts("utk_nan", 400, "pattern.points.text", {"format": "utk", "text": "nan 0.5\n", "weights": "equal"})
pts("utk_hex", 400, "pattern.points.text", {"format": "utk", "text": "0x1p-1 0.5\n", "weights": "equal"})
pts("utk_overflow", 400, "pattern.points.text", {"format": "utk", "text": "1e999 0.5\n", "weights": "equal"})
pts("utk_empty", 400, "pattern.points.text", {"format": "utk", "text": "", "weights": "equal"})
pts("utk_comments_only", 400, "pattern.points.text", {"format": "utk", "text": "# x y\n\n", "weights": "equal"})
pts("utk_nul_byte", 400, None, {"format": "utk", "text": "0.5\u0000 0.5\n", "weights": "equal"})
pts("utk_outside_tile", 400, "pattern.points.text", {"format": "utk", "text": "0.5 0.5\n1.5 0.5\n", "weights": "equal"})
pts("utk_negative", 400, "pattern.points.text", {"format": "utk", "text": "-0.25 0.5\n", "weights": "equal"})
pts("utk_duplicate_point", 400, "pattern.points.text", {"format": "utk", "text": "0.5 0.5\n0.5 0.5\n", "weights": "equal"})
pts("utk_empty_pixel", 400, "pattern.points.text", {"format": "utk", "text": "0.1 0.1\n", "tile": 2, "weights": "equal"})
pts("utk_too_many", 400, "pattern.points.text", {"format": "utk", "text": "0.5 0.5\n" * 4097, "weights": "equal"})
pts("xyw_mixed_arity", 400, "pattern.points.text", {"format": "xyw", "text": "0.2 0.2 0.5\n0.7 0.7\n"})
pts("xyw_weights_sum", 400, "pattern.points.text", {"format": "xyw", "text": "0.2 0.2 0.5\n0.7 0.7 0.25\n"})
pts("xyw_weight_huge", 400, "pattern.points.text", {"format": "xyw", "text": "0.2 0.2 1e300\n0.7 0.7 -1e300\n"})
pts("csv_no_header", 400, "pattern.points.text", {"format": "csv", "text": "0.5,0.5\n", "weights": "equal"})
pts("csv_extra_column", 400, "pattern.points.text", {"format": "csv", "text": "x,y,z\n0.5,0.5,1\n", "weights": "equal"})
pts("csv_missing_y", 400, "pattern.points.text", {"format": "csv", "text": "x,w\n0.5,1\n"})
pts("csv_short_row", 400, "pattern.points.text", {"format": "csv", "text": "x,y\n0.5\n", "weights": "equal"})
pts("json_text_invalid", 400, "pattern.points.text", {"format": "json", "text": "[[0.5,0.5]", "weights": "equal"})
pts("json_text_duplicate_key", 400, "pattern.points.text", {"format": "json", "text": '[{"x":0.5,"x":0.5,"y":0.5}]', "weights": "equal"})
pts("json_data_bad_point", 400, "pattern.points.data[1]", {"format": "json", "data": [[0.5, 0.5], [0.5]], "weights": "equal"})
pts("json_data_string_coord", 400, "pattern.points.data[0]", {"format": "json", "data": [["0.5", 0.5]], "weights": "equal"})
pts("json_data_empty", 400, "pattern.points.data", {"format": "json", "data": [], "weights": "equal"})
pts("json_data_object_unknown", 400, "pattern.points.data.bogus", {"format": "json", "data": {"points": [[0.5, 0.5]], "bogus": 1}, "weights": "equal"})
pts("header_not_json", 400, "pattern.points.text", {"format": "utk", "text": "# aalab-pattern {tile:1}\n0.5 0.5\n"})
pts("header_unknown_key", 400, "pattern.points.text", {"format": "utk", "text": '# aalab-pattern {"colour":1}\n0.5 0.5\n'})
pts("header_tile_disagrees", 400, "pattern.points.tile", {"format": "utk", "text": '# aalab-pattern {"tile":1,"weights":[[1]]}\n0.5 0.5\n', "tile": 2})
pts("header_weights_wrong_count", 400, "pattern.points.text", {"format": "utk", "text": '# aalab-pattern {"tile":1,"weights":[[0.5,0.5]]}\n0.5 0.5\n'})
pts("header_pattern_mismatch", 400, "pattern.points.text", {"format": "utk", "text": '# aalab-pattern {"pattern":{"preset":"rgss"}}\n0.5 0.5\n'})
pts("header_pattern_recursive", 400, "pattern.points.text", {"format": "utk", "text": '# aalab-pattern {"pattern":{"points":{"format":"utk","text":"0.5 0.5"}}}\n0.5 0.5\n'})
case("points_equal_ok", 200, None, body_json={"pattern": {"points": {"format": "utk", "text": "0.25 0.25\n0.75 0.75\n", "weights": "equal"}}}, check=OK)
case("points_in_job_spec_bad", 400, "pattern.points.text", path="/v1/jobs", body_json={"kind": "optimize", "pattern": {"points": {"format": "csv", "text": "x\n"}}, "max_iterations": 1})
# the sampling tools' formats (issue 31): UTK .bin and PSA .rps as base64, '#'-separated sets
import base64 as _b64
import struct as _st
def _utk(sets, dtype=5, d=2):
    f = "<d" if dtype == 5 else "<f"
    return _st.pack("<IB3xIII", 0x214B5455, dtype, len(sets), len(sets[0]), d) + b"".join(_st.pack(f, v) for s_ in sets for p_ in s_ for v in p_)
def _b(x): return _b64.b64encode(x).decode()
_T = [(0.25, 0.25), (0.75, 0.75)]
_B64F = "pattern.points.base64"
pts("bin_ok", 200, None, {"format": "bin", "base64": _b(_utk([_T])), "weights": "equal"})
pts("bin_truncated_header", 400, _B64F, {"format": "bin", "base64": _b(_utk([_T])[:19]), "weights": "equal"})
pts("bin_truncated_data", 400, _B64F, {"format": "bin", "base64": _b(_utk([_T])[:-1]), "weights": "equal"})
pts("bin_bad_magic", 400, _B64F, {"format": "bin", "base64": _b(b"UTK?" + _utk([_T])[4:]), "weights": "equal"})
pts("bin_int_dtype", 400, _B64F, {"format": "bin", "base64": _b(_st.pack("<IB3xIII", 0x214B5455, 0, 1, 2, 2) + b"\0" * 16), "weights": "equal"})
pts("bin_dimension_3", 400, _B64F, {"format": "bin", "base64": _b(_utk([[(0.1, 0.2, 0.3)]], d=3)), "weights": "equal"})
pts("bin_count_mismatch", 400, _B64F, {"format": "bin", "base64": _b(_utk([_T]) + b"\0" * 8), "weights": "equal"})
pts("bin_nan", 400, _B64F, {"format": "bin", "base64": _b(_utk([[(0.5, float("nan"))]])), "weights": "equal"})
pts("bin_too_many", 400, _B64F, {"format": "bin", "base64": _b(_utk([[(0.5, 0.5)] * 4097])), "weights": "equal"})
pts("bin_huge_m", 400, _B64F, {"format": "bin", "base64": _b(_st.pack("<IB3xIII", 0x214B5455, 5, 0xffffffff, 4096, 2)), "weights": "equal"})
pts("bin_two_sets_no_set", 400, "pattern.points.set", {"format": "bin", "base64": _b(_utk([_T, _T])), "weights": "equal"})
pts("bin_set_past_end", 400, "pattern.points.set", {"format": "bin", "base64": _b(_utk([_T, _T])), "set": 2, "weights": "equal"})
pts("rps_truncated", 400, _B64F, {"format": "rps", "base64": _b(b"\0" * 12), "weights": "equal"})
pts("rps_empty", 400, _B64F, {"format": "rps", "base64": "", "weights": "equal"})
pts("rps_inf", 400, _B64F, {"format": "rps", "base64": _b(_st.pack("<ff", float("inf"), 0.5)), "weights": "equal"})
pts("rps_too_many", 400, _B64F, {"format": "rps", "base64": _b(_st.pack("<f", 0.5) * 2 * 4097), "weights": "equal"})
pts("rps_as_text", 400, "pattern.points.text", {"format": "rps", "text": "0.5 0.5\n", "weights": "equal"})
pts("base64_invalid_char", 400, _B64F, {"format": "rps", "base64": "AAAA*AAA", "weights": "equal"})
pts("base64_unpadded", 400, _B64F, {"format": "rps", "base64": "AAAAAAAAAAA", "weights": "equal"})
pts("base64_not_string", 400, _B64F, {"format": "rps", "base64": 5, "weights": "equal"})
pts("base64_and_text", 400, _B64F, {"format": "utk", "text": "0.5 0.5\n", "base64": "MC41IDAuNQo=", "weights": "equal"})
pts("set_negative", 400, "pattern.points.set", {"format": "utk", "text": "0.5 0.5\n", "set": -1, "weights": "equal"})
pts("set_real", 400, "pattern.points.set", {"format": "utk", "text": "0.5 0.5\n", "set": 0.5, "weights": "equal"})
pts("set_past_end", 400, "pattern.points.set", {"format": "utk", "text": "0.1 0.1\n#\n0.5 0.5\n", "set": 2, "weights": "equal"})
pts("set_all_in_evaluate", 400, "pattern.points.set", {"format": "utk", "text": "0.1 0.1\n#\n0.5 0.5\n", "set": "all", "weights": "equal"})
pts("set_csv", 400, "pattern.points.set", {"format": "csv", "text": "x,y\n0.5,0.5\n", "set": 0, "weights": "equal"})
pts("set_json_data", 400, "pattern.points.set", {"format": "json", "data": [[0.5, 0.5]], "set": 0, "weights": "equal"})
pts("set_second_bad_line", 400, "pattern.points.text", {"format": "utk", "text": "0.1 0.1\n#\n0.5 x\n", "set": 1, "weights": "equal"})
pts("sets_without_set", 400, "pattern.points.text", {"format": "utk", "text": '# aalab-pattern {"tile":1,"weights":[[1]]}\n0.5 0.5\n# aalab-pattern {"tile":1,"weights":[[1]]}\n0.5 0.5\n'})
AN = "/v1/analyze"
_two = "0.1 0.2\n0.6 0.7\n#\n0.3 0.3\n0.8 0.9\n"
case("analyze_temporal_ok", 200, None, path=AN, body_json={"pattern": {"temporal": {"preset": "halton23-8"}}, "spectrum": {"radius": 4}})
case("analyze_temporal_too_many_points", 400, "pattern.temporal", path=AN, body_json={"pattern": {"temporal": {"jitter": {"generator": "halton", "count": 1024}, "frame_pattern": {"preset": "d3d-8x"}}}})
case("analyze_temporal_bad_offset", 400, "pattern.temporal.jitter[1]", path=AN, body_json={"pattern": {"temporal": {"jitter": [[0, 0], [0.9, 0]]}}})
case("analyze_temporal_bad_frame", 400, "pattern.temporal.frame_pattern.preset", path=AN, body_json={"pattern": {"temporal": {"jitter": [[0, 0], [0.1, 0]], "frame_pattern": {"preset": "nope"}}}})
case("analyze_set_all_ok", 200, None, path=AN, body_json={"pattern": {"points": {"format": "utk", "text": _two, "set": "all", "weights": "equal"}}, "spectrum": {"radius": 4}})
case("analyze_set_all_sizes_differ", 400, "pattern.points.set", path=AN, body_json={"pattern": {"points": {"format": "utk", "text": _two + "0.5 0.5\n", "set": "all", "weights": "equal"}}})
case("analyze_set_all_bad_set", 400, "pattern.points.text", path=AN, body_json={"pattern": {"points": {"format": "utk", "text": _two + "#\n0.5 z\n", "set": "all", "weights": "equal"}}})
case("analyze_set_all_too_many_sets", 400, "pattern.points.set", path=AN, body_json={"pattern": {"points": {"format": "utk", "text": "0.5 0.5\n#\n" * 1025, "set": "all", "weights": "equal"}}})
case("analyze_set_all_rps", 400, "pattern.points.text", path=AN, body_json={"pattern": {"points": {"format": "rps", "text": "x", "set": "all", "weights": "equal"}}})
case("export_post_metal_not_representable", 200, None, path="/v1/patterns/export", body_json={"pattern": {"preset": "flipquad"}, "format": "metal"})
case("unknown_key_long_multibyte", 400, "pattern.a" + "é" * 29, body_json={"pattern": {"preset": "rgss", "a" + "é" * 40: 1}})
EXP = "/v1/patterns/export"
case("export_post_no_format", 400, "format", path=EXP, body_json={"pattern": {"preset": "rgss"}})
case("export_post_bad_format", 400, "format", path=EXP, body_json={"pattern": {"preset": "rgss"}, "format": "png"})
case("export_post_format_number", 400, "format", path=EXP, body_json={"pattern": {"preset": "rgss"}, "format": 3})
case("export_post_no_pattern", 400, "pattern", path=EXP, body_json={"format": "csv"})
case("export_post_unknown_key", 400, "bogus", path=EXP, body_json={"pattern": {"preset": "rgss"}, "format": "csv", "bogus": 1})
case("export_post_bad_pattern", 400, "pattern.preset", path=EXP, body_json={"pattern": {"preset": "nope"}, "format": "csv"})
case("export_post_bad_points", 400, "pattern.points.text", path=EXP, body_json={"pattern": {"points": {"format": "utk", "text": "x\n", "weights": "equal"}}, "format": "utk"})
case("export_post_unknown_job", 400, "pattern.job", path=EXP, body_json={"pattern": {"job": 999999}, "format": "csv"})
case("export_post_bad_filter", 400, "filter.name", path=EXP, body_json={"pattern": {"preset": "rgss"}, "format": "csv", "filter": {"name": "nope"}})
case("export_post_not_json", 400, None, path=EXP, body="format=csv")
case("export_post_wrong_type", 415, None, path=EXP, headers={"Content-Type": "text/plain"}, body='{"pattern":{"preset":"rgss"},"format":"csv"}')
case("export_get_method", 405, None, method="GET", path=EXP)
case("export_get_format_csv_unknown_job", 404, "id", method="GET", path="/v1/patterns/999999/export?format=csv")
case("export_get_format_bad", 400, "format", method="GET", path="/v1/patterns/1/export?format=dat")
# --- POST /v1/predict: the render forms plus "patterns"
PR = "/v1/predict"
case("predict_ok_half_plane", 200, None, path=PR, body_json={"pattern": "rgss", "scene": {"name": "half-plane", "angle": 27}})
case("predict_no_pattern", 400, "pattern", path=PR, body_json={"scene": "siemens-star"})
case("predict_both_pattern_and_patterns", 400, "patterns", path=PR, body_json={"pattern": "rgss", "patterns": ["rgss"]})
case("predict_patterns_empty", 400, "patterns", path=PR, body_json={"patterns": []})
case("predict_patterns_not_array", 400, "patterns", path=PR, body_json={"patterns": "rgss"})
case("predict_patterns_too_many", 400, "patterns", path=PR, body_json={"patterns": ["rgss"] * 65})
case("predict_patterns_bad_preset", 400, "patterns[1]", path=PR, body_json={"patterns": ["rgss", "nope"]})
case("predict_patterns_bad_kernel", 400, "patterns[0].kernels[0][0][1]", path=PR, body_json={"patterns": [{"kernels": [[[0, "x", 1]]]}]})
case("predict_weights_sum_half", 400, "pattern.kernels[0]", path=PR, body_json={"pattern": {"kernels": [[[0, 0, 0.5]]]}})
case("predict_e1_by_angle_not_bool", 400, "e1_by_angle", path=PR, body_json={"pattern": "rgss", "e1_by_angle": "yes"})
case("predict_model_unknown", 400, "model", path=PR, body_json={"pattern": "rgss", "model": "segments"})
case("predict_model_not_string", 400, "model", path=PR, body_json={"pattern": "rgss", "model": 3})
case("predict_ok_exact_model", 200, None, path=PR, body_json={"pattern": "rgss", "scene": {"name": "half-plane", "angle": 27}, "model": "exact"})
case("predict_unknown_key", 400, "crop", path=PR, body_json={"pattern": "rgss", "crop": {"x": 0}})
case("predict_scene_unknown", 400, "scene", path=PR, body_json={"pattern": "rgss", "scene": "nope"})
case("predict_scene_angle_nan", 400, "scene.angle", path=PR, body_json={"pattern": "rgss", "scene": {"name": "sliver", "angle": "8"}})
case("predict_size_zero", 400, "size[0]", path=PR, body_json={"pattern": "rgss", "scene": "rings", "size": [0, 16]})
case("predict_reference_spp", 400, "reference.spp", path=PR, body_json={"pattern": "rgss", "reference": {"spp": 3}})
case("predict_reference_filter", 400, "reference.filter.name", path=PR, body_json={"pattern": "rgss", "reference": {"filter": "nope"}})
case("predict_job_ref_unknown", 400, "pattern.job", path=PR, body_json={"pattern": {"job": 999999999}})
case("predict_not_object", 400, None, path=PR, body_json=[1, 2])
case("predict_get", 405, None, method="GET", path=PR)
# optimize with a scene objective (issue 18 point 4; proto/job_scene_objective.h)
OSC = dict(OPT, family="P(1,1,4)")
case("optimize_objective_not_object", 400, "objective", path="/v1/jobs", body_json=dict(OSC, objective="star"))
case("optimize_objective_no_scene", 400, "objective.scene", path="/v1/jobs", body_json=dict(OSC, objective={"blend": 0.5}))
case("optimize_objective_unknown_key", 400, "objective.weight", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "rings", "weight": 1}))
case("optimize_objective_scene_unknown", 400, "objective.scene", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "nope"}))
case("optimize_objective_scene_angle", 400, "objective.scene.angle", path="/v1/jobs", body_json=dict(OSC, objective={"scene": {"name": "half-plane", "angle": "2"}}))
case("optimize_objective_size", 400, "objective.size[0]", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "rings", "size": [0, 16]}))
case("optimize_objective_animation", 400, "objective.scene", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "rotating-triangle"}))
case("optimize_objective_blend_high", 400, "objective.blend", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "rings", "blend": 1.5}))
case("optimize_objective_blend_string", 400, "objective.blend", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "rings", "blend": "0.5"}))
case("optimize_objective_with_grid", 400, "objective", path="/v1/jobs", body_json=dict(OSC, objective={"scene": "rings"}, grid={"bits": 4}))
# --- POST /v1/analyze: point-set analysis of a pattern's tile
AN = "/v1/analyze"
FQ = {"preset": "flipquad"}
case("analyze_ok_flipquad", 200, None, path=AN, body_json={"pattern": FQ})
case("analyze_no_pattern", 400, "pattern", path=AN, body_json={"metrics": ["spacing"]})
case("analyze_unknown_key", 400, "bogus", path=AN, body_json={"pattern": FQ, "bogus": 1})
case("analyze_metrics_empty", 400, "metrics", path=AN, body_json={"pattern": FQ, "metrics": []})
case("analyze_metrics_unknown", 400, "metrics[1]", path=AN, body_json={"pattern": FQ, "metrics": ["pcf", "fft"]})
case("analyze_metrics_not_string", 400, "metrics[0]", path=AN, body_json={"pattern": FQ, "metrics": [3]})
case("analyze_radius_zero", 400, "spectrum.radius", path=AN, body_json={"pattern": FQ, "spectrum": {"radius": 0}})
case("analyze_radius_over", 400, "spectrum.radius", path=AN, body_json={"pattern": FQ, "spectrum": {"radius": 129}})
case("analyze_radius_real", 400, "spectrum.radius", path=AN, body_json={"pattern": FQ, "spectrum": {"radius": 2.5}})
case("analyze_spectrum_not_object", 400, "spectrum", path=AN, body_json={"pattern": FQ, "spectrum": 4})
case("analyze_spectrum_unknown_key", 400, "spectrum.size", path=AN, body_json={"pattern": FQ, "spectrum": {"size": 4}})
case("analyze_pcf_bins_zero", 400, "pcf.bins", path=AN, body_json={"pattern": FQ, "pcf": {"bins": 0}})
case("analyze_pcf_r_max_over", 400, "pcf.r_max", path=AN, body_json={"pattern": FQ, "pcf": {"r_max": 0.6}})
case("analyze_pcf_sigma_negative", 400, "pcf.sigma", path=AN, body_json={"pattern": FQ, "pcf": {"sigma": -1}})
case("analyze_pcf_sigma_string", 400, "pcf.sigma", path=AN, body_json={"pattern": FQ, "pcf": {"sigma": "0.1"}})
case("analyze_one_point", 400, "pattern", path=AN, body_json={"pattern": {"preset": "centroid"}})
case("analyze_no_tile", 400, "pattern", path=AN, body_json={"pattern": {"kernels": [[[0, 0, 0.5], [0.1, 0.2, 0.5]], [[0, 0, 1]]]}})
case("analyze_bad_kernel", 400, "pattern.kernels[0][0][1]", path=AN, body_json={"pattern": {"kernels": [[[0, "x", 1]]]}})
case("analyze_job_ref_unknown", 400, "pattern.job", path=AN, body_json={"pattern": {"job": 999999999}})
case("analyze_not_object", 400, None, path=AN, body_json=[1, 2])
case("analyze_get", 405, None, method="GET", path=AN)
# --- point-set figures per random pattern in random-stats and table3 (issue 31; proto/job_point_metrics.c)
RS = {"kind": "random-stats", "family": "P(1,1,4)", "count": 10, "max_iterations": 5}
T3 = {"kind": "table3", "family": "P(1,1,4)", "seeds": 1, "count": 10, "max_iterations": 5}
for kind, base in [("random_stats", RS), ("table3", T3)]:
    case(kind + "_metrics_unknown", 400, "metrics[1]", path="/v1/jobs", body_json=dict(base, metrics=["l2_star", "fft"]))
    case(kind + "_metrics_duplicate", 400, "metrics[1]", path="/v1/jobs", body_json=dict(base, metrics=["centered", "centered"]))
    case(kind + "_metrics_too_many", 400, "metrics", path="/v1/jobs", body_json=dict(base, metrics=["l2_star"] * 13))
    case(kind + "_metrics_not_array", 400, "metrics", path="/v1/jobs", body_json=dict(base, metrics="l2_star"))
    case(kind + "_metrics_empty", 400, "metrics", path="/v1/jobs", body_json=dict(base, metrics=[]))
    case(kind + "_metrics_not_string", 400, "metrics[0]", path="/v1/jobs", body_json=dict(base, metrics=[1]))
    case(kind + "_metrics_group_name", 400, "metrics[0]", path="/v1/jobs", body_json=dict(base, metrics=["discrepancy"]))
    case(kind + "_metrics_one_point", 400, "metrics", path="/v1/jobs", body_json=dict(base, family="P(1,1,1)", metrics=["mixture"]))
case("random_stats_metrics_count_over", 400, "metrics", path="/v1/jobs", body_json=dict(RS, count=10001, metrics=["mixture"]))
case("table3_metrics_patterns_over", 400, "metrics", path="/v1/jobs", body_json=dict(T3, seeds=2, count=2501, distributions=["uniform", "poisson"], metrics=["mixture"]))
# --- the temporal pattern form (issue 30; proto/codec_temporal.c): POST /v1/evaluate only
def tmp(name, status, field, temporal, **extra):
    evp("temporal_" + name, status, field, {"temporal": temporal, **extra})
H8 = {"generator": "halton", "count": 8}
case("temporal_ok_preset", 200, None, body_json={"pattern": {"temporal": {"preset": "halton23-8"}}}, check=OK)
case("temporal_ok_box_one_offset", 200, None, body_json={"pattern": {"temporal": {"jitter": [[0, 0]], "blend": {"kind": "box"}}}}, check=OK)
tmp("not_object", 400, "pattern.temporal", [[0, 0]])
tmp("unknown_key", 400, "pattern.temporal.bogus", {"jitter": H8, "bogus": 1})
tmp("beside_other_key", 400, "pattern.normalize", {"jitter": H8}, normalize=True)
tmp("no_jitter", 400, "pattern.temporal.jitter", {"blend": {"kind": "box"}})
tmp("jitter_empty", 400, "pattern.temporal.jitter", {"jitter": []})
tmp("jitter_too_many", 400, "pattern.temporal.jitter", {"jitter": [[0, 0]] * 1025})
tmp("jitter_outside_range", 400, "pattern.temporal.jitter[1]", {"jitter": [[0, 0], [0.6, 0]]})
tmp("jitter_not_pair", 400, "pattern.temporal.jitter[0]", {"jitter": [[0, 0, 1]]})
tmp("jitter_string", 400, "pattern.temporal.jitter[0][1]", {"jitter": [[0, "0"]]})
tmp("jitter_range_zero", 400, "pattern.temporal.jitter_range", {"jitter": H8, "jitter_range": 0})
tmp("jitter_range_huge", 400, "pattern.temporal.jitter_range", {"jitter": H8, "jitter_range": 17})
tmp("generator_unknown", 400, "pattern.temporal.jitter.generator", {"jitter": {"generator": "sobol", "count": 8}})
tmp("halton_no_count", 400, "pattern.temporal.jitter.count", {"jitter": {"generator": "halton"}})
tmp("halton_count_zero", 400, "pattern.temporal.jitter.count", {"jitter": {"generator": "halton", "count": 0}})
tmp("halton_count_real", 400, "pattern.temporal.jitter.count", {"jitter": {"generator": "halton", "count": 8.0}})
tmp("halton_count_huge", 400, "pattern.temporal.jitter.count", {"jitter": {"generator": "halton", "count": 1025}})
tmp("halton_base_one", 400, "pattern.temporal.jitter.bases[0]", {"jitter": {"generator": "halton", "count": 8, "bases": [1, 3]}})
tmp("halton_bases_three", 400, "pattern.temporal.jitter.bases", {"jitter": {"generator": "halton", "count": 8, "bases": [2, 3, 5]}})
tmp("halton_start_negative", 400, "pattern.temporal.jitter.start", {"jitter": {"generator": "halton", "count": 8, "start": -1}})
tmp("r2_with_bases", 400, "pattern.temporal.jitter.bases", {"jitter": {"generator": "r2", "count": 8, "bases": [2, 3]}})
tmp("rgss4_with_count", 400, "pattern.temporal.jitter.count", {"jitter": {"generator": "rgss4", "count": 8}})
tmp("fsr2_scale_low", 400, "pattern.temporal.jitter.scale", {"jitter": {"generator": "fsr2", "scale": 0.5}})
tmp("fsr2_scale_huge", 400, "pattern.temporal.jitter.scale", {"jitter": {"generator": "fsr2", "scale": 100}})
tmp("fsr2_scale_string", 400, "pattern.temporal.jitter.scale", {"jitter": {"generator": "fsr2", "scale": "2"}})
tmp("preset_generator_unknown", 400, "pattern.temporal.jitter.preset", {"jitter": {"generator": "preset", "preset": "nope"}})
tmp("preset_generator_mirrored", 400, "pattern.temporal.jitter.preset", {"jitter": {"generator": "preset", "preset": "flipquad"}})
tmp("preset_unknown", 400, "pattern.temporal.preset", {"preset": "taa-9000"})
tmp("preset_override_bad_alpha", 400, "pattern.temporal.blend.alpha", {"preset": "halton23-8", "blend": {"kind": "exponential", "alpha": 2}})
tmp("blend_alpha_zero", 400, "pattern.temporal.blend.alpha", {"jitter": H8, "blend": {"kind": "exponential", "alpha": 0}})
tmp("blend_alpha_missing", 400, "pattern.temporal.blend.alpha", {"jitter": H8, "blend": {"kind": "exponential"}})
tmp("blend_alpha_nan", 400, "pattern.temporal.blend.alpha", {"jitter": H8, "blend": {"kind": "exponential", "alpha": "nan"}})
tmp("blend_box_alpha", 400, "pattern.temporal.blend.alpha", {"jitter": H8, "blend": {"kind": "box", "alpha": 0.5}})
tmp("blend_kind_unknown", 400, "pattern.temporal.blend.kind", {"jitter": H8, "blend": {"kind": "median"}})
tmp("blend_not_object", 400, "pattern.temporal.blend", {"jitter": H8, "blend": 0.1})
tmp("resolve_no_filter", 400, "pattern.temporal.resolve.filter", {"jitter": H8, "resolve": {"radius": 1}})
tmp("resolve_filter_unknown", 400, "pattern.temporal.resolve.filter.name", {"jitter": H8, "resolve": {"filter": {"name": "nope"}}})
tmp("resolve_radius_5", 400, "pattern.temporal.resolve.radius", {"jitter": H8, "resolve": {"filter": {"name": "gaussian"}, "radius": 5}})
tmp("resolve_box_no_weight", 400, "pattern.temporal.jitter[0]", {"jitter": [[0.5, 0.5]], "jitter_range": 2, "resolve": {"filter": {"name": "box", "radius": 0.25}, "radius": 0}})
tmp("frame_pattern_bad", 400, "pattern.temporal.frame_pattern.kernels[0]", {"jitter": H8, "frame_pattern": {"kernels": [[[0, 0, 0.5]]]}})
tmp("frame_pattern_temporal", 400, "pattern.temporal.frame_pattern.temporal", {"jitter": H8, "frame_pattern": {"temporal": {"jitter": H8}}})
tmp("resolve_frame_no_tile", 400, "pattern.temporal.frame_pattern", {"jitter": H8, "frame_pattern": {"kernels": [[[0, 0, 1]], [[0, 0, 1]]]}, "resolve": {"filter": {"name": "gaussian"}}})
tmp("cut_frames_zero", 400, "pattern.temporal.cut_frames", {"jitter": H8, "cut_frames": 0})
tmp("cut_frames_huge", 400, "pattern.temporal.cut_frames", {"jitter": H8, "cut_frames": 4097})
tmp("work_bound", 400, "pattern.temporal", {"jitter": {"generator": "halton", "count": 1024}, "resolve": {"filter": {"name": "gaussian"}, "radius": 3}})
tmp("group_samples_limit", 400, "pattern.temporal.jitter", {"jitter": {"generator": "halton", "count": 1024}, "resolve": {"filter": {"name": "gaussian"}, "radius": 4}})
case("temporal_ok_256_phases", 200, None, body_json={"pattern": {"temporal": {"jitter": {"generator": "halton", "count": 256}, "blend": {"kind": "exponential", "alpha": 0.0001}}}}, check=OK)
case("temporal_lp", 400, "lp", body_json={"pattern": {"temporal": {"jitter": H8}}, "lp": 2})
# Exports of a temporal pattern: json, jitter-c/-hlsl, one phase in the point formats (handlers_export_temporal.c).
EXP = "/v1/patterns/export"
case("temporal_export_ok_jitter_c", 200, None, path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "jitter-c"}, check={"content_type_prefix": "text/plain"})
case("temporal_export_csv_no_phase", 400, "phase", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "csv"})
case("temporal_export_phase_too_big", 400, "phase", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "csv", "phase": 8})
case("temporal_export_phase_huge", 400, "phase", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "utk", "phase": 9223372036854775807})
case("temporal_export_phase_string", 400, "phase", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "xyw", "phase": "0"})
case("temporal_export_phase_with_json", 400, "phase", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "json", "phase": 0})
case("temporal_export_vulkan", 400, "format", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "vulkan"})
case("temporal_export_d3d12", 400, "format", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": "d3d12"})
case("temporal_export_jitter_spatial", 400, "format", path=EXP, body_json={"pattern": {"preset": "rgss"}, "format": "jitter-hlsl"})
case("temporal_export_phase_spatial", 400, "phase", path=EXP, body_json={"pattern": {"preset": "rgss"}, "format": "csv", "phase": 0})
case("temporal_export_bad_alpha", 400, "pattern.temporal.blend.alpha", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8, "blend": {"kind": "exponential", "alpha": 0}}}, "format": "jitter-c"})
case("temporal_export_format_number", 400, "format", path=EXP, body_json={"pattern": {"temporal": {"jitter": H8}}, "format": 1})
case("temporal_in_job", 400, "pattern.temporal", path="/v1/jobs", body_json={"kind": "optimize", "pattern": {"temporal": {"jitter": H8}}, "max_iterations": 1})
# The temporal-optimize job kind (proto/job_temporal_optimize.c).
TOPT = {"kind": "temporal-optimize", "max_iterations": 1, "seeds": 1}
def topt(name, field, **spec): case("temporal_optimize_" + name, 400, field, path="/v1/jobs", body_json=dict(TOPT, **spec))
case("temporal_optimize_ok", 202, None, path="/v1/jobs", body_json=dict(TOPT, family="T(4)"))
topt("no_family_no_pattern", "family")
topt("family_and_pattern", "family", family="T(8)", pattern={"temporal": {"jitter": H8}})
topt("family_zero", "family", family="T(0)")
topt("family_huge", "family", family="T(257)")
topt("family_overflow", "family", family="T(99999999999999999999)")
topt("family_spatial", "family", family="P(4,1+,2)")
topt("family_trailing", "family", family="T(8) ")
topt("family_number", "family", family=8)
topt("pattern_spatial", "pattern", pattern={"preset": "rgss"})
topt("pattern_bad_alpha", "pattern.temporal.blend.alpha", pattern={"temporal": {"jitter": H8, "blend": {"kind": "exponential", "alpha": 0}}})
topt("pattern_too_many", "pattern.temporal.jitter", pattern={"temporal": {"jitter": {"generator": "halton", "count": 257}}})
topt("pattern_with_blend", "blend", pattern={"temporal": {"jitter": H8}}, blend={"kind": "box"})
topt("blend_bad", "blend.kind", family="T(8)", blend={"kind": "median"})
topt("resolve_bad", "resolve.radius", family="T(8)", resolve={"filter": {"name": "gaussian"}, "radius": 9})
topt("frame_pattern_bad", "frame_pattern.preset", family="T(8)", frame_pattern={"preset": "nope"})
topt("resolve_frame_no_tile", "frame_pattern", family="T(8)", frame_pattern={"kernels": [[[0, 0, 1]], [[0, 0, 1]]]}, resolve={"filter": {"name": "gaussian"}})
topt("jitter_range_zero", "jitter_range", family="T(8)", jitter_range=0)
topt("seeds_zero", "seeds", family="T(8)", seeds=0)
topt("flicker_weight_nan", "flicker_weight", family="T(8)", flicker_weight="nan")
topt("flicker_cap_alone", "flicker_cap", family="T(8)", flicker_cap=0.1)
topt("flicker_with_resolve", "flicker_weight", family="T(8)", flicker_weight=1, resolve={"filter": {"name": "gaussian"}})
topt("grid_bits_zero", "grid.bits", family="T(8)", grid={"bits": 0})
topt("grid_d3d12", "grid", family="T(8)", grid={"bits": 4, "d3d12": True})
topt("grid_coarse", "grid.bits", family="T(8)", grid={"bits": 1}, jitter_range=0.5)
topt("order_bad", "order", family="T(8)", order="shuffle")
topt("method", "method", family="T(8)", method="minimax")
topt("max_iterations_zero", "max_iterations", family="T(8)", max_iterations=0)
topt("max_seconds_zero", "max_seconds", family="T(8)", max_seconds=0)
topt("angles_bad", "angles[0]", family="T(8)", angles=["x"])
# --- the temporal-render job kind and POST /v1/predict with a temporal pattern (issue 30 point 5)
TR = {"kind": "temporal-render", "scene": "rings", "size": [32, 32], "reference": {"spp": 16}}
def trj(name, status, field, **spec):
    case("temporal_render_" + name, status, field, path="/v1/jobs", body_json={**TR, **spec})
trj("spatial_pattern", 400, "pattern", pattern="rgss")
trj("no_pattern", 400, "pattern")
trj("animation_scene", 400, "scene.name", pattern={"temporal": {"jitter": H8}}, scene="rotating-triangle")
trj("bad_alpha", 400, "pattern.temporal.blend.alpha", pattern={"temporal": {"jitter": H8, "blend": {"kind": "exponential", "alpha": 0}}})
trj("pattern_extra_key", 400, "pattern.preset", pattern={"temporal": {"jitter": H8}, "preset": "rgss"})
trj("resolve_no_weight", 400, "pattern.temporal.jitter[0]", pattern={"temporal": {"jitter": [[0.5, 0.5]], "jitter_range": 2, "resolve": {"filter": {"name": "box", "radius": 0.25}, "radius": 0}}})
trj("work_bound", 400, "pattern.temporal", pattern={"temporal": {"jitter": {"generator": "halton", "count": 1024}, "resolve": {"filter": {"name": "gaussian"}, "radius": 3}}})
trj("unknown_key", 400, "frames", pattern={"temporal": {"jitter": H8}}, frames=4)
trj("tiles_not_bool", 400, "tiles", pattern={"temporal": {"jitter": H8}}, tiles="no")
case("temporal_render_phase_ok", 200, None, path="/v1/render", body_json={"scene": "rings", "size": [32, 32], "reference": {"spp": 16}, "pattern": {"temporal": {"jitter": H8}}, "phase": 7})
case("temporal_render_phase_past_n", 400, "phase", path="/v1/render", body_json={"scene": "rings", "size": [32, 32], "pattern": {"temporal": {"jitter": H8}}, "phase": 8})
case("temporal_render_phase_negative", 400, "phase", path="/v1/render", body_json={"scene": "rings", "size": [32, 32], "pattern": {"temporal": {"jitter": H8}}, "phase": -1})
case("temporal_render_phase_real", 400, "phase", path="/v1/render", body_json={"scene": "rings", "size": [32, 32], "pattern": {"temporal": {"jitter": H8}}, "phase": 1.0})
case("temporal_render_phase_spatial", 400, "phase", path="/v1/render", body_json={"scene": "rings", "size": [32, 32], "pattern": "rgss", "phase": 0})
case("temporal_render_phase_kernel_samples", 400, "pattern.temporal.jitter", path="/v1/render", body_json={"scene": "rings", "size": [32, 32], "pattern": {"temporal": {"jitter": {"generator": "halton", "count": 512}, "resolve": {"filter": {"name": "gaussian"}}}}})
case("temporal_render_phase_bad_blend", 400, "pattern.temporal.blend.kind", path="/v1/render", body_json={"scene": "rings", "pattern": {"temporal": {"jitter": H8, "blend": {"kind": "max"}}}})
case("temporal_in_compare_bad_alpha", 400, "patterns[0].temporal.blend.alpha", path="/v1/jobs", body_json={"kind": "compare", "scene": "rings", "patterns": [{"temporal": {"jitter": H8, "blend": {"kind": "exponential", "alpha": -1}}}]})
case("temporal_in_compare_rows", 400, "patterns[1].temporal", path="/v1/jobs", body_json={"kind": "compare", "scene": "rings", "patterns": ["rgss", {"temporal": {"jitter": {"generator": "halton", "count": 1024}}}, {"temporal": {"jitter": {"generator": "halton", "count": 1024}}}]})
case("temporal_in_compare_samples", 400, "patterns[0].temporal", path="/v1/jobs", body_json={"kind": "compare", "scene": "rings", "patterns": [{"temporal": {"jitter": {"generator": "halton", "count": 1024}, "frame_pattern": {"preset": "d3d-8x"}}}]})
case("temporal_in_animation", 400, "pattern.temporal", path="/v1/jobs", body_json={"kind": "animation", "scene": "rotating-triangle", "pattern": {"temporal": {"jitter": H8}}})
case("predict_temporal_ok", 200, None, path=PR, body_json={"pattern": {"temporal": {"preset": "halton23-8"}}, "scene": {"name": "half-plane", "angle": 27}})
case("predict_temporal_bad_alpha", 400, "pattern.temporal.blend.alpha", path=PR, body_json={"pattern": {"temporal": {"jitter": H8, "blend": {"kind": "exponential", "alpha": 2}}}})
case("predict_temporal_in_list_bad", 400, "patterns[1].temporal.jitter[1]", path=PR, body_json={"patterns": ["rgss", {"temporal": {"jitter": [[0, 0], [0.7, 0]]}}]})
case("predict_temporal_phase_samples", 400, "pattern.temporal", path=PR, body_json={"pattern": {"temporal": {"jitter": {"generator": "halton", "count": 1024}, "resolve": {"filter": {"name": "gaussian"}, "radius": 4}}}})
case("predict_temporal_kernel_samples", 400, "pattern.temporal.jitter", path=PR, body_json={"pattern": {"temporal": {"jitter": {"generator": "halton", "count": 512}, "resolve": {"filter": {"name": "gaussian"}}}}})
case("predict_temporal_phase_ok", 200, None, path=PR, body_json={"pattern": {"temporal": {"preset": "halton23-8"}}, "phase": 7})
case("predict_temporal_phase_past_n", 400, "phase", path=PR, body_json={"pattern": {"temporal": {"preset": "halton23-8"}}, "phase": 8})
case("predict_phase_spatial", 400, "phase", path=PR, body_json={"pattern": "rgss", "phase": 0})
case("predict_phase_patterns", 400, "phase", path=PR, body_json={"patterns": [{"temporal": {"preset": "halton23-8"}}], "phase": 0})
case("predict_temporal_work", 400, "pattern", path=PR, body_json={"scene": "rings", "pattern": {"temporal": {"jitter": {"generator": "halton", "count": 256}}}})
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "cases.jsonl"), "w") as f:
    for c in C:
        f.write(json.dumps(c, separators=(",", ":")) + "\n")
print(len(C))
