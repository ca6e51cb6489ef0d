// Jobs view, with the daemon's harmless "sleep" kind: progress, trace, best pattern, exports and
// cancel. The optimize job itself is the optimize suite.

import { assert, eventually } from '../lib/check.mjs';

export async function rowOf(page, id) {
  return page.$eval(`#jobs-table tr[data-job-id="${id}"]`, (tr) => ({ state: tr.dataset.state, progress: Number(tr.querySelector('progress').value) }));
}

export async function watchToDone(page, id, timeout) {
  const seen = [];
  await eventually(async () => {
    const row = await rowOf(page, id);
    if (seen[seen.length - 1] !== row.state) seen.push(row.state);
    return row.state === 'done' && row.progress === 1;
  }, { timeout, interval: 150, message: `job ${id} to be done with progress 1` });
  return seen;
}

export default async function jobsSuite({ page, base, api, step, shot, daemon, consoleProblems }) {
  const auth = { headers: { Authorization: `Bearer ${daemon.token}` } };
  await step('a job (sleep kind, with a pattern) shows progress to done, its trace, best pattern and exports', async () => {
    await page.goto(`${base}/#/jobs`);
    const r = await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 1.5, pattern: { preset: 'rgss' } });
    const id = String(r.id);
    await page.goto(`${base}/#/jobs?job=${id}`);
    const seen = await watchToDone(page, id, 20000);
    console.log(`#   sleep job ${id}: states seen ${seen.join(' → ')}`);
    const job = await api('GET', `/v1/jobs/${id}`);
    await page.waitForFunction((n) => Number(document.getElementById('jd-trace').dataset.points) === n, job.trace.length, { timeout: 5000 });
    assert(job.trace.length > 1, `API trace has ${job.trace.length} points`);
    assert(await page.$('#jd-trace canvas'), 'no trace chart canvas');
    const dots = await page.$$eval('#jd-pattern g.dot-primary', (g) => g.length);
    assert(dots === 4, `best pattern (RGSS) should draw 4 samples, found ${dots}`);
    for (const format of ['json', 'utk', 'xyw', 'csv', 'vulkan', 'd3d12']) {
      await page.click(`#jd-export button[data-format="${format}"]`);
      await page.waitForFunction((f) => document.getElementById('jd-download').download.includes(`.${f === 'utk' ? 'dat' : f}`), format, { timeout: 5000 });
      const text = await page.textContent('#jd-export-text');
      const ref = await fetch(`${base}/v1/patterns/${id}/export?format=${format}`, auth).then((x) => x.text());
      if (['utk', 'xyw', 'csv'].includes(format)) assert(text === ref, `${format} export shown differs from the API's`);
      else assert(JSON.stringify(JSON.parse(text)) === JSON.stringify(JSON.parse(ref)), `${format} export shown differs from the API's`);
    }
    await shot('jobs-detail');
  });

  await step('cancel a running job from the list', async () => {
    const r = await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 120 });
    const cid = String(r.id);
    await page.waitForSelector(`#jobs-table tr[data-job-id="${cid}"][data-state="running"]`, { timeout: 10000 });
    await page.click(`#jobs-table tr[data-job-id="${cid}"] button[data-action="cancel"]`);
    await eventually(async () => (await page.getAttribute(`#jobs-table tr[data-job-id="${cid}"]`, 'data-state')) === 'cancelled', { timeout: 15000, message: `job ${cid} cancelled` });
    const shown = await page.textContent(`#jobs-table tr[data-job-id="${cid}"] td.state`);
    assert(/⊘\s*cancelled/.test(shown), `state cell "${shown}" should carry a symbol and the word`);
  });

  await step('first visit without a token: the page asks for one and sends no request that would be refused', async () => {
    const before = consoleProblems.length;
    const apiCalls = [];
    const onRequest = (req) => new URL(req.url()).pathname.startsWith('/v1/') && apiCalls.push(req.url());
    await page.evaluate(() => localStorage.clear());
    page.on('request', onRequest);
    await page.goto(`${base}/`);
    await page.waitForSelector('#token-form:not([hidden])', { timeout: 10000 });
    await page.waitForTimeout(1500); // a health poll or a view would have asked by now
    page.off('request', onRequest);
    assert(apiCalls.length === 0, `the page sent ${apiCalls.length} API requests without a token: ${apiCalls.join(', ')}`);
    assert(/no API token/.test(await page.textContent('#health')), 'the status line should say that a token is needed');
    assert(consoleProblems.length === before, `console: ${consoleProblems.slice(before).join('; ')}`);
    // The URL the daemon's start-up prints (scripts/run.sh, aalab token) carries the token.
    await page.goto(`${base}/#token=${encodeURIComponent(daemon.token)}`);
    await page.waitForFunction(() => localStorage.getItem('aalab.token') && !location.hash.includes('token='));
    await eventually(async () => /aalabd/.test(await page.textContent('#health')), { timeout: 10000, message: 'health line with the token' });
  });

  await step('without a valid token the API is refused (401) and the page asks for the token', async () => {
    const before = consoleProblems.length;
    for (const p of ['/v1/health', '/v1/jobs', '/v1/presets']) {
      const r = await fetch(`${base}${p}`);
      assert(r.status === 401, `GET ${p} without a token: HTTP ${r.status}`);
    }
    assert((await fetch(`${base}/`)).status === 200, 'the dashboard page itself needs no token');
    // A token that was revoked: issued over the socket, revoked, then used by the page.
    const { unixRequest } = await import('../lib/daemon.mjs');
    const issued = await unixRequest(daemon.socket, 'POST', '/v1/tokens', { label: 'to revoke' });
    assert(issued.status === 201, `issue: ${issued.status}`);
    const revoked = await unixRequest(daemon.socket, 'DELETE', `/v1/tokens/${issued.json.id}`);
    assert(revoked.status === 200, `revoke: ${revoked.status}`);
    await page.evaluate((t) => localStorage.setItem('aalab.token', t), issued.json.token);
    await page.goto(`${base}/#/jobs`);
    await page.reload();
    await page.waitForSelector('#token-form:not([hidden])', { timeout: 10000 });
    // The user pastes a good token: the form closes and the views load again.
    await page.fill('#token-input', daemon.token);
    await page.click('#token-form button[type=submit]');
    await page.waitForSelector('#token-form', { state: 'hidden', timeout: 5000 });
    await eventually(async () => !/unreachable/.test(await page.textContent('#health')), { timeout: 10000, message: 'health line back after the token' });
    // The browser logs the refused requests this step provoked; those, and only those, are expected.
    const provoked = consoleProblems.splice(before);
    const unexpected = provoked.filter((m) => !/\b401\b/.test(m));
    consoleProblems.push(...unexpected);
    assert(provoked.length > unexpected.length, 'the revoked token should have been refused with 401');
  });
}
