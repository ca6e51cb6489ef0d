// Tiles view: render a tile and see the pattern, reference and difference images with stats.

import { assert, eventually } from '../lib/check.mjs';

export default async function tilesSuite({ page, base, api, step, shot }) {
  await step('render Siemens star with Quincunx: three images and the statistics', async () => {
    await page.goto(`${base}/#/tiles`);
    await page.waitForSelector('#tile-pattern option[value="preset:quincunx"]', { state: 'attached' });
    await page.selectOption('#tile-scene', 'siemens-star');
    await page.selectOption('#tile-pattern', 'preset:quincunx');
    await page.selectOption('#tile-size', '64');
    await page.selectOption('#tile-ref', '256');
    await page.click('#tile-render');
    await page.waitForFunction(() => /rendered|render failed|with/.test(document.getElementById('tile-status').textContent), null, { timeout: 60000 });
    const status = await page.textContent('#tile-status');
    assert(!status.startsWith('render failed'), status);
    for (const k of ['pattern', 'reference', 'difference']) {
      const size = await page.$eval(`#tile-img-${k}`, (img) => [img.naturalWidth, img.naturalHeight, img.dataset.loaded]);
      assert(size[0] === 64 && size[1] === 64 && size[2] === 'true', `${k} image: ${JSON.stringify(size)}`);
    }
    const rmse = await page.textContent('#tile-rmse');
    assert(/^\d+\.\d{3}$/.test(rmse), `RMSE shown "${rmse}"`);
    assert(await page.$('#tile-hist canvas'), 'no histogram chart');
    await page.fill('#tile-zoom', '4');
    const w = await page.$eval('#tile-img-difference', (img) => img.getBoundingClientRect().width);
    assert(Math.abs(w - 256) < 1, `zoom 4× should show the 64 px tile 256 px wide, got ${w}`);
    await shot('tiles');
  });

  await step('a job result renders too (pattern {"job": id})', async () => {
    const r = await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 0.1, pattern: { preset: 'flipquad' } });
    const id = String(r.id);
    await eventually(async () => (await api('GET', `/v1/jobs/${id}`)).state === 'done', { message: `job ${id} done` });
    await page.goto(`${base}/#/families`); // leave and come back: the pattern list is rebuilt on show
    await page.goto(`${base}/#/tiles`);
    await page.waitForSelector(`#tile-pattern option[value="job:${id}"]`, { state: 'attached', timeout: 10000 });
    await page.selectOption('#tile-pattern', `job:${id}`);
    await page.click('#tile-render');
    await page.waitForFunction((i) => document.getElementById('tile-status').textContent.includes(`job #${i}`) || /render failed/.test(document.getElementById('tile-status').textContent), id, { timeout: 60000 });
    const status = await page.textContent('#tile-status');
    assert(!status.startsWith('render failed'), status);
    for (const k of ['pattern', 'reference', 'difference']) {
      const ok = await page.$eval(`#tile-img-${k}`, (img) => img.dataset.loaded === 'true' && img.naturalWidth > 0);
      assert(ok, `${k} image of the job render not loaded`);
    }
  });

  await step('comparison job: error against render time plotted, one row per pattern', async () => {
    const wanted = ['centroid', 'quincunx', 'rgss'];
    for (const box of await page.$$('#cmp-patterns input[type=checkbox]')) {
      const v = await box.getAttribute('value');
      if (wanted.includes(v.replace(/^preset:/, ''))) await box.check();
      else await box.uncheck();
    }
    await page.click('#cmp-start');
    await page.waitForFunction(() => /comparison job \S+: (done|failed|cancelled|interrupted)|not started/.test(document.getElementById('cmp-status').textContent), null, { timeout: 90000 });
    const status = await page.textContent('#cmp-status');
    assert(/: done/.test(status), status);
    const id = /comparison job (\S+):/.exec(status)[1];
    const job = await api('GET', `/v1/jobs/${id}`);
    const rows = (job.result && job.result.rows) || [];
    assert(rows.length === 3, `API result has ${rows.length} rows`);
    const shown = await page.$$eval('#cmp-table tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
    assert(shown.length === 3, `table shows ${shown.length} rows`);
    for (const r of rows) {
      const line = shown.find((c) => c[0] === r.name);
      assert(line, `no table row for ${r.name}`);
      assert(line[3] === r.rmse.toFixed(3), `${r.name}: RMSE shown ${line[3]}, API ${r.rmse}`);
    }
    const points = await page.$$eval('#cmp-plot .point-marker', (m) => m.length);
    assert(points === 3, `${points} points in the error-against-time plot`);
    await shot('tiles-compare');
  });
}
