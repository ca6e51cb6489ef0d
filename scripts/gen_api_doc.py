#!/usr/bin/env python3
"""Regenerates the field tables and the per-kind curl examples of docs/api.md from the JSON
Schemas in proto/schemas, so the reference cannot drift from them. Standard library only.

    python3 scripts/gen_api_doc.py          # rewrite docs/api.md in place
    python3 scripts/gen_api_doc.py --check  # exit 1 if docs/api.md is not up to date

docs/api.md is prose with generated blocks between
    <!-- generated:begin table SCHEMA -->  ...  <!-- generated:end -->
    <!-- generated:begin example KIND -->  ...  <!-- generated:end -->
where SCHEMA is a path under proto/schemas, optionally with #/$defs/NAME. Only the inside of
those blocks is rewritten. A job kind with schemas in proto/schemas/kinds but no section yet gets
one (heading, the spec schema's description, both tables and the example) above the marker
    <!-- kind sections end -->
so adding a kind needs no hand edit here; its prose can be written afterwards."""

import json
import os
import re
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCHEMA_DIR = os.path.join(ROOT, "proto", "schemas")
DOC = os.path.join(ROOT, "docs", "api.md")

BLOCK = re.compile(
    r"(<!-- generated:begin (table|example) (\S+) -->\n)(.*?)(<!-- generated:end -->)", re.S)

KINDS_END = "<!-- kind sections end -->"
# What each kind's curl example prints of the finished job (jq 1.6: keys as .["key"]); a kind
# not listed prints its whole result (DEFAULT_SUMMARY).
SUMMARY = {
    "optimize": '.["result"] | [.["e2"], .["family"], .["method"], .["seeds_run"]] | @tsv',
    "family-sweep": ('.["result"]["ranked"][] | [.["rank"], .["e2"], .["config"]["interior"]]'
                     ' | @tsv'),
    "random-stats": ('.["result"] | [.["random"]["min"], .["random"]["avg"], .["random"]["max"],'
                     ' .["opt_w"]["e2"], .["opt_wp"]["e2"]] | @tsv'),
    "table3": ('.["result"]["rows"][] | [.["distribution"], .["columns"]["opt_w"]["mean"],'
               ' .["columns"]["opt_w"]["sd"], .["columns"]["opt_wp"]["mean"]] | @tsv'),
    "temporal-optimize": ('.["result"] | [.["e2"], .["mean_phase_e2"], .["f2"], .["family"],'
                          ' .["seeds_run"]] | @tsv'),
    "compare": ('.["result"]["rows"][] | [.["name"], .["samples_per_pixel"], .["e2"], .["rmse"]]'
                ' | @tsv'),
    "animation": '.["result"]["frames"][] | [.["frame"], .["rmse"], .["max_dev"]] | @tsv',
    "reference-convergence": '.["result"]["rows"][] | [.["spp"], .["rmse"], .["seconds"]] | @tsv',
    "temporal-render": ('.["result"]["phases"][] | [.["phase"], .["e2"], .["rmse"],'
                        ' .["predicted_rmse"]] | @tsv'),
    "sleep": '.["result"]["slept_seconds"]',
}
DEFAULT_SUMMARY = '.["result"] | tojson'


def load(rel):
    with open(os.path.join(SCHEMA_DIR, rel)) as f:
        return json.load(f)


def resolve_local(root, ref):
    node = root
    for part in ref[2:].split("/"):
        node = node[part]
    return node


def ref_name(ref):
    """'../pattern.json' -> 'pattern.json'; '#/$defs/tile' -> '#/$defs/tile'."""
    if ref.startswith("#"):
        return ref
    path, _, frag = ref.partition("#")
    return os.path.basename(path) + ("#" + frag if frag else "")


def fmt_value(v):
    return json.dumps(v, ensure_ascii=False)


def squares(values):
    n = len(values)
    return n > 3 and values == [i * i for i in range(1, n + 1)]


def type_of(s):
    if s is True or s == {}:
        return "any"
    if "$ref" in s:
        return "`%s`" % ref_name(s["$ref"])
    if "const" in s:
        return "`%s`" % fmt_value(s["const"])
    if "enum" in s:
        kinds = sorted({"string" if isinstance(v, str) else "integer" if isinstance(v, int)
                        else "number" for v in s["enum"]})
        return " or ".join(kinds)
    for key in ("oneOf", "anyOf"):
        if key in s:
            return " or ".join(type_of(x) for x in s[key])
    if "allOf" in s:
        refs = [x for x in s["allOf"] if "$ref" in x]
        return type_of(refs[0]) if refs else "object"
    t = s.get("type")
    if isinstance(t, list):
        return " or ".join(t)
    if t == "array":
        if "prefixItems" in s:
            return "[%s]" % ", ".join(type_of(x) for x in s["prefixItems"])
        items = s.get("items")
        return "array of %s" % type_of(items) if isinstance(items, dict) else "array"
    return t or "any"


def range_of(s):
    out = []
    if "enum" in s:
        vals = s["enum"]
        if squares(vals):
            out.append("a square k² for k = 1..%d (1, 4, 9, ..., %d)" % (len(vals), vals[-1]))
        else:
            out.append("one of " + ", ".join("`%s`" % fmt_value(v) for v in vals))
    lo, hi = s.get("minimum"), s.get("maximum")
    xlo, xhi = s.get("exclusiveMinimum"), s.get("exclusiveMaximum")
    if lo is not None or hi is not None or xlo is not None or xhi is not None:
        left = "%s ≤ " % fmt_value(lo) if lo is not None else (
            "%s < " % fmt_value(xlo) if xlo is not None else "")
        right = " ≤ %s" % fmt_value(hi) if hi is not None else (
            " < %s" % fmt_value(xhi) if xhi is not None else "")
        out.append(left + "x" + right)
    if "minItems" in s or "maxItems" in s:
        out.append("%s..%s items" % (s.get("minItems", 0), s.get("maxItems", "∞")))
    if "maxLength" in s:
        out.append("at most %d characters" % s["maxLength"])
    if "multipleOf" in s:
        out.append("a multiple of %s" % fmt_value(s["multipleOf"]))
    if "pattern" in s:
        out.append("matches `%s`" % s["pattern"])
    items = s.get("items")
    if isinstance(items, dict) and s.get("type") == "array":
        inner = range_of(items)
        if inner:
            out.append("each: " + inner)
    return "; ".join(out)


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def walk(root, node, path, required, rows, depth=0):
    """Appends (path, schema, required) for every property under node, following local
    references and descending into objects, arrays of objects and oneOf/anyOf/allOf branches."""
    if depth > 12 or not isinstance(node, dict):
        return
    if "$ref" in node and node["$ref"].startswith("#"):
        walk(root, resolve_local(root, node["$ref"]), path, required, rows, depth + 1)
    for key in ("oneOf", "anyOf", "allOf"):
        for sub in node.get(key, []):
            if isinstance(sub, dict) and not ("$ref" in sub and not sub["$ref"].startswith("#")):
                walk(root, sub, path, required, rows, depth + 1)
    req = set(node.get("required", []))
    for name, sub in node.get("properties", {}).items():
        p = path + name
        if not any(r[0] == p for r in rows):
            rows.append((p, sub, name in req))
        elif name in req:
            rows[:] = [(r[0], r[1], True) if r[0] == p else r for r in rows]
        if isinstance(sub, dict):
            walk(root, sub, p + ".", required, rows, depth + 1)
            items = sub.get("items")
            if isinstance(items, dict):
                walk(root, items, p + "[].", required, rows, depth + 1)


def section_root(key):
    rel, _, frag = key.partition("#")
    root = load(rel)
    return root, (resolve_local(root, "#" + frag) if frag else root)


def field_paths(key):
    """Every property path of the schema root key (a file, or file#/$defs/NAME)."""
    root, node = section_root(key)
    rows = []
    walk(root, node, "", set(), rows)
    return rows


def table(key):
    root, node = section_root(key)
    rows = field_paths(key)
    lines = []
    if node.get("title") and node is root:
        lines.append("*%s* (`proto/schemas/%s`)" % (node["title"], key))
        lines.append("")
    if not rows:
        lines.append("(no fields)")
        return "\n".join(lines) + "\n"
    lines.append("| field | type | required / default | range | meaning |")
    lines.append("|---|---|---|---|---|")
    for path, s, req in rows:
        if not isinstance(s, dict):
            s = {}
        default = "required" if req else (
            "`%s`" % fmt_value(s["default"]) if "default" in s else "")
        if req and "default" in s:
            default = "`%s`" % fmt_value(s["default"])
        desc = s.get("description", "")
        lines.append("| `%s` | %s | %s | %s | %s |" % (
            path, cell(type_of(s)), cell(default), cell(range_of(s)), cell(desc)))
    return "\n".join(lines) + "\n"


def example(kind):
    spec = load("kinds/%s.spec.json" % kind)
    body = json.dumps(spec["examples"][0], ensure_ascii=False)
    return ("```sh\n"
            "ID=$(curl -sS --unix-socket \"$SOCK\" -H 'Content-Type: application/json' -d @- \\\n"
            "       http://aalab/v1/jobs <<'JSON' | jq '.[\"id\"]'\n"
            "%s\n"
            "JSON\n"
            ")\n"
            "aalab_wait \"$ID\"   # prints done\n"
            "curl -sS --unix-socket \"$SOCK\" \"http://aalab/v1/jobs/$ID\" |\n"
            "  jq -r '%s'\n"
            "```\n") % (body, SUMMARY.get(kind, DEFAULT_SUMMARY))


def kind_names():
    """Every kind with a spec schema in proto/schemas/kinds, sorted."""
    tail = ".spec.json"
    return sorted(f[:-len(tail)] for f in os.listdir(os.path.join(SCHEMA_DIR, "kinds"))
                  if f.endswith(tail))


def kind_section(kind):
    """A new kind's section: its blocks are filled in by render()."""
    spec = load("kinds/%s.spec.json" % kind)
    lines = ["### %s" % kind, ""]
    if spec.get("description"):
        lines += [spec["description"], ""]
    for what in ("spec", "result"):
        lines += ["<!-- generated:begin table kinds/%s.%s.json -->" % (kind, what),
                  "<!-- generated:end -->", ""]
    lines += ["<!-- generated:begin example %s -->" % kind, "<!-- generated:end -->", "", ""]
    return "\n".join(lines)


def add_kind_sections(text):
    """text with a section for every kind whose example block it lacks, above KINDS_END."""
    missing = [k for k in kind_names()
               if "<!-- generated:begin example %s -->" % k not in text]
    if not missing:
        return text
    if KINDS_END not in text:
        raise SystemExit("docs/api.md lacks the marker %s" % KINDS_END)
    return text.replace(KINDS_END, "".join(kind_section(k) for k in missing) + KINDS_END, 1)


def render(text):
    text = add_kind_sections(text)

    def sub(m):
        what, key = m.group(2), m.group(3)
        inner = table(key) if what == "table" else example(key)
        return m.group(1) + inner + m.group(5)
    return BLOCK.sub(sub, text)


def main():
    with open(DOC) as f:
        old = f.read()
    new = render(old)
    if "--check" in sys.argv[1:]:
        if new != old:
            print("docs/api.md is out of date: run python3 scripts/gen_api_doc.py")
            return 1
        return 0
    if new != old:
        with open(DOC, "w") as f:
            f.write(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
