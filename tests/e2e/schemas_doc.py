"""The schemas and the API reference, without a daemon:
- every file in proto/schemas is a valid draft 2020-12 schema whose $id is aalab/<its path>;
- every job kind has a spec and a result schema; the spec schema takes the envelope and rejects
  unknown keys, and each of its examples validates against it;
- docs/api.md is what scripts/gen_api_doc.py makes of the schemas, and every property path of
  every schema (and of each $defs entry) appears in that schema's table in docs/api.md;
- the e2e response check fails on an unknown route, a wrong body and a wrong content type."""

import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "scripts"))

from schema_check import kind_names, schemas  # noqa: E402
import gen_api_doc  # noqa: E402
import response_check  # noqa: E402

KINDS = kind_names()  # every kind with a spec schema in proto/schemas/kinds
DOC = os.path.join(ROOT, "docs", "api.md")
BLOCK = re.compile(r"<!-- generated:begin table (\S+) -->\n(.*?)<!-- generated:end -->", re.S)


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def schema_roots(raw):
    """Every file, and every $defs entry with properties: the keys docs/api.md has tables for."""
    roots = []
    for rel in sorted(raw):
        roots.append(rel)
        for name in sorted(raw[rel].get("$defs", {})):
            key = "%s#/$defs/%s" % (rel, name)
            if gen_api_doc.field_paths(key):
                roots.append(key)
    return roots


def missing_fields(doc_text, raw):
    """[(schema key, path)] of every property path that docs/api.md does not show in the table
    of its schema (a $defs entry may also be shown in its file's table)."""
    tables = {}
    for key, body in BLOCK.findall(doc_text):
        tables[key] = tables.get(key, "") + body
    missing = []
    for key in schema_roots(raw):
        own = tables.get(key, "")
        parent = tables.get(key.partition("#")[0], "") if "#" in key else ""
        for path, _, _ in gen_api_doc.field_paths(key):
            needle = "`%s`" % path
            if needle not in own and needle not in parent:
                missing.append((key, path))
    return missing


def check_kinds(s):
    for kind in KINDS:
        spec, result = "kinds/%s.spec.json" % kind, "kinds/%s.result.json" % kind
        check(spec in s.raw and result in s.raw, "kind %s lacks a spec or result schema" % kind)
        sch = s.raw[spec]
        check({"$ref": "../job_envelope.json"} in sch.get("allOf", []),
              "%s does not take the envelope" % spec)
        check(sch.get("unevaluatedProperties") is False, "%s accepts unknown keys" % spec)
        check(sch["properties"]["kind"] == {"const": kind, "description": "the job kind"},
              "%s: kind is not const %r" % (spec, kind))
        check(s.raw[result].get("additionalProperties") is False,
              "%s: the result's top level is not closed" % result)
        examples = sch.get("examples") or []
        check(examples, "%s has no examples" % spec)
        for i, ex in enumerate(examples):
            errors = s.errors(spec, ex)
            check(not errors, "%s example %d does not validate: %s" % (spec, i, errors))
            check(ex["kind"] == kind, "%s example %d is of kind %s" % (spec, i, ex["kind"]))
            # The envelope is accepted, an unknown key and a wrong kind are not.
            env = dict(ex, label="l", priority=3, visibility="private", pinned=True)
            errors = s.errors(spec, env)
            check(not errors, "%s rejects the envelope: %s" % (spec, errors))
            check(s.errors(spec, dict(ex, bogus=1)), "%s accepts an unknown key" % spec)
            check(s.errors(spec, dict(ex, kind="nope")), "%s accepts another kind" % spec)
            check(s.errors(spec, dict(ex, priority=11)), "%s accepts priority 11" % spec)


def check_response_check():
    def fails(*args):
        try:
            response_check.check(*args)
        except AssertionError:
            return True
        return False
    j = {"content-type": "application/json"}
    check(fails("GET", "/v1/nowhere", 200, j, b"{}"), "an unknown route passed")
    check(fails("GET", "/v1/health", 200, j, b'{"status":"ok"}'), "a short health answer passed")
    check(fails("GET", "/v1/health", 200, {"content-type": "text/plain"}, b"ok"),
          "a text answer on a JSON route passed")
    check(fails("GET", "/v1/jobs/1", 404, j, b'{"error":{"code":"x"}}'), "a bad error passed")
    check(fails("POST", "/v1/jobs", 200, j, b"{}"), "an unlisted status passed")
    check(not fails("GET", "/v1/nowhere", 404, j,
                    b'{"error":{"code":"not_found","message":"m","field":""}}'),
          "a valid error failed")


def main():
    s = schemas()  # checks every file against the meta-schema and its $id
    check(len(s.raw) >= 30, "only %d schema files found" % len(s.raw))
    check_kinds(s)
    check_response_check()

    p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "gen_api_doc.py"), "--check"],
                       capture_output=True, text=True)
    check(p.returncode == 0, "gen_api_doc --check: %s%s" % (p.stdout, p.stderr))

    with open(DOC) as f:
        doc = f.read()
    paths = [p for key in schema_roots(s.raw) for p, _, _ in gen_api_doc.field_paths(key)]
    for probe in ("ranked[].config.corners", "rows[].stats", "per_seed[].initial_e2", "levels",
                  "opt_wp.method", "frames[].tiles.difference", "grid.bits", "error.field"):
        check(probe in paths, "the field walk misses %s" % probe)
    missing = missing_fields(doc, s.raw)
    check(not missing, "docs/api.md lacks these schema fields: %s" % missing)
    # The check can fail: drop one row of the optimize result table and it is reported.
    row = "| `per_seed[].initial_e2` |"
    check(row in doc, "row %r not in docs/api.md" % row)
    cut = re.sub(re.escape(row) + r"[^\n]*\n", "", doc, count=1)
    check(("kinds/optimize.result.json", "per_seed[].initial_e2") in missing_fields(cut, s.raw),
          "a removed row was not reported")
    print("schemas_doc: ok (%d schemas, %d fields)" % (len(s.raw), len(paths)))


if __name__ == "__main__":
    main()
