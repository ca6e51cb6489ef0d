"""The daemon's JSON Schemas (draft 2020-12), the ones in the repository's ``proto/schemas``.

The installed package carries a copy made at build time (``python/setup.py`` copies
``proto/schemas``; nothing is committed twice). Where that copy is missing (the package imported
from the source tree), ``$AALAB_SCHEMA_DIR`` or the repository's ``proto/schemas`` beside
``python/`` is used. Validation needs the optional ``jsonschema`` package (Debian
``python3-jsonschema``); loading the schemas does not.

The schemas' ``$id`` are relative (``aalab/kinds/optimize.spec.json``) and refer to each other
relatively (``../pattern.json``); jsonschema 4.10 (Debian 12) resolves a relative ``$id``
wrongly, so the validators here see them under an absolute base, which changes no reference.
"""

from __future__ import annotations

import copy
import json
import os
import threading
from typing import Any, Dict, List, Optional

from .errors import AalabError

_BASE = "https://aalab.invalid/"


def schema_dir() -> Optional[str]:
    """Directory of the schemas: the package's copy, ``$AALAB_SCHEMA_DIR``, or the repository's
    ``proto/schemas`` when the package is used from the source tree; None if none exists."""
    here = os.path.dirname(os.path.abspath(__file__))
    for d in (os.path.join(here, "schemas"), os.environ.get("AALAB_SCHEMA_DIR") or "",
              os.path.join(here, "..", "..", "proto", "schemas")):
        if d and os.path.isfile(os.path.join(d, "pattern.json")):
            return os.path.normpath(d)
    return None


class Schemas:
    """The schemas of one directory, loaded once, with cached validators (thread-safe)."""

    def __init__(self, directory: Optional[str] = None) -> None:
        d = directory or schema_dir()
        if d is None:
            raise AalabError("unavailable", "no JSON Schemas found: install the package from the "
                             "repository (pip install ./python) or set $AALAB_SCHEMA_DIR to "
                             "proto/schemas")
        self.directory = d
        self.raw: Dict[str, Any] = {}
        for root, _, files in os.walk(d):
            for f in sorted(files):
                if f.endswith(".json"):
                    path = os.path.join(root, f)
                    rel = os.path.relpath(path, d).replace(os.sep, "/")
                    with open(path, encoding="utf-8") as fh:
                        self.raw[rel] = json.load(fh)
        self._by_id = {}
        for rel, s in self.raw.items():
            c = copy.deepcopy(s)
            c["$id"] = _BASE + s.get("$id", "aalab/" + rel)
            self._by_id[c["$id"]] = c
        self._validators: Dict[str, Any] = {}
        self._lock = threading.Lock()

    def names(self) -> List[str]:
        """Relative paths of every schema (``pattern.json``, ``kinds/optimize.spec.json``)."""
        return sorted(self.raw)

    def validator(self, name: str) -> Any:
        """A jsonschema validator for ``name`` (``evaluate_response.json``, or
        ``tokens.json#/$defs/issued``)."""
        with self._lock:
            v = self._validators.get(name)
            if v is None:
                v = self._validators[name] = self._make(name)
            return v

    def _make(self, name: str) -> Any:
        try:
            import jsonschema
        except ImportError:
            raise AalabError("unavailable", "validation needs the jsonschema package "
                             "(Debian: python3-jsonschema)") from None
        path, _, pointer = name.partition("#")
        root = self._by_id.get(_BASE + "aalab/" + path)
        if root is None:
            raise AalabError("not_found", "no schema %s in %s" % (path, self.directory))
        schema = {"$ref": root["$id"] + "#" + pointer} if pointer else root
        try:  # jsonschema >= 4.18
            from referencing import Registry, Resource
            reg = Registry().with_resources(
                (k, Resource.from_contents(x)) for k, x in self._by_id.items())
            return jsonschema.Draft202012Validator(schema, registry=reg)
        except ImportError:  # 4.10 (Debian 12)
            resolver = jsonschema.RefResolver("" if pointer else root["$id"], schema,
                                              store=dict(self._by_id))
            return jsonschema.Draft202012Validator(schema, resolver=resolver)

    def errors(self, name: str, doc: Any) -> List[str]:
        """Every violation of schema ``name`` by ``doc``, each prefixed with its JSON path."""
        out = []
        for e in self.validator(name).iter_errors(doc):
            path = "".join("[%d]" % p if isinstance(p, int) else ".%s" % p
                           for p in e.absolute_path)
            out.append("%s: %s" % (path.lstrip(".") or "(root)", e.message[:300]))
        return out

    def validate(self, name: str, doc: Any) -> None:
        """Raises :class:`AalabError` (code ``protocol``) naming the first violations."""
        errs = self.errors(name, doc)
        if errs:
            raise AalabError("protocol", "answer does not match %s: %s"
                             % (name, "; ".join(errs[:5])), errs[0].split(":")[0])


_default: Optional[Schemas] = None
_default_lock = threading.Lock()


def default() -> Schemas:
    """The schemas of :func:`schema_dir`, loaded on first use (read-only afterwards)."""
    global _default
    with _default_lock:
        if _default is None:
            _default = Schemas()
        return _default
