"""Runs every shell example of docs/api.md, in order and in one bash with set -euo pipefail,
against a daemon on a temporary socket (test kinds enabled). Each job kind's example must end
done with a result that validates against kinds/<kind>.result.json; the schemas' other examples
are submitted too, and GET /v1/kinds must serve the schemas and examples of proto/schemas."""

import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)

from schema_check import kind_names, schemas  # noqa: E402
from e2e_lib import Daemon, check  # noqa: E402

KINDS = kind_names()  # every kind with a spec schema in proto/schemas/kinds
DOC = os.path.join(ROOT, "docs", "api.md")
FENCE = re.compile(r"(<!-- generated:begin example (\S+) -->\n)?```sh\n(.*?)```", re.S)


def doc_script():
    """The doc's sh blocks as one script; after a kind's example it prints '@@job KIND ID'."""
    with open(DOC) as f:
        text = f.read()
    parts, kinds = [], []
    for n, m in enumerate(FENCE.finditer(text)):
        kind = m.group(2)
        line = text.count("\n", 0, m.start(3)) + 1
        parts.append("echo '@@block %d line %d' >&2\n%s" % (n, line, m.group(3)))
        if kind:
            kinds.append(kind)
            parts.append('echo "@@job %s $ID"\n' % kind)
    return "set -euo pipefail\n" + "\n".join(parts), kinds


def main():
    s = schemas()
    script, kinds = doc_script()
    check(sorted(kinds) == sorted(KINDS), "docs/api.md has examples for %s" % kinds)
    d = Daemon(sys.argv[1], tcp=False).start()
    try:
        with tempfile.TemporaryDirectory(prefix="aalab-doc-") as cwd:
            env = dict(os.environ, SOCK=d.sock)
            p = subprocess.run(["bash", "-c", script], cwd=cwd, env=env, capture_output=True,
                               text=True, timeout=280)
        blocks = [x for x in p.stderr.splitlines() if x.startswith("@@block")]
        check(p.returncode == 0, "a docs/api.md example failed (exit %d) in %s\nstdout:\n%s\n"
              "stderr:\n%s" % (p.returncode, blocks[-1] if blocks else "?", p.stdout[-3000:],
                               p.stderr[-3000:]))
        jobs = dict(line.split()[1:3] for line in p.stdout.splitlines()
                    if line.startswith("@@job "))
        for kind in KINDS:
            job = d.get("/v1/jobs/%s" % jobs[kind]).json()  # job.json: checked by response_check
            check(job["kind"] == kind and job["state"] == "done",
                  "%s example ended %s: %s" % (kind, job["state"], job.get("error")))
            errors = s.errors("kinds/%s.result.json" % kind, job["result"])
            check(not errors, "%s result does not validate: %s" % (kind, errors))
            for i, ex in enumerate(s.raw["kinds/%s.spec.json" % kind]["examples"][1:], 1):
                r = d.post("/v1/jobs", ex)
                check(r.status == 202, "%s example %d: %r" % (kind, i, r))
                j = d.wait_job(r.json()["id"], timeout=120)
                check(j["state"] == "done", "%s example %d ended %s" % (kind, i, j["state"]))
                errors = s.errors("kinds/%s.result.json" % kind, j["result"])
                check(not errors, "%s example %d result: %s" % (kind, i, errors))
        # The daemon serves the schemas it was built with.
        r = d.get("/v1/kinds")
        check(r.status == 200, "GET /v1/kinds: %r" % r)
        served = {k["name"]: k for k in r.json()["kinds"]}
        check(sorted(served) == sorted(KINDS), "GET /v1/kinds lists %s" % sorted(served))
        check(r.json()["envelope_schema"] == s.raw["job_envelope.json"],
              "GET /v1/kinds serves another envelope schema")
        for kind in KINDS:
            spec = s.raw["kinds/%s.spec.json" % kind]
            check(served[kind]["spec_schema"] == spec, "%s: served spec schema differs" % kind)
            check(served[kind]["result_schema"] == s.raw["kinds/%s.result.json" % kind],
                  "%s: served result schema differs" % kind)
            check(served[kind]["examples"] == spec["examples"], "%s: served examples differ" % kind)
    except BaseException:
        print(d.log_text())
        raise
    finally:
        d.cleanup()
    print("e2e_api_doc: ok (%d kinds)" % len(KINDS))


if __name__ == "__main__":
    main()
