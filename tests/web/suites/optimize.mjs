// Jobs view with the optimizer: a short optimize job started from the form; its progress must
// reach done and its E2-against-run-time curve appear, with the API's trace points.

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

  await step('optimize: progress reaches done and the E2-against-time curve appears', async () => {
    const seen = await watchToDone(page, id, 60000);
    const job = await api('GET', `/v1/jobs/${id}`);
    assert(job.state === 'done', `API says job ${id} is ${job.state}`);
    assert(Array.isArray(job.trace) && job.trace.length > 0, 'API job has no trace');
    await page.waitForFunction((n) => Number(document.getElementById('jd-trace').dataset.points) === n, job.trace.length, { timeout: 10000 });
    assert(await page.$('#jd-trace canvas'), 'no trace chart canvas');
    const e2Text = await page.textContent('#jd-e2');
    const last = job.trace[job.trace.length - 1].best_e2;
    assert(/^\d\.\d{6}$/.test(e2Text), `best E2 shown "${e2Text}"`);
    console.log(`#   optimize job ${id}: states seen ${seen.join(' → ')}, best E2 shown ${e2Text}, last trace point ${last}`);
    await shot('jobs');
  });
}
