"""The package reads the daemon's JSON Schemas (proto/schemas): the installed copy is the
repository's, every schema is valid draft 2020-12, and every job kind's example from
GET /v1/kinds runs through Client.submit with its result valid against the kind's result
schema (the job-kind contract)."""

import os

import jsonschema
import pytest

import aalab
from aalab import schemas

REPO_SCHEMAS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "proto",
                            "schemas")


def test_package_schemas_are_the_repository_s():
    s = schemas.default()
    repo = schemas.Schemas(REPO_SCHEMAS)
    assert s.names() == repo.names() and len(s.names()) >= 30
    assert s.raw == repo.raw, "the installed package's schemas are stale: pip install ./python"
    for name in s.names():
        jsonschema.Draft202012Validator.check_schema(s.raw[name])


@pytest.mark.skipif(not os.environ.get("AALAB_TEST_INSTALLED"),
                    reason="AALAB_TEST_INSTALLED unset: the package may be used from python/")
def test_the_installed_package_is_tested():
    # scripts/test.sh's python stage: the tests import the venv's copy, schemas included.
    pkg = os.path.dirname(aalab.__file__)
    assert "site-packages" in pkg, pkg
    assert schemas.schema_dir() == os.path.join(pkg, "schemas")


def test_validate_reports_the_path():
    s = schemas.default()
    s.validate("error.json", {"error": {"code": "x", "message": "m", "field": ""}})
    with pytest.raises(aalab.AalabError) as e:
        s.validate("evaluate_response.json", {"e2": "high"})
    assert e.value.code == "protocol" and "e2" in e.value.message
    assert s.errors("tokens.json#/$defs/revoked", {"id": 1, "revoked": True}) == []
    with pytest.raises(aalab.AalabError):
        s.validator("nope.json")


def test_every_kind_example_meets_its_result_schema(client):
    s = schemas.default()
    jobs = []
    for kind in client.kinds():
        example = kind["examples"][0]
        assert s.errors("kinds/%s.spec.json" % kind["name"], example) == []
        jobs.append((kind["name"], client.submit(example)))
    for name, job in jobs:
        job.wait(progress=False, timeout=120, poll=0.1)
        assert job.state == "done", (name, job.info.get("error"))
        assert s.errors("kinds/%s.result.json" % name, job.result) == [], name


def test_requests_the_package_builds_meet_the_request_schemas(tmp_path):
    import numpy as np
    from aalab import formats
    s = schemas.default()
    f = tmp_path / "p.csv"
    formats.write(f, [[0.25, 0.25, 0.5], [0.75, 0.75, 0.5]])
    # (pattern argument, weights option): points without w need filter or equal.
    patterns = [("rgss", None), ({"mirrored": [[0.5, 0.1, 1.0]]}, None),
                (np.array([[0.5, 0.5]]), "equal"), (f, None),
                (formats.loads("0.5 0.5\n", "utk"), "filter")]
    for p, weights in patterns:
        body = {"pattern": aalab.as_pattern(p, weights=weights), "detail": True}
        assert s.errors("evaluate_request.json", body) == [], p
        assert s.errors("export_request.json", {"pattern": body["pattern"], "format": "csv"}) == []
    bad = {"pattern": {"points": {"format": "svg", "text": ""}}}
    assert s.errors("evaluate_request.json", bad)
