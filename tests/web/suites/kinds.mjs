// Jobs view, one detail view per job kind (small budgets): family-sweep's ranked table whose
// rows open in Evaluate, random-stats' Table 3 row, table3's table with ± columns, compare's error against samples per pixel,
// animation's frames, reference-convergence's levels, temporal-optimize's seeds and sequence
// (opened in Temporal), temporal-render's phases against the edge model; the trace's axes and legend; and showing
// another job leaves nothing of the previous one on screen.

import { assert, eventually } from '../lib/check.mjs';

const SPECS = {
  optimize: { kind: 'optimize', family: 'P(4,1+,2)', seeds: 3, max_iterations: 20, rng_seed: 3 },
  'family-sweep': { kind: 'family-sweep', cost: 1.25, seeds_per_config: 1, max_seconds: 1, rng_seed: 3 },
  'random-stats': { kind: 'random-stats', family: 'P(1,4,2)', count: 20, max_seconds: 1, rng_seed: 3, metrics: ['mixture', 'star_linf'] },
  table3: { kind: 'table3', family: 'P(4,4,2)', seeds: 2, count: 10, max_iterations: 30, rng_seed: 3, metrics: ['centered'] },
  compare: { kind: 'compare', scene: { name: 'siemens-star', width: 32, height: 32 }, reference: { spp: 64 }, patterns: [{ preset: 'centroid' }, { preset: 'quincunx' }, { preset: 'rgss' }] },
  animation: { kind: 'animation', scene: { name: 'rotating-triangle', frames: 3, width: 32, height: 32 }, reference: { spp: 64 }, pattern: { preset: 'rgss' } },
  'reference-convergence': { kind: 'reference-convergence', scene: { name: 'siemens-star', width: 32, height: 32 }, levels: [16, 64], baseline_spp: 256 },
  'temporal-optimize': { kind: 'temporal-optimize', family: 'T(4)', seeds: 1, max_iterations: 3 },
  'temporal-render': { kind: 'temporal-render', scene: { name: 'siemens-star', width: 32, height: 32 }, pattern: { temporal: { preset: 'halton23-8' } }, reference: { spp: 16 } },
};

async function cells(page, selector) {
  return page.$$eval(`${selector} tbody tr`, (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent.trim())));
}

export default async function kindsSuite({ page, base, api, step, shot }) {
  const ids = {};
  const jobs = {};
  const open = async (kind) => {
    await page.goto(`${base}/#/jobs?job=${ids[kind]}`);
    await page.waitForFunction((id) => document.getElementById('job-detail-body').dataset.job === id && document.getElementById('jd-state').dataset.state === 'done', String(ids[kind]), { timeout: 20000 });
  };

  await step('a small job of every kind runs to done', async () => {
    for (const [kind, spec] of Object.entries(SPECS)) ids[kind] = (await api('POST', '/v1/jobs', spec)).id;
    for (const [kind, id] of Object.entries(ids)) {
      jobs[kind] = await eventually(async () => {
        const j = await api('GET', `/v1/jobs/${id}`);
        return !['queued', 'running'].includes(j.state) && j;
      }, { timeout: 60000, interval: 250, message: `${kind} job ${id} to finish` });
      assert(jobs[kind].state === 'done', `${kind} job ${id} ended ${jobs[kind].state}: ${JSON.stringify(jobs[kind].error)}`);
    }
  });

  await step("the job list shows each summary's best E2", async () => {
    const list = await api('GET', '/v1/jobs');
    await page.goto(`${base}/#/jobs`);
    for (const s of list.jobs) {
      const row = await page.waitForSelector(`#jobs-table tr[data-job-id="${s.id}"][data-state="${s.state}"]`, { timeout: 10000 });
      const e2 = await row.$eval('td.best-e2', (td) => td.textContent);
      assert(e2 === (typeof s.best_e2 === 'number' ? s.best_e2.toFixed(4) : '—'), `job ${s.id}: best E2 shown ${e2}, summary ${s.best_e2}`);
      // An animation's pattern E2 is its best: the list says what the detail says (issue 34).
      if (s.kind === 'animation') assert(e2 === jobs.animation.result.e2.toFixed(4), `animation ${s.id}: list shows ${e2}, its result E2 ${jobs.animation.result.e2}`);
    }
  });

  await step('the job list fits its panel at 1400x1000 and 1000x800, Cancel buttons included', async () => {
    for (const size of [{ width: 1400, height: 1000 }, { width: 1000, height: 800 }]) {
      await page.setViewportSize(size);
      await page.waitForTimeout(150);
      const out = await page.evaluate(() => {
        // The panel's content edge: inside its border and padding.
        const p = document.getElementById('jobs-table').closest('.panel');
        const cs = getComputedStyle(p);
        const edge = p.getBoundingClientRect().right - parseFloat(cs.borderRightWidth) - parseFloat(cs.paddingRight);
        const right = Math.max(...[...document.querySelectorAll('#jobs-table button, #jobs-table')].map((b) => b.getBoundingClientRect().right));
        return { right, panel: edge + 0.5 };
      });
      assert(out.right <= out.panel, `${size.width}x${size.height}: the jobs table reaches ${out.right} px, its panel ends at ${out.panel}`);
    }
    await page.setViewportSize({ width: 1366, height: 900 });
  });

  await step("every kind's detail shows its submitted settings, its timings and its executor", async () => {
    for (const kind of Object.keys(SPECS)) {
      const j = jobs[kind];
      await open(kind);
      const d = await page.evaluate(() => ({
        settings: [...document.querySelectorAll('#jd-settings .setting')].map((x) => x.textContent),
        timings: document.getElementById('jd-timings').textContent,
        executor: document.getElementById('jd-executor').textContent,
      }));
      const keys = Object.keys(SPECS[kind]).filter((k) => k !== 'kind');
      assert(JSON.stringify(d.settings.map((x) => x.split(' ')[0])) === JSON.stringify(keys), `${kind}: settings ${JSON.stringify(d.settings)}, spec keys ${keys}`);
      for (const k of keys) {
        const v = SPECS[kind][k];
        if (typeof v === 'number' || typeof v === 'string') assert(d.settings.includes(`${k} ${v}`), `${kind}: ${k} ${v} not in ${JSON.stringify(d.settings)}`);
      }
      const ran = (j.finished - j.started).toFixed(j.finished - j.started < 10 ? 2 : 1);
      const queued = (j.started - j.created).toFixed(j.started - j.created < 10 ? 2 : 1);
      assert(d.timings.includes(`ran ${ran} s`) && d.timings.includes(`queued ${queued} s`), `${kind}: timings "${d.timings}", API queued ${queued} ran ${ran}`);
      assert(/^(local|slurm)/.test(d.executor), `${kind}: executor "${d.executor}"`);
    }
  });

  await step('optimize: a row per seed, initial and final E2 as the API, the best seed marked', async () => {
    const r = jobs.optimize.result;
    await open('optimize');
    const rows = await cells(page, '#jd-seeds-table');
    assert(rows.length === r.per_seed.length && rows.length === 3, `${rows.length} rows, ${r.per_seed.length} seeds`);
    r.per_seed.forEach((x, i) => assert(rows[i][0].startsWith(String(x.seed)) && rows[i][2] === x.initial_e2.toFixed(6) && rows[i][3] === x.e2.toFixed(6), `seed ${x.seed}: ${JSON.stringify(rows[i])}`));
    const best = rows.filter((x) => x[0].includes('(best)'));
    const lowest = Math.min(...r.per_seed.map((x) => x.e2));
    assert(best.length === 1 && best[0][3] === lowest.toFixed(6), `best seed row ${JSON.stringify(best)}, lowest seed E2 ${lowest}`);
    const hint = await page.$eval('#jd-kind', (k) => k.textContent);
    assert(hint.includes(r.e2.toFixed(6)), `the job's final E2 ${r.e2} is not said beside the seeds`);
    await shot('jobs-optimize');
  });

  await step('family-sweep: ranked table; a row opens its configuration in Evaluate', async () => {
    const r = jobs['family-sweep'].result;
    await open('family-sweep');
    const rows = await cells(page, '#jd-sweep-table');
    assert(rows.length === r.ranked.length, `${rows.length} rows shown, ${r.ranked.length} configurations`);
    r.ranked.forEach((x, i) => {
      assert(rows[i][0] === String(x.rank), `row ${i}: rank ${rows[i][0]}`);
      assert(rows[i][3] === x.e2.toFixed(6), `rank ${x.rank}: E2 shown ${rows[i][3]}, API ${x.e2}`);
      assert(rows[i][1].includes(`corners ${x.config.corners.join('')}`) && rows[i][1].includes(`interior ${x.config.interior}`), `rank ${x.rank}: configuration "${rows[i][1]}"`);
    });
    await shot('jobs-family-sweep');
    const pick = r.ranked[Math.min(2, r.ranked.length - 1)];
    await page.click(`#jd-sweep-table tr[data-rank="${pick.rank}"] a`);
    await page.waitForFunction((e2) => location.hash.startsWith('#/evaluate') && Math.abs(Number(document.getElementById('ev-e2').dataset.e2) - e2) < 1e-9, pick.e2, { timeout: 10000 });
    const dots = await page.$$eval('#ev-pattern g.dot-primary', (g) => g.length);
    assert(dots === pick.best.mirrored.length, `Evaluate draws ${dots} samples, configuration ${pick.rank} has ${pick.best.mirrored.length}`);
  });

  await step('trace: log/linear axes, several ticks, legend with values, curve to the job end', async () => {
    const j = jobs['family-sweep'];
    await open('family-sweep');
    await page.waitForSelector('#jd-trace canvas');
    const end = Number(await page.getAttribute('#jd-trace', 'data-end'));
    assert(Math.abs(end - (j.finished - j.started)) < 1e-9, `curve ends at ${end} s, the job ran ${j.finished - j.started} s`);
    assert(end >= j.trace[j.trace.length - 1].seconds, 'curve ends before the last trace point');
    const legend = await page.$$eval('#jd-trace .u-legend .u-value', (v) => v.map((x) => x.textContent));
    assert(legend.includes(j.result.e2.toFixed(6)), `legend values ${JSON.stringify(legend)} lack the best E2 ${j.result.e2.toFixed(6)}`);
    for (const mode of ['linear', 'log']) {
      await page.selectOption('#jd-axes', mode);
      await page.waitForFunction((m) => document.getElementById('jd-trace').getAttribute('aria-label').includes(m), mode);
      const ticks = Number(await page.getAttribute('#jd-trace', 'data-y-ticks'));
      assert(ticks >= 3, `${mode}: ${ticks} E2 ticks`);
      assert(await page.$('#jd-trace canvas'), `${mode}: no chart`);
    }
  });

  await step('random-stats: Min, Avg, Max, Opt W, Opt W+P (Laine & Aila Table 3)', async () => {
    const r = jobs['random-stats'].result;
    await open('random-stats');
    const head = await page.$$eval('#jd-stats-table thead th', (th) => th.map((x) => x.textContent));
    assert(JSON.stringify(head.slice(2)) === JSON.stringify(['Min', 'Avg', 'Max', 'Opt W', 'Opt W+P']), `columns ${JSON.stringify(head)}`);
    const [row] = await cells(page, '#jd-stats-table');
    const want = [r.family, r.distribution, ...[r.random.min, r.random.avg, r.random.max, r.opt_w.e2, r.opt_wp.e2].map((v) => v.toFixed(4))];
    assert(JSON.stringify(row) === JSON.stringify(want), `row ${JSON.stringify(row)}, API ${JSON.stringify(want)}`);
    // issue 31: the spec's metrics, Spearman's rho of each figure with E2 as the API
    const rho = await cells(page, '#jd-point-metrics');
    const wantRho = r.point_metrics.spearman.map((e) => [e.metric, e.rho.toFixed(3), String(e.n)]);
    assert(JSON.stringify(rho.map((x) => x.slice(0, 3))) === JSON.stringify(wantRho), `rho ${JSON.stringify(rho)}, API ${JSON.stringify(wantRho)}`);
    await shot('jobs-random-stats');
  });

  await step('table3: the paper\'s table with a ± column, mean and sd as the API', async () => {
    const r = jobs.table3.result;
    await open('table3');
    const head = await page.$$eval('#jd-table3 thead th', (th) => th.map((x) => x.textContent));
    assert(JSON.stringify(head) === JSON.stringify(['Distribution', 'Min', '±', 'Avg', '±', 'Max', '±', 'Opt W', '±', 'Opt W+P', '±']), `columns ${JSON.stringify(head)}`);
    const rows = await cells(page, '#jd-table3');
    assert(rows.length === r.rows.length, `${rows.length} rows, API ${r.rows.length} (P(4,4,2): no paper rows)`);
    for (const [i, row] of r.rows.entries()) {
      const want = [row.distribution, ...['min', 'avg', 'max', 'opt_w', 'opt_wp'].flatMap((k) => [row.columns[k].mean.toFixed(4), row.columns[k].sd.toFixed(4)])];
      assert(JSON.stringify(rows[i]) === JSON.stringify(want), `row ${JSON.stringify(rows[i])}, API ${JSON.stringify(want)}`);
    }
    const hint = await page.$eval('#job-detail-body', (n) => n.textContent);
    assert(hint.includes('dart-throwing-torus') && hint.includes('naiman v2'), 'generator and acuity shown');
    // issue 31: rho of the spec's figure with E2 per distribution, over both seeds' patterns
    const rho = await cells(page, '#jd-point-metrics');
    const wantRho = r.rows.map((row) => [row.distribution, 'centered', row.point_metrics.spearman[0].rho.toFixed(3), '20']);
    assert(JSON.stringify(rho.map((x) => x.slice(0, 4))) === JSON.stringify(wantRho), `rho ${JSON.stringify(rho)}, API ${JSON.stringify(wantRho)}`);
    // Its trace is Opt W+P work: drawn to its last point, not to the job's wall time (issue 34).
    const trace = jobs.table3.trace;
    const tr = await page.$eval('#jd-trace', (h) => ({ end: h.dataset.end, label: h.dataset.xLabel, points: h.dataset.points }));
    assert(tr.end === '' && /Opt W\+P seconds/.test(tr.label) && Number(tr.points) === trace.length, `table3 trace ${JSON.stringify(tr)}, ${trace.length} points`);
    // The table fits the panel at both sizes: nothing scrolls or is cut off (issue 34).
    for (const size of [{ width: 1400, height: 1000 }, { width: 1000, height: 800 }]) {
      await page.setViewportSize(size);
      await page.waitForTimeout(150);
      const fit = await page.evaluate(() => {
        const t = document.getElementById('jd-table3').getBoundingClientRect();
        const p = document.getElementById('job-detail');
        const cs = getComputedStyle(p);
        const edge = p.getBoundingClientRect().right - parseFloat(cs.borderRightWidth) - parseFloat(cs.paddingRight);
        const k = document.getElementById('jd-kind');
        return { table: t.right, panel: edge + 0.5, scroll: k.scrollWidth, client: k.clientWidth };
      });
      assert(fit.table <= fit.panel && fit.scroll <= fit.client, `${size.width}x${size.height}: table3 ${JSON.stringify(fit)}`);
    }
    await shot('jobs-table3');
  });

  await step('compare: RMSE and E2 against samples per pixel, one row per pattern', async () => {
    const r = jobs.compare.result;
    await open('compare');
    const rows = await cells(page, '#jd-cmp-table');
    assert(rows.length === r.rows.length, `${rows.length} rows, API ${r.rows.length}`);
    r.rows.forEach((x, i) => {
      assert(rows[i][0] === x.name && rows[i][1] === String(x.samples_per_pixel) && rows[i][2] === x.e2.toFixed(4) && rows[i][3] === x.rmse.toFixed(3), `row ${JSON.stringify(rows[i])} vs API ${x.name} ${x.samples_per_pixel} ${x.e2} ${x.rmse}`);
      // The edge model's prediction beside the measured RMSE.
      assert(rows[i][6] === x.predicted_rmse.toFixed(3) && rows[i][7] === (x.rmse / x.predicted_rmse).toFixed(3), `row ${JSON.stringify(rows[i])}: predicted ${x.predicted_rmse}`);
    });
    for (const size of [{ width: 1400, height: 1000 }, { width: 1000, height: 800 }]) {
      await page.setViewportSize(size);
      await page.waitForTimeout(150);
      const k = await page.$eval('#jd-kind', (x) => ({ scroll: x.scrollWidth, client: x.clientWidth }));
      assert(k.scroll <= k.client, `${size.width}x${size.height}: the comparison's table is wider than the panel ${JSON.stringify(k)}`);
    }
    await page.setViewportSize({ width: 1366, height: 900 });
    for (const plot of ['#jd-cmp-plot', '#jd-cmp-plot-e2']) {
      const n = await page.$$eval(`${plot} .point-marker`, (m) => m.length);
      assert(n === r.rows.length, `${plot}: ${n} points`);
      const svgText = await page.$eval(plot, (p) => p.textContent);
      assert(svgText.includes('samples per pixel') && !/render time/.test(svgText), `${plot}: x axis is not samples per pixel`);
    }
    assert(await page.$eval('#jd-best', (e) => e.hidden), 'a comparison has no best pattern to show');
    // Its images: the reference, then each pattern's render and difference, all loaded.
    await page.waitForFunction((n) => [...document.querySelectorAll('#jd-cmp-images img')].filter((i) => i.complete && i.naturalWidth > 0).length === n, 1 + 2 * r.rows.length, { timeout: 10000 });
    const tiles = await page.$$eval('#jd-cmp-images img', (i) => i.map((x) => x.dataset.tile));
    assert(tiles[0] === r.reference.renders[0].tile.url && tiles[1] === r.rows[0].tiles.pattern.url && tiles[2] === r.rows[0].tiles.difference.url, `images ${JSON.stringify(tiles)}`);
    await shot('jobs-compare');
  });

  await step('animation: a row per frame and the whole animation', async () => {
    const r = jobs.animation.result;
    await open('animation');
    const rows = await cells(page, '#jd-anim-table');
    assert(rows.length === r.frames.length + 1, `${rows.length} rows for ${r.frames.length} frames`);
    r.frames.forEach((f, i) => assert(rows[i][0] === String(f.frame) && rows[i][1] === f.rmse.toFixed(3) && rows[i][3] === String(f.pixels_recomputed), `frame ${f.frame}: ${JSON.stringify(rows[i])}`));
    assert(rows[r.frames.length][1] === r.total.rmse.toFixed(3), `total RMSE ${rows[r.frames.length][1]}, API ${r.total.rmse}`);
    await page.waitForFunction((n) => [...document.querySelectorAll('#jd-anim-images img')].filter((i) => i.complete && i.naturalWidth > 0).length === n, 3 * r.frames.length, { timeout: 10000 });
    await shot('jobs-animation');
  });

  await step('reference-convergence: RMSE per reference level', async () => {
    const r = jobs['reference-convergence'].result;
    await open('reference-convergence');
    const rows = await cells(page, '#jd-conv-table');
    assert(JSON.stringify(rows.map((x) => x[0])) === JSON.stringify(r.rows.map((x) => String(x.spp))), `levels ${JSON.stringify(rows.map((x) => x[0]))}`);
    r.rows.forEach((x, i) => assert(rows[i][1] === x.rmse.toFixed(3), `${x.spp} spp: RMSE ${rows[i][1]}, API ${x.rmse}`));
    // RMSE against spp as a plot: one point per level, log axes.
    const titles = await page.$$eval('#jd-conv-plot title', (t) => t.map((x) => x.textContent));
    r.rows.forEach((x) => assert(titles.includes(`${x.spp} spp: RMSE ${x.rmse.toFixed(3)}`), `no point for ${x.spp} spp in ${JSON.stringify(titles)}`));
    const text = await page.$eval('#jd-conv-plot', (p) => p.textContent);
    assert(text.includes('(log scale)'), 'the convergence plot does not say its axes are logarithmic');
    await shot('jobs-reference-convergence');
  });

  // The kind's detail fits the panel at both layouts (issue 34, as web_layout checks).
  const fits = async (what) => {
    for (const size of [{ width: 1400, height: 1000 }, { width: 1000, height: 800 }]) {
      await page.setViewportSize(size);
      await page.waitForTimeout(150);
      const k = await page.$eval('#jd-kind', (x) => ({ scroll: x.scrollWidth, client: x.clientWidth }));
      assert(k.scroll <= k.client, `${size.width}x${size.height}: ${what} is wider than the panel ${JSON.stringify(k)}`);
    }
    await page.setViewportSize({ width: 1366, height: 900 });
  };

  await step('temporal-optimize: figures, E2 per phase and seeds as the API, the sequence drawn, Open in Temporal', async () => {
    const r = jobs['temporal-optimize'].result;
    await open('temporal-optimize');
    const fig = await cells(page, '#jd-topt-figures');
    const value = (name) => (fig.find((x) => x[0] === name) || [])[1];
    assert(value('E2, worst phase') === r.e2.toFixed(6) && value('E2, mean over phases') === r.mean_phase_e2.toFixed(6) && value('Flicker F2') === r.f2.toFixed(6), `figures ${JSON.stringify(fig)}, API ${r.e2} ${r.mean_phase_e2} ${r.f2}`);
    assert(value('Seeds run') === String(r.seeds_run), `seeds run ${value('Seeds run')}`);
    const phases = await cells(page, '#jd-topt-phases');
    assert(phases.length === r.phase_e2.length, `${phases.length} phase rows, API ${r.phase_e2.length}`);
    r.phase_e2.forEach((v, i) => assert(phases[i][1] === v.toFixed(6), `phase ${i}: ${phases[i][1]}, API ${v}`));
    assert(phases.filter((x) => x[0].includes('(worst)')).length === 1, 'one phase marked worst');
    const seeds = await cells(page, '#jd-topt-seeds');
    assert(seeds.length === r.per_seed.length, `${seeds.length} seed rows`);
    r.per_seed.forEach((x, i) => assert(seeds[i][1] === x.start && seeds[i][3] === x.score.toFixed(6) && seeds[i][5] === x.f2.toFixed(6), `seed ${i}: ${JSON.stringify(seeds[i])}`));
    // The sequence with a numbered mark per frame at the API's offsets.
    const marks = await page.$$eval('#jd-tseq .tp-frame title', (t) => t.map((x) => x.textContent));
    const jitter = r.best.temporal.jitter;
    assert(marks.length === jitter.length, `${marks.length} frames drawn, ${jitter.length} offsets`);
    jitter.forEach(([x, y], f) => assert(marks[f] === `frame ${f}: (${x.toFixed(4)}, ${y.toFixed(4)})`, `frame ${f}: ${marks[f]}`));
    assert(await page.$eval('#jd-best', (e) => e.hidden), 'a sequence is not shown as a one-kernel-set best pattern');
    await fits('the temporal-optimize detail');
    await shot('jobs-temporal-optimize');
    await page.click('#jd-open-temporal');
    await page.waitForFunction((e2) => {
      const o = document.getElementById('tp-e2');
      return o && !document.getElementById('view-temporal').hidden && Math.abs(Number(o.dataset.e2) - e2) <= 1e-9 * Math.max(1, e2);
    }, r.e2, { timeout: 10000 });
    const src = await page.$eval('#tp-source', (e) => e.textContent);
    assert(src.includes(`job ${ids['temporal-optimize']}`), `Temporal says its sequence is "${src}"`);
  });

  await step('temporal-render: a row per phase with predicted and ratio, after-cut plot, the images', async () => {
    const r = jobs['temporal-render'].result;
    await open('temporal-render');
    const rows = await cells(page, '#jd-trender-phases');
    assert(rows.length === r.phases.length, `${rows.length} rows, API ${r.phases.length} phases`);
    r.phases.forEach((x, i) => assert(rows[i][1] === x.e2.toFixed(4) && rows[i][2] === x.rmse.toFixed(3) && rows[i][4] === x.predicted_rmse.toFixed(3) && rows[i][5] === x.ratio.toFixed(3), `phase ${x.phase}: ${JSON.stringify(rows[i])}`));
    assert(rows[r.steady.worst_phase][0].includes('(worst)'), `worst phase ${r.steady.worst_phase} not marked`);
    const sum = await cells(page, '#jd-trender-summary');
    assert(sum[2][1] === r.flicker.step_rmse.toFixed(3) && sum[2][2] === r.flicker.predicted_step_rmse.toFixed(3) && sum[4][1] === String(r.frames_to_5pct ?? 'none'), `summary ${JSON.stringify(sum)}`);
    const titles = await page.$$eval('#jd-trender-plot title', (t) => t.map((x) => x.textContent));
    r.after_cut.forEach((v, k) => assert(titles.includes(`frame ${k + 1}: RMSE ${v.toFixed(3)}`), `no point for frame ${k + 1} in the after-cut plot`));
    await page.waitForFunction(() => [...document.querySelectorAll('#jd-trender-images img')].filter((i) => i.complete && i.naturalWidth > 0).length === 3, null, { timeout: 10000 });
    const tiles = await page.$$eval('#jd-trender-images img', (i) => i.map((x) => x.dataset.tile));
    assert(JSON.stringify(tiles) === JSON.stringify([r.tiles.pattern.url, r.tiles.reference.url, r.tiles.difference.url]), `images ${JSON.stringify(tiles)}`);
    await fits('the temporal-render detail');
    await shot('jobs-temporal-render');
  });

  await step("showing job B after job A's export leaves nothing of A", async () => {
    const a = ids['family-sweep'];
    await open('family-sweep');
    await page.click('#jd-export button[data-format="json"]');
    await page.waitForFunction(() => !document.getElementById('jd-download').hidden && document.getElementById('jd-export-text').textContent.length > 0);
    const aDots = await page.$$eval('#jd-pattern g.dot-primary', (g) => g.length);
    assert(aDots > 0, 'job A draws no pattern');
    // B without a pattern: the whole best-pattern part goes away with A's export.
    await page.click(`#jobs-table tr[data-job-id="${ids['reference-convergence']}"] button[data-action="show"]`);
    await page.waitForFunction((id) => document.getElementById('job-detail-body').dataset.job === id, String(ids['reference-convergence']));
    const after = await page.evaluate(() => ({
      exportText: document.getElementById('jd-export-text').textContent,
      download: !document.getElementById('jd-download').hidden || document.getElementById('jd-download').hasAttribute('href'),
      dots: document.querySelectorAll('#jd-pattern g.dot-primary').length,
      sweep: !!document.getElementById('jd-sweep-table'),
      trace: document.querySelectorAll('#jd-trace canvas').length,
      title: document.getElementById('job-detail-title').textContent,
    }));
    assert(after.exportText === '' && !after.download && after.dots === 0 && !after.sweep && after.trace === 0, `job ${a} left ${JSON.stringify(after)}`);
    // B with a pattern of its own: B's drawing, no export until asked.
    await open('family-sweep');
    await page.click('#jd-export button[data-format="utk"]');
    await page.waitForFunction(() => !document.getElementById('jd-download').hidden);
    await page.click(`#jobs-table tr[data-job-id="${ids['random-stats']}"] button[data-action="show"]`);
    await page.waitForFunction((id) => document.getElementById('job-detail-body').dataset.job === id, String(ids['random-stats']));
    const b = await page.evaluate(() => ({
      exportText: document.getElementById('jd-export-text').textContent,
      download: !document.getElementById('jd-download').hidden,
      sweep: !!document.getElementById('jd-sweep-table'),
      stats: !!document.getElementById('jd-stats-table'),
      dots: document.querySelectorAll('#jd-pattern g.dot-primary').length,
    }));
    const bKernel = jobs['random-stats'].result.best.kernels_expanded[0].length;
    assert(b.exportText === '' && !b.download && !b.sweep && b.stats && b.dots === bKernel, `after job B: ${JSON.stringify(b)} (B's kernel has ${bKernel} samples)`);
  });
}
