// Families view: one point per preset, grouped into family series, each point a link that opens
// the pattern in Evaluate.

import { assert } from '../lib/check.mjs';

export default async function familiesSuite({ page, base, api, step, shot }) {
  await step('every preset is plotted as a link, one series per family', async () => {
    const presets = await api('GET', '/v1/presets');
    const list = Array.isArray(presets) ? presets : presets.presets;
    await page.goto(`${base}/#/families`);
    await page.waitForFunction(() => /\d+ points/.test(document.getElementById('fam-status').textContent), null, { timeout: 30000 });
    const status = await page.textContent('#fam-status');
    assert(!/could not/.test(status), status);
    const links = await page.$$eval('#fam-plot a.point-link', (a) => a.map((x) => x.getAttribute('href')));
    assert(links.length === list.length, `${links.length} points for ${list.length} presets`);
    const series = await page.$$eval('#fam-legend .legend-item', (s) => s.map((x) => x.textContent.trim()));
    assert(series.length >= 3 && series.every((s) => /^P\(.+,n\)$/.test(s)), `series ${JSON.stringify(series)}`);
    const withPublished = list.filter((p) => typeof p.published_e2 === 'number');
    const table = await page.$$eval('#fam-table tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
    for (const p of withPublished) {
      const row = table.find((c) => c[1] === p.name);
      assert(row && row[4] === String(p.published_e2), `${p.name}: published E2 shown "${row && row[4]}", API ${p.published_e2}`);
    }
    await shot('families');
  });

  await step('a point opens its pattern in Evaluate (keyboard)', async () => {
    await page.focus('#fam-plot a.point-link[href$="preset=rgss"]');
    await page.keyboard.press('Enter');
    await page.waitForFunction(() => location.hash.startsWith('#/evaluate') && document.getElementById('ev-preset').value === 'rgss', null, { timeout: 10000 });
    const ref = await api('POST', '/v1/evaluate', { pattern: { preset: 'rgss' } });
    await page.waitForFunction((e2) => Number(document.getElementById('ev-e2').dataset.e2) === e2, ref.e2, { timeout: 10000 });
  });
}
