// Jobs view with the optimizer: a short optimize job started from the form (with a chosen step
// rule); its progress must reach done and its E2-against-run-time curve appear, with the API's
// trace points.

import { assert, eventually } from '../lib/check.mjs';
import { watchToDone } from './jobs.mjs';

export default async function optimizeSuite({ page, base, api, step, shot }) {
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
    await page.selectOption('#job-method', 'minimax');
    await page.fill('#job-label', 'from the form');
    await page.click('#job-submit');
    const status = await eventually(async () => {
      const t = await page.textContent('#job-form-status');
      return /job \S+ submitted|not started/.test(t) && t;
    }, { message: 'the submit answer' });
    const m = /job (\S+) submitted/.exec(status);
    assert(m, `job not started: ${status}`);
    id = m[1];
    await page.waitForSelector(`#jobs-table tr[data-job-id="${id}"]`);
    const label = await page.textContent(`#jobs-table tr[data-job-id="${id}"] td.label`);
    const job = await api('GET', `/v1/jobs/${id}`);
    assert(job.label === 'from the form' && label === job.label, `label in the list "${label}", API ${JSON.stringify(job.label)}`);
  });

  await step('optimize: progress reaches done and the E2-against-time curve appears', async () => {
    const seen = await watchToDone(page, id, 60000);
    const job = await api('GET', `/v1/jobs/${id}`);
    assert(job.state === 'done', `API says job ${id} is ${job.state}`);
    assert(Array.isArray(job.trace) && job.trace.length > 0, 'API job has no trace');
    await page.waitForFunction((n) => Number(document.getElementById('jd-trace').dataset.points) === n, job.trace.length, { timeout: 10000 });
    assert(await page.$('#jd-trace canvas'), 'no trace chart canvas');
    const e2Text = await page.textContent('#jd-e2');
    const last = job.trace[job.trace.length - 1].best_e2;
    console.log(`#   optimize job ${id}: states seen ${seen.join(' → ')}, best E2 shown ${e2Text}, result e2 ${job.result && job.result.e2}, last trace point ${last}`);
    assert(job.result && typeof job.result.e2 === 'number', 'the finished job has no result e2');
    assert(job.result.method === 'minimax', `the form asked for the minimax step rule, the job used ${job.result.method}`);
    assert(e2Text === job.result.e2.toFixed(6), `best E2 shown ${e2Text}, the job's result says ${job.result.e2}`);
    assert(Math.abs(last - job.result.e2) < 1e-12, `last trace point ${last} is not the result e2 ${job.result.e2}`);
    const dots = await page.$$eval('#jd-pattern g.dot-primary', (g) => g.length);
    assert(dots === job.result.best.mirrored.length, `best pattern drawn with ${dots} samples, result has ${job.result.best.mirrored.length}`);
    await shot('jobs');
  });

  await step('the optimized pattern appears in Families and opens in Evaluate with its E2', async () => {
    const job = await api('GET', `/v1/jobs/${id}`);
    await page.goto(`${base}/#/families`);
    await page.waitForFunction(() => /\d+ points/.test(document.getElementById('fam-status').textContent), null, { timeout: 30000 });
    const link = page.locator(`#fam-plot a.point-link[href$="job=${id}"]`);
    assert((await link.count()) === 1, `no point for job ${id} in Families`);
    await link.focus();
    await page.keyboard.press('Enter');
    await page.waitForFunction((e2) => Math.abs(Number(document.getElementById('ev-e2').dataset.e2) - e2) < 1e-9, job.result.e2, { timeout: 10000 });
    await shot('families-with-job');
  });

  await step('the JSON export is the pattern shown (its E2 is the job\'s best)', async () => {
    const job = await api('GET', `/v1/jobs/${id}`);
    const exported = await api('GET', `/v1/patterns/${id}/export?format=json`);
    const ev = await api('POST', '/v1/evaluate', { pattern: exported.pattern || exported });
    assert(Math.abs(ev.e2 - job.result.e2) < 1e-9, `exported pattern has E2 ${ev.e2}, the job's best is ${job.result.e2} (GET /v1/jobs/${id} best.e2 ${job.best && job.best.e2}): the export is not the best pattern`);
  });
}
