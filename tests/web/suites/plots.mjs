// Plots of paper quality (issue 34, What to build 2): every plot has zoom (drag a rectangle) and
// reset, and downloads as PNG and SVG and of its data as CSV; the job trace's as well; Families
// draws the published bests as reference marks; several jobs' traces overlay in one plot.

import fs from 'node:fs';
import { assert, eventually } from '../lib/check.mjs';

async function download(page, selector) {
  const [dl] = await Promise.all([page.waitForEvent('download', { timeout: 10000 }), page.click(selector)]);
  const file = await dl.path();
  return { name: dl.suggestedFilename(), bytes: fs.readFileSync(file) };
}

/* RFC 4180 records (quoted fields may hold commas and quotes). */
function csvRows(text) {
  assert(text.endsWith('\r\n'), 'CSV records end in CRLF');
  const rows = [];
  for (const line of text.slice(0, -2).split('\r\n')) {
    const cells = [];
    let i = 0;
    while (i <= line.length) {
      if (line[i] === '"') {
        let v = '';
        i++;
        while (i < line.length && !(line[i] === '"' && line[i + 1] !== '"')) {
          v += line[i] === '"' ? '"' : line[i];
          i += line[i] === '"' ? 2 : 1;
        }
        cells.push(v);
        i += 2;
      } else {
        const j = line.indexOf(',', i);
        cells.push(line.slice(i, j < 0 ? line.length : j));
        i = j < 0 ? line.length + 1 : j + 1;
      }
    }
    rows.push(cells);
  }
  return rows;
}

async function drag(page, selector, from, to) {
  const r = await page.$eval(selector, (e) => {
    const b = e.getBoundingClientRect();
    return { x: b.left, y: b.top, w: b.width, h: b.height };
  });
  await page.mouse.move(r.x + r.w * from[0], r.y + r.h * from[1]);
  await page.mouse.down();
  await page.mouse.move(r.x + r.w * ((from[0] + to[0]) / 2), r.y + r.h * ((from[1] + to[1]) / 2), { steps: 4 });
  await page.mouse.move(r.x + r.w * to[0], r.y + r.h * to[1], { steps: 4 });
  await page.mouse.up();
}

export default async function plotsSuite({ page, base, api, step, shot }) {
  await step('Families: zoom by dragging, reset, and PNG, SVG and CSV downloads', async () => {
    await page.setViewportSize({ width: 1400, height: 1000 });
    await page.goto(`${base}/#/families`);
    await page.waitForFunction(() => /\d+ points/.test(document.getElementById('fam-status').textContent), null, { timeout: 30000 });
    const svgSel = '#fam-plot svg.scatter-svg';
    // The E2 axis: labelled at four values at least, and says whether it is log or linear.
    const yTicks = await page.$$eval(`${svgSel} text.tick[text-anchor="end"]`, (t) => t.map((x) => x.textContent));
    assert(yTicks.length >= 4, `E2 axis ticks ${JSON.stringify(yTicks)}`);
    assert(/E2 \((linear|log scale)\)/.test(await page.$eval(svgSel, (s) => s.textContent)), 'the E2 axis does not say log or linear');
    const vb0 = await page.getAttribute(svgSel, 'viewBox');
    await drag(page, svgSel, [0.3, 0.3], [0.6, 0.7]);
    const vb1 = await page.getAttribute(svgSel, 'viewBox');
    assert(vb1 !== vb0 && (await page.getAttribute(svgSel, 'data-zoomed')) === 'true', `no zoom: viewBox ${vb0} -> ${vb1}`);
    const w1 = Number(vb1.split(' ')[2]);
    assert(w1 < 0.5 * Number(vb0.split(' ')[2]), `zoomed viewBox ${vb1} of ${vb0}`);
    await page.click('#fam-plot .plot-tools button[data-action="reset"]');
    assert((await page.getAttribute(svgSel, 'viewBox')) === vb0, 'reset does not restore the view');
    const svg = await download(page, '#fam-plot .plot-tools button[data-action="svg"]');
    const text = svg.bytes.toString('utf8');
    assert(svg.name.endsWith('.svg') && text.startsWith('<?xml') && text.includes('<svg') && text.includes('samples per pixel'), `SVG download ${svg.name}: ${text.slice(0, 200)}`);
    assert(/font-size:\s*\d/.test(text), 'the SVG has no inlined styles');
    const png = await download(page, '#fam-plot .plot-tools button[data-action="png"]');
    assert(png.bytes.subarray(0, 8).toString('hex') === '89504e470d0a1a0a' && png.bytes.length > 2000, `PNG download ${png.name}, ${png.bytes.length} bytes`);
    const csv = await download(page, '#fam-plot .plot-tools button[data-action="csv"]');
    const rows = csvRows(csv.bytes.toString('utf8'));
    assert(rows[0].join(',') === 'series,samples_per_pixel,e2,title', `CSV header ${rows[0]}`);
    const points = await page.$$eval('#fam-plot .point-marker, #fam-plot g.ref-mark', (m) => m.length);
    assert(rows.length - 1 === points, `${rows.length - 1} CSV rows, ${points} points and marks drawn`);
    assert(rows.some((r) => r[0] === 'published best'), 'the reference marks are not in the CSV');
  });

  await step('Families: the published bests are reference marks, each with its source', async () => {
    const marks = await page.$$eval('#fam-plot g.ref-mark title', (t) => t.map((x) => x.textContent));
    const rows = await page.$$eval('#fam-published tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
    assert(marks.length === rows.length && rows.length >= 5, `${marks.length} marks, ${rows.length} table rows`);
    for (const r of rows) {
      assert((/Laine & Aila 2006/.test(r[3]) && /Table [23]/.test(r[3])) || /laines9\/patterns/.test(r[3]), `source "${r[3]}"`);
      assert(marks.some((m) => m.includes(`of ${r[0]}: E2 ${Number(r[2])}`)), `no mark for ${r[0]} ${r[2]}`);
    }
    // Table 2's Flipquad row and Table 3's Poisson-disk Opt W+P are there as printed.
    assert(rows.some((r) => r[0] === 'P(4,1+,2)' && r[2] === '0.359') && rows.some((r) => r[0] === 'P(16,16,4)' && r[2] === '0.161'), JSON.stringify(rows));
    // The Aalto pattern page's tables (issue 34): P(1,4,6) 0.168, as the page prints it.
    assert(rows.some((r) => r[0] === 'P(1,4,6)' && Number(r[2]) === 0.168 && /laines9/.test(r[3])), JSON.stringify(rows));
  });

  await step('Evaluate: the polar plots download as PNG and their data as CSV', async () => {
    await page.goto(`${base}/#/evaluate?preset=flipquad`);
    await page.waitForFunction(() => document.querySelectorAll('#ev-polar-e1 path.polar-curve').length === 4);
    const csv = await download(page, '#ev-polar-e1 .plot-tools button[data-action="csv"]');
    const rows = csvRows(csv.bytes.toString('utf8'));
    assert(rows[0].join(',') === 'kernel,angle_deg,value' && rows.length - 1 === 4 * 36, `polar CSV: ${rows[0]}, ${rows.length - 1} rows`);
    const png = await download(page, '#ev-polar-weighted .plot-tools button[data-action="png"]');
    assert(png.bytes.subarray(0, 8).toString('hex') === '89504e470d0a1a0a', 'polar PNG');
  });

  await step("Tiles: the penalised histogram downloads as PNG and its 256 counts as CSV", async () => {
    await page.goto(`${base}/#/tiles`);
    await page.click('#tile-render');
    await page.waitForSelector('#tile-hist canvas', { timeout: 20000 });
    await page.waitForSelector('#tile-hist .plot-tools button[data-action="csv"]');
    const csv = await download(page, '#tile-hist .plot-tools button[data-action="csv"]');
    const rows = csvRows(csv.bytes.toString('utf8'));
    assert(rows[0].join(',') === 'abs_error,penalised_count' && rows.length - 1 === 256, `histogram CSV ${rows[0]}, ${rows.length - 1} rows`);
    const png = await download(page, '#tile-hist .plot-tools button[data-action="png"]');
    assert(png.bytes.subarray(0, 8).toString('hex') === '89504e470d0a1a0a', 'histogram PNG');
    await page.click('#tile-hist .plot-tools button[data-action="reset"]');
  });

  let id;
  await step("a job's trace: zoom by dragging and reset; CSV, SVG and PNG downloads", async () => {
    id = String((await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 0.6, pattern: { preset: 'rgss' } })).id);
    const j = await eventually(async () => {
      const x = await api('GET', `/v1/jobs/${id}`);
      return x.state === 'done' && x;
    }, { timeout: 20000, message: 'the sleep job' });
    await page.goto(`${base}/#/jobs?job=${id}`);
    await page.waitForSelector('#jd-trace canvas');
    await page.waitForTimeout(300);
    await drag(page, '#jd-trace .u-over', [0.2, 0.2], [0.7, 0.8]);
    await page.waitForFunction(() => document.getElementById('jd-trace').dataset.zoomed === 'true');
    assert(!(await page.$eval('#jd-trace-tools [data-action="reset"]', (b) => b.disabled)), 'Reset zoom stays disabled after a zoom');
    await page.click('#jd-trace-tools [data-action="reset"]');
    await page.waitForFunction(() => document.getElementById('jd-trace').dataset.zoomed === '');
    const csv = await download(page, '#jd-trace-tools [data-action="csv"]');
    const rows = csvRows(csv.bytes.toString('utf8'));
    assert(rows[0].join(',') === 'seconds,iterations,evaluations,best_e2' && rows.length - 1 === j.trace.length, `trace CSV ${rows[0]}, ${rows.length - 1} rows for ${j.trace.length} points`);
    const svg = await download(page, '#jd-trace-tools [data-action="svg"]');
    assert(svg.bytes.toString('utf8').includes('best E2'), 'trace SVG without its axis label');
    const png = await download(page, '#jd-trace-tools [data-action="png"]');
    assert(png.bytes.subarray(0, 8).toString('hex') === '89504e470d0a1a0a', 'trace PNG');
  });

  await step('the traces of jobs ticked in the list overlay in one plot, with their data as CSV', async () => {
    const other = String((await api('POST', '/v1/jobs', { kind: 'sleep', seconds: 0.4, pattern: { preset: 'quincunx' } })).id);
    const jobs = {};
    for (const x of [id, other])
      jobs[x] = await eventually(async () => {
        const j = await api('GET', `/v1/jobs/${x}`);
        return j.state === 'done' && j;
      }, { timeout: 20000, message: `job ${x}` });
    await page.goto(`${base}/#/jobs`);
    assert(await page.$eval('#jobs-overlay-figure', (f) => f.hidden), 'an overlay shown with no job ticked');
    for (const x of [id, other]) await page.check(`#jobs-table tr[data-job-id="${x}"] input.overlay-pick`);
    await page.waitForFunction(() => document.querySelectorAll('#jobs-overlay path.series-line').length === 2);
    const legend = await page.$$eval('#jobs-overlay-legend .legend-item', (l) => l.map((x) => x.textContent.trim()));
    assert(legend.length === 2 && legend[0].startsWith(`#${id} sleep`) && legend[1].startsWith(`#${other} sleep`), `legend ${JSON.stringify(legend)}`);
    const csv = await download(page, '#jobs-overlay .plot-tools button[data-action="csv"]');
    const rows = csvRows(csv.bytes.toString('utf8'));
    for (const x of [id, other]) {
      const n = rows.filter((r) => r[0].startsWith(`#${x} `)).length;
      assert(n >= jobs[x].trace.filter((p) => p.seconds > 0).length, `job ${x}: ${n} CSV rows, ${jobs[x].trace.length} trace points`);
    }
    // No two labels of the overlay plot overprint (its x axis spans 1e-7 .. 1 s).
    const clash = await page.evaluate(() => {
      const b = [...document.querySelectorAll('#jobs-overlay svg text')].map((t) => ({ t: t.textContent, r: t.getBoundingClientRect() }));
      const out = [];
      for (let i = 0; i < b.length; i++)
        for (let j = i + 1; j < b.length; j++) {
          const ox = Math.min(b[i].r.right, b[j].r.right) - Math.max(b[i].r.left, b[j].r.left);
          const oy = Math.min(b[i].r.bottom, b[j].r.bottom) - Math.max(b[i].r.top, b[j].r.top);
          if (ox > 1 && oy > 1) out.push(`${b[i].t} / ${b[j].t}`);
        }
      return out;
    });
    assert(!clash.length, `overlay labels overprint: ${clash.slice(0, 5).join('; ')}`);
    await shot('jobs-overlay');
    // The choice survives the list's refresh; unticking one leaves one line.
    await page.waitForTimeout(4500);
    await page.uncheck(`#jobs-table tr[data-job-id="${other}"] input.overlay-pick`);
    await page.waitForFunction(() => document.querySelectorAll('#jobs-overlay path.series-line').length === 1);
    for (const size of [{ width: 1400, height: 1000 }, { width: 1000, height: 800 }]) {
      await page.setViewportSize(size);
      await page.waitForTimeout(150);
      const w = await page.evaluate(() => document.documentElement.scrollWidth);
      assert(w <= size.width, `${size.width}: page ${w} px wide with the overlay`);
    }
  });

  await step('while a job runs, the header and the trace legend show the same best E2', async () => {
    const run = String((await api('POST', '/v1/jobs', { kind: 'optimize', family: 'P(4,4,2)', seeds: 4, max_seconds: 2.5, rng_seed: 5 })).id);
    await page.goto(`${base}/#/jobs?job=${run}`);
    await page.waitForSelector('#jd-trace canvas', { timeout: 20000 });
    let compared = 0;
    for (let i = 0; i < 40; i++) {
      const s = await page.evaluate(() => ({
        state: document.getElementById('jd-state').dataset.state,
        header: document.getElementById('jd-e2').textContent,
        legend: [...document.querySelectorAll('#jd-trace .u-legend .u-value')].map((v) => v.textContent),
      }));
      if (s.state !== 'running') break;
      if (s.legend.length === 2 && s.legend[1] !== '--') {
        assert(s.header === s.legend[1], `running: header ${s.header}, legend ${s.legend[1]}`);
        compared++;
      }
      await page.waitForTimeout(120);
    }
    assert(compared >= 3, `compared header and legend ${compared} times while the job ran`);
    await eventually(async () => (await api('GET', `/v1/jobs/${run}`)).state === 'done', { timeout: 20000, message: 'the optimize job' });
  });
}
