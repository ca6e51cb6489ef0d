// Jobs view: start a short optimize job from the form, watch its progress bar reach done and
// its error-against-time curve appear; export; cancel a long job.

import { assert, eventually } from '../lib/check.mjs';

export default async function jobsSuite({ page, base, api, step, shot }) {
  let id;
  await step('start a short optimize job from the form', async () => {
    const health = await api('GET', '/v1/health');
    assert(!Array.isArray(health.job_kinds) || health.job_kinds.includes('optimize'), `this aalabd has no optimize job kind (it has ${JSON.stringify(health.job_kinds)}): the optimizer is not built in`);
    await page.goto(`${base}/#/jobs`);
    await page.selectOption('#job-start', 'family');
    await page.fill('#job-family', 'P(4,1+,2)');
    await page.fill('#job-seeds', '4');
    await page.fill('#job-seconds', '2');
    await page.fill('#job-rng', '7');
    await page.click('#job-submit');
    const status = await eventually(async () => {
      const t = await page.textContent('#job-form-status');
      return /job \S+ submitted|not started/.test(t) && t;
    }, { message: 'the submit answer' });
    const m = /job (\S+) submitted/.exec(status);
    assert(m, `job not started: ${status}`);
    id = m[1];
    await page.waitForSelector(`#jobs-table tr[data-job-id="${id}"]`);
  });

  await step('progress reaches done and the trace curve appears', async () => {
    const seen = new Set();
    await eventually(async () => {
      const row = await page.$eval(`#jobs-table tr[data-job-id="${id}"]`, (tr) => ({ state: tr.dataset.state, progress: Number(tr.querySelector('progress').value) }));
      seen.add(row.state);
      return row.state === 'done' && row.progress === 1;
    }, { timeout: 60000, interval: 200, message: `job ${id} to be done with progress 1` });
    const job = await api('GET', `/v1/jobs/${id}`);
    const j = job.job || job;
    assert(j.state === 'done', `API says job ${id} is ${j.state}`);
    await page.waitForFunction(() => Number(document.getElementById('jd-trace').dataset.points) > 0, null, { timeout: 10000 });
    assert(await page.$('#jd-trace canvas'), 'no trace chart canvas');
    const e2Text = await page.textContent('#jd-e2');
    assert(/^\d\.\d{6}$/.test(e2Text), `best E2 shown "${e2Text}"`);
    const shownState = await page.$eval('#jobs-table tr[data-job-id="' + id + '"] td.state', (td) => td.textContent);
    assert(/✓\s*done/.test(shownState), `state cell "${shownState}" should carry a symbol and the word`);
    console.log(`#   job ${id}: states seen in the list ${[...seen].join(' → ')}, best E2 ${e2Text}`);
    await shot('jobs');
  });

  await step('export the best pattern as JSON', async () => {
    await page.click('#jd-export button[data-format="json"]');
    const text = await eventually(async () => {
      const t = await page.textContent('#jd-export-text');
      return t && t.length > 2 && t;
    }, { message: 'export text' });
    assert(!text.startsWith('export failed'), text);
    JSON.parse(text);
  });

  await step('cancel a running job from the list', async () => {
    const r = await api('POST', '/v1/jobs', { kind: 'optimize', family: 'P(4,1+,3)', seeds: 64, max_seconds: 60, rng_seed: 3 });
    const cid = String(r.id);
    await page.waitForSelector(`#jobs-table tr[data-job-id="${cid}"]`, { timeout: 10000 });
    await page.click(`#jobs-table tr[data-job-id="${cid}"] button[data-action="cancel"]`);
    await eventually(async () => (await page.getAttribute(`#jobs-table tr[data-job-id="${cid}"]`, 'data-state')) === 'cancelled', { timeout: 15000, message: `job ${cid} cancelled` });
  });
}
