"""Every answer the e2e tests receive is checked against its JSON Schema by route: the table
below maps (method, path, status) to a schema of proto/schemas. An answer the table does not
cover, or one that does not match its schema, raises AssertionError in the test that got it.

e2e_lib.Daemon.curl, aalabd_harness.Daemon.request (when RESPONSE_HOOK is set, as unix_users
does) and unix_users.User.request call check()."""

import json
import re

from schema_check import schemas

JSON = "application/json"

# (method, path regex, {status: schema}); schema None: no JSON body (checked by content type).
# Errors (status >= 400) of every /v1 route are error.json and are not listed.
ROUTES = [
    ("GET", r"/v1/health", {200: "health_response.json"}),
    ("GET", r"/v1/kinds", {200: "kinds_response.json"}),
    ("GET", r"/v1/presets", {200: "presets_response.json"}),
    ("GET", r"/v1/presets/[^/]+", {200: "preset_response.json"}),
    ("GET", r"/v1/filters", {200: "filters_response.json"}),
    ("GET", r"/v1/acuity", {200: "acuity_response.json"}),
    ("POST", r"/v1/evaluate", {200: "evaluate_response.json"}),
    ("POST", r"/v1/analyze", {200: "analyze_response.json"}),
    ("POST", r"/v1/jobs", {202: "job.json"}),
    ("GET", r"/v1/jobs", {200: "jobs_list.json"}),
    ("GET", r"/v1/jobs/[^/]+", {200: "job.json"}),
    ("PATCH", r"/v1/jobs/[^/]+", {200: "job.json"}),
    ("DELETE", r"/v1/jobs/[^/]+", {200: "job_delete_response.json",
                                   202: "job_delete_response.json"}),
    ("GET", r"/v1/usage", {200: "usage_response.json"}),
    ("POST", r"/v1/families/enumerate", {200: "enumerate_response.json"}),
    ("GET", r"/v1/patterns/[^/]+/export", {200: "export_response.json"}),
    ("POST", r"/v1/patterns/export", {200: "export_response.json"}),
    ("POST", r"/v1/render", {200: "render_response.json"}),
    ("POST", r"/v1/predict", {200: "predict_response.json"}),
    ("GET", r"/v1/tiles/[^/]+", {200: None}),
    ("POST", r"/v1/tokens", {201: "tokens.json#/$defs/issued"}),
    ("GET", r"/v1/tokens", {200: "tokens.json#/$defs/list"}),
    ("DELETE", r"/v1/tokens/[^/]+", {200: "tokens.json#/$defs/revoked"}),
]
# Not JSON: the dashboard's static files (TCP only), PNG tiles, the utk, xyw and csv exports.
NOT_JSON = [
    ("GET", r"/v1/tiles/[^/]+", "image/png"),
    ("GET", r"/v1/patterns/[^/]+/export", "text/plain"),
    ("POST", r"/v1/patterns/export", "text/plain"),
    ("GET", r"/v1/patterns/[^/]+/export", "application/octet-stream"),  # bin, rps
    ("POST", r"/v1/patterns/export", "application/octet-stream"),
]
STATIC = re.compile(r"^/(?!v1(/|$))")

_compiled = [(m, re.compile("^" + p + "$"), table) for m, p, table in ROUTES]

checked = {}  # schema -> count, for the tests' own summary

# Bodies above this size (the store tests' 1.9 MB patterns) are checked with every array cut to
# its first LONG_ARRAY_ITEMS items: a full check of 100,000 samples takes seconds in Python, and
# the items of one array share one schema. Only a maxItems bound below the true length is missed.
LARGE_BODY_BYTES = 256 * 1024
LONG_ARRAY_ITEMS = 64


def _cut_long_arrays(v):
    if isinstance(v, list):
        return [_cut_long_arrays(x) for x in v[:LONG_ARRAY_ITEMS]]
    if isinstance(v, dict):
        return {k: _cut_long_arrays(x) for k, x in v.items()}
    return v


def schema_for(method, path, status):
    """The schema of the answer, None for a non-JSON one; raises if the route is unknown."""
    if status >= 400:
        return "error.json"
    for m, rx, table in _compiled:
        if m == method and rx.match(path):
            if status in table:
                return table[status]
            raise AssertionError("%s %s answered %d, a status the route table does not list"
                                 % (method, path, status))
    raise AssertionError("%s %s (status %d): no schema for this route" % (method, path, status))


def check(method, path, status, headers, body):
    """Validates one answer. body: bytes or str; headers: lower-case names."""
    path = path.split("?", 1)[0].split("#", 1)[0]
    ctype = (headers.get("content-type") or "").split(";")[0].strip()
    if method == "HEAD" or status in (204, 304) or (status < 400 and STATIC.match(path)):
        return  # no body, or a dashboard file
    if status == 100:
        return
    name = schema_for(method, path, status)
    if name is None or ctype != JSON:
        for m, p, want in NOT_JSON:
            if m == method and re.match("^" + p + "$", path) and ctype == want and status < 400:
                return
        raise AssertionError("%s %s answered %d with Content-Type %r, no schema covers it"
                             % (method, path, status, ctype))
    if isinstance(body, bytes):
        body = body.decode("utf-8")
    try:
        doc = json.loads(body)
    except ValueError as e:
        raise AssertionError("%s %s answered %d with invalid JSON (%s): %r"
                             % (method, path, status, e, body[:200]))
    if len(body) > LARGE_BODY_BYTES:
        doc = _cut_long_arrays(doc)
    errors = schemas().errors(name, doc)
    # A job's result against its kind's result schema, for every kind (job.json's per-kind
    # branches need not list a new kind for its results to be checked).
    if not errors and name == "job.json" and isinstance(doc.get("result"), dict):
        result_schema = "kinds/%s.result.json" % doc.get("kind")
        if result_schema in schemas().raw:
            errors = ["result (%s): %s" % (result_schema, e)
                      for e in schemas().errors(result_schema, doc["result"])]
    if errors:
        raise AssertionError("%s %s answered %d not matching %s:\n  %s\nbody: %s"
                             % (method, path, status, name, "\n  ".join(errors[:5]), body[:600]))
    checked[name] = checked.get(name, 0) + 1
