// Validates every JSON answer of the daemon that a browser test sees against its JSON Schema
// (draft 2020-12, ajv) from proto/schemas/: the page's own requests and the test's API calls.

import fs from 'node:fs';
import path from 'node:path';
import Ajv2020 from 'ajv/dist/2020.js';

/* Endpoint -> schema file (relative to proto/schemas). An answer of an endpoint not listed here
 * is counted apart and named in the suite's output. */
const ROUTES = [
  { method: 'GET', re: /^\/v1\/health$/, schema: 'health_response.json' },
  { method: 'GET', re: /^\/v1\/presets$/, schema: 'presets_response.json' },
  { method: 'GET', re: /^\/v1\/presets\/[^/]+$/, schema: 'preset_response.json' },
  { method: 'GET', re: /^\/v1\/filters$/, schema: 'filters_response.json' },
  { method: 'GET', re: /^\/v1\/acuity$/, schema: 'acuity_response.json' },
  { method: 'GET', re: /^\/v1\/kinds$/, schema: 'kinds_response.json' },
  { method: 'GET', re: /^\/v1\/jobs$/, schema: 'jobs_list.json' },
  { method: 'GET', re: /^\/v1\/jobs\/\d+$/, schema: 'job.json' },
  { method: 'POST', re: /^\/v1\/jobs$/, schema: 'job.json' },
  { method: 'DELETE', re: /^\/v1\/jobs\/\d+$/, schema: 'job_delete_response.json' },
  { method: 'GET', re: /^\/v1\/patterns\/\d+\/export$/, schema: 'export_response.json' },
  { method: 'POST', re: /^\/v1\/evaluate$/, schema: 'evaluate_response.json' },
  { method: 'POST', re: /^\/v1\/render$/, schema: 'render_response.json' },
  { method: 'POST', re: /^\/v1\/predict$/, schema: 'predict_response.json' },
  { method: 'POST', re: /^\/v1\/analyze$/, schema: 'analyze_response.json' },
];

function schemaFiles(dir) {
  const out = [];
  for (const e of fs.readdirSync(dir, { withFileTypes: true })) {
    const p = path.join(dir, e.name);
    if (e.isDirectory()) out.push(...schemaFiles(p));
    else if (e.name.endsWith('.json')) out.push(p);
  }
  return out;
}

export class ResponseValidator {
  constructor(schemaDir) {
    this.dir = schemaDir;
    this.ajv = new Ajv2020({ allErrors: true, strict: false });
    this.ids = new Map(); // file relative to schemaDir -> $id
    for (const file of schemaFiles(schemaDir)) {
      const schema = JSON.parse(fs.readFileSync(file, 'utf8'));
      this.ajv.addSchema(schema);
      this.ids.set(path.relative(schemaDir, file), schema.$id);
    }
    this.validated = 0;
    this.unschemed = new Set();
    this.problems = [];
  }

  /* Checks one answer; a problem is recorded (and reported by the runner), not thrown, so that
   * a page's own request cannot hide it. */
  check(method, urlPath, status, body) {
    let file = null;
    if (status >= 400) file = 'error.json';
    else {
      const route = ROUTES.find((r) => r.method === method && r.re.test(urlPath));
      if (route) file = route.schema;
    }
    if (!file) {
      this.unschemed.add(`${method} ${urlPath.replace(/\/\d+(?=\/|$)/g, '/{id}').replace(/\/v1\/presets\/[^/]+$/, '/v1/presets/{name}')}`);
      return;
    }
    const id = this.ids.get(file);
    if (!id) {
      this.problems.push(`${method} ${urlPath}: no schema ${file} in ${this.dir}`);
      return;
    }
    const validate = this.ajv.getSchema(id);
    this.validated++;
    if (!validate(body)) {
      const errs = validate.errors.slice(0, 5).map((e) => `${e.instancePath || '/'} ${e.message}${e.params ? ' ' + JSON.stringify(e.params) : ''}`);
      this.problems.push(`${method} ${urlPath} (HTTP ${status}) does not match ${file}: ${errs.join('; ')}`);
    }
  }

  /* Watches a playwright page: every JSON answer under /v1/. */
  watch(page) {
    page.on('response', async (resp) => {
      const url = new URL(resp.url());
      if (!url.pathname.startsWith('/v1/')) return;
      if (!(resp.headers()['content-type'] || '').includes('json')) return;
      let body;
      try {
        body = await resp.json();
      } catch {
        return; // the page navigated away before the body arrived
      }
      this.check(resp.request().method(), url.pathname, resp.status(), body);
    });
  }
}
