// Layout at 1400x1000 and 1000x800 (issue 34, defects 3 and 10): no view is wider than the window
// (document.documentElement.scrollWidth), also after a CSV export of a P(16,16,4)-sized pattern,
// and no two text labels of a plot (any SVG of the page) overlap.

import { assert } from '../lib/check.mjs';
import { overlappingLabels } from '../lib/labels.mjs';

const SIZES = [
  { width: 1400, height: 1000 },
  { width: 1000, height: 800 },
];

/* A P(16,16,4)-sized pattern: 16 kernels of 64 samples on a jittered 8x8 grid, weights 1/64. */
function bigPattern() {
  const kernels = [];
  for (let k = 0; k < 16; k++) {
    const kernel = [];
    for (let i = 0; i < 64; i++) kernel.push([((i % 8) + 0.5) / 8 - 0.5 + ((k * 7 + i) % 5) * 0.001, (Math.floor(i / 8) + 0.5) / 8 - 0.5, 1 / 64]);
    kernels.push(kernel);
  }
  return { kernels };
}

/* Plot text drawn smaller than 11 px on screen (font size times the SVG's scale). */
function smallText(page) {
  return page.evaluate(() => {
    const out = [];
    for (const svg of document.querySelectorAll('main svg')) {
      const vb = svg.viewBox && svg.viewBox.baseVal;
      const r = svg.getBoundingClientRect();
      if (!r.width) continue;
      const scale = vb && vb.width ? Math.min(r.width / vb.width, r.height / vb.height) : 1;
      for (const t of svg.querySelectorAll('text')) {
        if (!t.textContent.trim() || !t.getClientRects().length) continue;
        const px = parseFloat(getComputedStyle(t).fontSize) * scale;
        if (px < 10.5) out.push(`${svg.id || svg.parentElement.id}: "${t.textContent.trim()}" ${px.toFixed(1)} px`);
      }
    }
    return out;
  });
}

async function checkWidth(page, what) {
  const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, inner: window.innerWidth }));
  assert(w.scroll <= w.inner, `${what}: page ${w.scroll} px wide in a ${w.inner} px window`);
}

export default async function layoutSuite({ page, base, api, step, artifacts }) {
  let id;
  await step('a finished job with a P(16,16,4)-sized pattern', async () => {
    const r = await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 0.3, pattern: bigPattern() });
    id = String(r.id);
    for (let i = 0; i < 100; i++) {
      if ((await api('GET', `/v1/jobs/${id}`)).state === 'done') return;
      await new Promise((res) => setTimeout(res, 100));
    }
    throw new Error(`job ${id} not done in 10 s`);
  });

  await step('16 kernels: the polar plots draw the kernel picked in their menu, or all', async () => {
    await page.goto(`${base}/#/evaluate?job=${id}`);
    await page.waitForFunction(() => document.querySelectorAll('#ev-polar-weighted path.polar-curve').length === 16);
    const options = await page.$$eval('#ev-polar-kernel option', (o) => o.map((x) => x.value));
    assert(options.length === 17 && options[0] === 'all', `picker options ${JSON.stringify(options)}`);
    assert(await page.isVisible('#ev-polar-kernel'), 'the kernel picker is hidden');
    await page.selectOption('#ev-polar-kernel', '5');
    await page.waitForFunction(() => document.querySelectorAll('#ev-polar-weighted path.polar-curve').length === 1);
    for (const plot of ['#ev-polar-weighted', '#ev-polar-e1']) {
      const k = await page.$$eval(`${plot} path.polar-curve`, (p) => p.map((x) => x.dataset.kernel));
      assert(JSON.stringify(k) === '["5"]', `${plot} draws kernels ${JSON.stringify(k)}`);
    }
    await page.selectOption('#ev-polar-kernel', 'all');
    await page.waitForFunction(() => document.querySelectorAll('#ev-polar-e1 path.polar-curve').length === 16);
    // A preset of one kernel has no picker.
    await page.goto(`${base}/#/evaluate?preset=rgss`);
    await page.waitForFunction(() => document.querySelectorAll('#ev-polar-weighted path.polar-curve').length === 1);
    assert(!(await page.isVisible('#ev-polar-kernel')), 'a one-kernel pattern shows a kernel picker');
  });

  await step("the P(16,16,4)-sized pattern's weight labels cover no dot and no other label", async () => {
    await page.goto(`${base}/#/jobs?job=${id}`);
    await page.waitForSelector('#jd-pattern g.dot-primary');
    const bad = await page.evaluate(() => {
      const dots = [...document.querySelectorAll('#jd-pattern circle.dot-shape')].map((c) => c.getBoundingClientRect());
      const labels = [...document.querySelectorAll('#jd-pattern .dot-label')].map((t) => t.getBoundingClientRect());
      const out = [];
      const inter = (a, b, m) => Math.min(a.right, b.right) - Math.max(a.left, b.left) > m && Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top) > m;
      labels.forEach((l, i) => {
        // A circle's box corners stick out of it: a label box overlapping its middle half is on the dot.
        for (const d of dots) {
          const core = { left: d.left + d.width / 4, right: d.right - d.width / 4, top: d.top + d.height / 4, bottom: d.bottom - d.height / 4 };
          if (inter(l, core, 0.5)) out.push(`label ${i} on a dot`);
        }
        for (const m of labels.slice(i + 1)) if (inter(l, m, 1)) out.push(`label ${i} on another label`);
      });
      return { out, labels: labels.length, dots: dots.length };
    });
    assert(!bad.out.length, `${bad.out.length} overlaps of ${bad.labels} labels, e.g. ${bad.out.slice(0, 5).join('; ')}`);
  });

  // A finished job of each kind with a detail view of its own: its tables, plots and images
  // are checked at both sizes too (compare with two patterns at 2 spp, as in defect 6).
  const kindJobs = {};
  await step('a finished job of each kind', async () => {
    const specs = {
      optimize: { kind: 'optimize', family: 'P(4,1+,2)', seeds: 2, max_iterations: 20, rng_seed: 3 },
      table3: { kind: 'table3', family: 'P(4,4,2)', seeds: 2, count: 10, max_iterations: 30, rng_seed: 3 },
      compare: { kind: 'compare', scene: { name: 'siemens-star', width: 32, height: 32 }, reference: { spp: 64 }, patterns: [{ preset: 'centroid' }, { preset: 'quincunx' }, { preset: 'flipquad' }, { preset: 'hasselgren-f' }, { preset: 'rgss' }] },
      animation: { kind: 'animation', scene: { name: 'rotating-triangle', frames: 3, width: 32, height: 32 }, reference: { spp: 64 }, pattern: { preset: 'rgss' } },
      'reference-convergence': { kind: 'reference-convergence', scene: { name: 'siemens-star', width: 32, height: 32 }, levels: [16, 64], baseline_spp: 256 },
    };
    for (const [k, spec] of Object.entries(specs)) kindJobs[k] = String((await api('POST', '/v1/jobs', spec)).id);
    for (const [k, jid] of Object.entries(kindJobs)) {
      let j;
      for (let i = 0; i < 600; i++) {
        j = await api('GET', `/v1/jobs/${jid}`);
        if (!['queued', 'running'].includes(j.state)) break;
        await new Promise((res) => setTimeout(res, 100));
      }
      assert(j.state === 'done', `${k} job ${jid}: ${j.state}`);
    }
  });

  for (const size of SIZES) {
    const tag = `${size.width}x${size.height}`;
    await step(`${tag}: every view fits the window, plot labels do not overlap`, async () => {
      await page.setViewportSize(size);
      const views = [
        ['evaluate?preset=quincunx', () => page.waitForFunction(() => document.getElementById('ev-e2').dataset.e2)],
        [`evaluate?job=${id}`, () => page.waitForFunction(() => document.getElementById('ev-preset').value === '__custom')],
        ['families', () => page.waitForFunction(() => /\d+ points/.test(document.getElementById('fam-status').textContent), null, { timeout: 30000 })],
        [`jobs?job=${id}`, () => page.waitForSelector('#jd-pattern g.dot-primary')],
        ['tiles', () => page.waitForTimeout(500)],
        ...Object.entries(kindJobs).map(([k, jid]) => [`jobs?job=${jid}&kind=${k}`, () => page.waitForFunction((x) => document.getElementById('jd-kind').dataset.kind === x, k, { timeout: 20000 })]),
      ];
      const problems = [];
      for (const [route, ready] of views) {
        await page.goto(`${base}/#/${route}`);
        await ready();
        await page.waitForTimeout(300);
        const name = route.includes('kind=') ? `jobs-${route.split('kind=')[1]}` : route.split('?')[0];
        await page.screenshot({ path: `${artifacts}/layout-${name}-${tag}.png`, fullPage: true }).catch(() => {});
        const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, inner: window.innerWidth }));
        if (w.scroll > w.inner) problems.push(`${route}: page ${w.scroll} px wide in a ${w.inner} px window`);
        const overlaps = await overlappingLabels(page);
        // A menu whose chosen entry is wider than the menu shows it cut off.
        const cut = await page.evaluate(() => {
          const ctx = document.createElement('canvas').getContext('2d');
          return [...document.querySelectorAll('main select')]
            .filter((s) => s.getClientRects().length && s.selectedIndex >= 0)
            .filter((s) => {
              ctx.font = getComputedStyle(s).font;
              return ctx.measureText(s.options[s.selectedIndex].text).width > s.clientWidth - 24;
            })
            .map((s) => `${s.id}: "${s.options[s.selectedIndex].text}"`);
        });
        if (cut.length) problems.push(`${route}: menus cut off: ${cut.join('; ')}`);
        const small = await smallText(page);
        if (small.length) problems.push(`${route}: ${small.length} plot labels under 11 px, e.g. ${small.slice(0, 4).join('; ')}`);
        if (overlaps.length) problems.push(`${route}: ${overlaps.length} overlapping plot labels, e.g. ${overlaps.slice(0, 4).join('; ')}`);
      }
      assert(!problems.length, problems.join('\n'));
    });

    await step(`${tag}: a CSV export of the P(16,16,4)-sized pattern keeps the page in the window`, async () => {
      await page.goto(`${base}/#/jobs?job=${id}`);
      await page.waitForSelector('#jd-pattern g.dot-primary');
      await page.waitForTimeout(500); // the detail's refresh settles, so it does not redraw mid-export
      for (const format of ['csv', 'json', 'xyw']) {
        const ext = format;
        await page.evaluate(() => (document.getElementById('jd-export-text').textContent = ''));
        await page.click(`#jd-export button[data-format="${format}"]`);
        await page.waitForFunction((e) => document.getElementById("jd-export-text").textContent.length > 1000 && document.getElementById("jd-download").download.includes(`.${e}`), ext, { timeout: 8000 }).catch(async () => {
          throw new Error(`${format} export not shown: ${JSON.stringify(await page.evaluate(() => [document.getElementById("jd-export-text").textContent.slice(0, 200), document.getElementById("jd-download").download]))}`);
        });
        await checkWidth(page, `after the ${format} export`);
        const open = await page.$eval('#jd-open', (b) => {
          const r = b.getBoundingClientRect();
          return r.right <= window.innerWidth && r.width > 0;
        });
        assert(open, `"Open in Evaluate" cut off after the ${format} export`);
      }
    });
  }
}
