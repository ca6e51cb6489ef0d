// Tiles view: render a tile and see the pattern, reference and difference images with stats,
// and the edge model's prediction beside the measured RMSE (POST /v1/predict).

import { assert, eventually } from '../lib/check.mjs';

/* The vertices of a polar plot's curve (path "Mx,yLx,y…Z") in drawing units, as offsets from
 * the plot's centre with y up. */
async function polarVertices(page, selector) {
  return page.$eval(selector, (svg) => {
    const path = svg.querySelector('.polar-curve');
    if (!path) return null;
    // The centre: drawPolar puts it at (SIZE/2, SIZE/2 + 6) of its 360-wide view box.
    const [cx, cy] = [180, 186];
    return [...path.getAttribute('d').matchAll(/[ML](-?[\d.]+),(-?[\d.]+)/g)].map((m) => [+m[1] - cx, cy - +m[2]]);
  });
}

export default async function tilesSuite({ page, base, api, step, shot, consoleProblems }) {
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

  // The tile of the first step, as the page sends it.
  const star = { pattern: { preset: 'quincunx' }, scene: { name: 'siemens-star', width: 64, height: 64 }, reference: { spp: 256 } };

  await step('predicted RMSE beside the measured one, with their ratio and the uncovered shares', async () => {
    const pred = (await api('POST', '/v1/predict', star)).predictions[0];
    const measured = (await api('POST', '/v1/render', star)).stats.rmse;
    await eventually(async () => (await page.getAttribute('#tile-pred', 'data-state')) === 'done', { message: 'prediction shown' });
    assert((await page.textContent('#tile-rmse')) === measured.toFixed(3), 'measured RMSE is the API render\'s');
    const shown = await page.textContent('#tile-pred-rmse');
    assert(shown === pred.predicted_rmse.toFixed(3), `predicted RMSE shown ${shown}, API ${pred.predicted_rmse}`);
    const ratio = await page.textContent('#tile-pred-ratio');
    assert(ratio === (measured / pred.predicted_rmse).toFixed(3), `ratio shown ${ratio}, API ${measured / pred.predicted_rmse}`);
    // The star's centre is below the pixel scale and its rays are partly pixel-locked.
    assert(pred.subpixel_area_share > 0 && pred.locked_share > 0, 'the star has locked and sub-pixel parts');
    const locked = await page.textContent('#tile-pred-locked');
    assert(locked.startsWith(`${(pred.locked_share * 100).toFixed(1)} %`), `locked share "${locked}", API ${pred.locked_share}`);
    const sub = await page.textContent('#tile-pred-subpixel');
    assert(sub.startsWith(`${(pred.subpixel_area_share * 100).toFixed(1)} %`) && /not predicted/.test(sub), `sub-pixel share "${sub}", API ${pred.subpixel_area_share}`);
  });

  await step('the scene\'s L(θ) and the pattern\'s E1(θ) are drawn to scale; the costliest angles listed', async () => {
    const r = await api('POST', '/v1/predict', { ...star, e1_by_angle: true });
    const pred = r.predictions[0];
    for (const [sel, values, what] of [['#tile-polar-edges svg', r.edges.length, 'L(θ)'], ['#tile-polar-e1 svg', pred.e1_by_angle, 'E1(θ)']]) {
      const pts = await polarVertices(page, sel);
      assert(pts && pts.length === 360, `${what}: ${pts && pts.length} vertices, want 360 (180 bins, both half-turns)`);
      // Each vertex at its bin's angle (and the opposite one), at a radius proportional to the
      // API's value there: within the path's 0.1-unit rounding of where it belongs.
      const top = values.indexOf(Math.max(...values));
      const scale = Math.hypot(...pts[top]) / values[top];
      assert(scale > 0, `${what}: the largest value is drawn away from the centre`);
      for (let k = 0; k < 360; k++) {
        const d = k % 180;
        const a = (k * Math.PI) / 180;
        const want = [values[d] * scale * Math.cos(a), values[d] * scale * Math.sin(a)];
        const off = Math.hypot(pts[k][0] - want[0], pts[k][1] - want[1]);
        assert(off < 0.1, `${what} at ${k}°: drawn at ${pts[k]}, want ${want}`);
      }
      const label = await page.$eval(sel, (svg) => svg.querySelector('.polar-argmax-label').textContent);
      assert(label.includes(`@ ${top}°`), `${what}: maximum label "${label}", API maximum at ${top}°`);
      const aria = await page.getAttribute(sel, 'aria-label');
      assert(aria.endsWith(`maximum ${values[top].toFixed(4)} at ${top}°`), `${what}: aria-label "${aria}"`);
    }
    // The costliest angles are marked on the pattern's curve and listed with their shares.
    const marks = await page.$$eval('#tile-polar-e1 .polar-mark', (m) => m.map((c) => +c.dataset.angle));
    const want = pred.angles.slice(0, 6).map((a) => a.angle);
    assert(JSON.stringify([...new Set(marks)]) === JSON.stringify(want), `marks at ${marks}, costliest angles ${want}`);
    const rows = await page.$$eval('#tile-pred-angles-table tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent.trim())));
    want.forEach((a, i) => {
      assert(rows[i][0] === `${a}°`, `row ${i}: angle ${rows[i][0]}, want ${a}°`);
      assert(rows[i][1] === `${(pred.angles[i].share * 100).toFixed(1)} %`, `row ${i}: share ${rows[i][1]}, API ${pred.angles[i].share}`);
    });
    const rest = pred.angles.slice(6).reduce((s, a) => s + a.share, 0);
    assert(rows[6][0] === `${pred.angles.length - 6} other angles` && rows[6][1] === `${(rest * 100).toFixed(1)} %`, `rest row ${rows[6]}`);
    const bar = await page.$eval('#tile-pred-angles-table tbody tr .share-bar', (b) => b.getBoundingClientRect().width / b.parentElement.getBoundingClientRect().width);
    assert(Math.abs(bar - pred.angles[0].share) < 0.03, `first bar ${bar} of its track, share ${pred.angles[0].share}`);
  });

  await step('while a render runs: progress shown, the prediction arrives, the page answers', async () => {
    // Hold the render request so that it is certainly running while the page is checked.
    let release;
    const held = new Promise((r) => (release = r));
    let sent;
    const continued = new Promise((r) => (sent = r));
    const hold = async (route) => {
      await held;
      await route.continue();
      sent();
    };
    await page.route('**/v1/render', hold);
    try {
      await page.selectOption('#tile-scene', 'half-plane');
      await page.click('#tile-render');
      await page.waitForSelector('#tile-progress:not([hidden])', { timeout: 5000 });
      const half = { ...star, scene: { ...star.scene, name: 'half-plane' } };
      const pred = (await api('POST', '/v1/predict', half)).predictions[0];
      await eventually(async () => (await page.textContent('#tile-pred-rmse')) === pred.predicted_rmse.toFixed(3), { message: 'the half-plane prediction shown while the render runs' });
      assert((await page.textContent('#tile-pred-ratio')) === '—', 'no ratio against the star\'s measured RMSE');
      const t0 = await page.textContent('#tile-elapsed');
      await page.fill('#tile-zoom', '3'); // the page answers input while the request is held
      assert((await page.textContent('#tile-zoom-out')) === '3×', 'zoom moved while rendering');
      await eventually(async () => (await page.textContent('#tile-elapsed')) !== t0, { message: 'elapsed time advances' });
      assert(await page.isDisabled('#tile-render'), 'the render button waits for the render');
    } finally {
      release();
      await continued;
      await page.unroute('**/v1/render', hold);
    }
    await page.waitForSelector('#tile-progress', { state: 'hidden', timeout: 60000 });
    const measured = (await api('POST', '/v1/render', { ...star, scene: { ...star.scene, name: 'half-plane' } })).stats.rmse;
    const pred = (await api('POST', '/v1/predict', { ...star, scene: { ...star.scene, name: 'half-plane' } })).predictions[0];
    assert((await page.textContent('#tile-pred-ratio')) === (measured / pred.predicted_rmse).toFixed(3), 'ratio of the half-plane render');
    // The default half-plane's edge is locked to the pixel grid: all of its predicted error.
    assert((await page.textContent('#tile-pred-locked')).startsWith('100.0 %'), 'locked half-plane');
    await shot('tiles-predict');
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

  await step('a failed prediction and render are shown with the field the daemon names', async () => {
    // The pattern list still offers a job that has been deleted since: both requests fail.
    const r = await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 0.05, pattern: { preset: 'rgss' } });
    const id = String(r.id);
    await eventually(async () => (await api('GET', `/v1/jobs/${id}`)).state === 'done', { message: `job ${id} done` });
    await page.goto(`${base}/#/families`);
    await page.goto(`${base}/#/tiles`);
    await page.waitForSelector(`#tile-pattern option[value="job:${id}"]`, { state: 'attached', timeout: 10000 });
    await api('DELETE', `/v1/jobs/${id}?purge=1`);
    const before = consoleProblems.length;
    await page.selectOption('#tile-pattern', `job:${id}`);
    await page.click('#tile-render');
    await eventually(async () => (await page.getAttribute('#tile-pred', 'data-state')) === 'failed', { message: 'prediction failed' });
    const predStatus = await page.textContent('#tile-pred-status');
    assert(/^prediction failed: .*\(field pattern\.job\)/.test(predStatus), `prediction status "${predStatus}"`);
    assert((await page.getAttribute('#tile-pred-status', 'class')).includes('error-text'), 'shown as an error');
    assert((await page.textContent('#tile-pred-rmse')) === '—', 'no predicted RMSE left from before');
    assert((await page.$$('#tile-polar-e1 svg, #tile-polar-edges svg')).length === 0, 'no plots left from before');
    await page.waitForFunction(() => /render failed/.test(document.getElementById('tile-status').textContent), null, { timeout: 60000 });
    const status = await page.textContent('#tile-status');
    assert(/\(field pattern\.job\)/.test(status), `render status "${status}"`);
    await shot('tiles-predict-error');
    // The refused requests this step provoked are expected; nothing else.
    const provoked = consoleProblems.splice(before);
    const unexpected = provoked.filter((m) => !(/\b400\b/.test(m) && /\/v1\/(predict|render)\b/.test(m)));
    consoleProblems.push(...unexpected);
    assert(provoked.length >= 2 && !unexpected.length, `console: ${provoked.join('; ')}`);
    await page.selectOption('#tile-pattern', 'preset:quincunx'); // the comparison below starts from a good tile
    await eventually(async () => (await page.getAttribute('#tile-pred', 'data-state')) === 'done', { message: 'prediction back' });
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
      assert(line[6] === r.predicted_rmse.toFixed(3), `${r.name}: predicted RMSE shown ${line[6]}, API ${r.predicted_rmse}`);
      assert(line[7] === (r.rmse / r.predicted_rmse).toFixed(3), `${r.name}: measured/predicted shown ${line[7]}`);
    }
    const caption = await page.textContent('#cmp-table caption');
    assert(caption.includes(`Spearman ρ ${job.result.prediction.spearman.toFixed(3)}`), `caption "${caption}"`);
    const points = await page.$$eval('#cmp-plot .point-marker', (m) => m.length);
    assert(points === 3, `${points} points in the error-against-time plot`);
    await shot('tiles-compare');
  });
}
