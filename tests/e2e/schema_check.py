"""The JSON Schemas of proto/schemas (draft 2020-12) loaded once, and validators for them that
work with Debian 12's python3-jsonschema 4.10 (RefResolver) and with jsonschema >= 4.18
(referencing registry).

The schemas' "$id"s are relative ("aalab/kinds/optimize.spec.json") and refer to each other by
relative references ("../pattern.json"). jsonschema 4.10 joins a referenced schema's own $id
onto the current scope, which turns a relative $id into a wrong URL; so the copies validated
here carry their $ids under an absolute base, which changes no reference's meaning."""

import copy
import glob
import json
import os

try:
    import jsonschema
except ImportError as e:  # the e2e tests validate every answer: without a validator they fail
    raise ImportError("python3-jsonschema is needed (scripts/install-deps.sh)") from e

SCHEMA_DIR = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                           "proto", "schemas"))
BASE = "https://aalab.invalid/"


def schema_files():
    """Paths relative to SCHEMA_DIR of every schema file, sorted."""
    out = []
    for path in glob.glob(os.path.join(SCHEMA_DIR, "**", "*.json"), recursive=True):
        out.append(os.path.relpath(path, SCHEMA_DIR))
    return sorted(out)


def kind_names():
    """The job kinds: one kinds/<kind>.spec.json each, sorted by name."""
    tail = ".spec.json"
    return [rel[len("kinds/"):-len(tail)] for rel in schema_files()
            if rel.startswith("kinds/") and rel.endswith(tail)]


def load_raw():
    """{relative path: schema as written}; every one checked against the 2020-12 meta-schema."""
    raw = {}
    for rel in schema_files():
        with open(os.path.join(SCHEMA_DIR, rel)) as f:
            s = json.load(f)
        jsonschema.Draft202012Validator.check_schema(s)
        raw[rel] = s
    return raw


class Schemas:
    def __init__(self):
        self.raw = load_raw()
        self.by_id = {}
        for rel, s in self.raw.items():
            if s.get("$id") != "aalab/" + rel:
                raise ValueError("%s: $id %r, expected %r" % (rel, s.get("$id"), "aalab/" + rel))
            c = copy.deepcopy(s)
            c["$id"] = BASE + s["$id"]
            self.by_id[c["$id"]] = c
        self._validators = {}

    def validator(self, rel):
        """A validator for the schema at proto/schemas/<rel> (or rel#/json/pointer)."""
        if rel in self._validators:
            return self._validators[rel]
        path, _, pointer = rel.partition("#")
        root = self.by_id[BASE + "aalab/" + path]
        schema = {"$ref": root["$id"] + ("#" + pointer if pointer else "")} if pointer else root
        try:  # jsonschema >= 4.18
            from referencing import Registry, Resource
            reg = Registry().with_resources(
                (k, Resource.from_contents(x)) for k, x in self.by_id.items())
            v = jsonschema.Draft202012Validator(schema, registry=reg)
        except ImportError:  # Debian 12's 4.10
            # A wrapper {"$ref": ...} has no $id of its own: resolve it from the store.
            base = "" if pointer else root["$id"]
            resolver = jsonschema.RefResolver(base, schema, store=dict(self.by_id))
            v = jsonschema.Draft202012Validator(schema, resolver=resolver)
        self._validators[rel] = v
        return v

    def errors(self, rel, doc):
        """Messages of every violation of schema rel by doc, with the JSON path of each."""
        out = []
        for e in self.validator(rel).iter_errors(doc):
            path = "".join("[%d]" % p if isinstance(p, int) else ".%s" % p
                           for p in e.absolute_path)
            out.append("%s: %s" % (path or "(root)", e.message[:300]))
        return out


_SCHEMAS = None


def schemas():
    global _SCHEMAS
    if _SCHEMAS is None:
        _SCHEMAS = Schemas()
    return _SCHEMAS
