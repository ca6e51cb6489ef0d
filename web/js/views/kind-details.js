// The part of a job's detail that depends on its kind: a family sweep's ranked table, the
// random-stats row of Laine & Aila's Table 3, a comparison's error against samples per pixel,
// an animation's frames, a reference's convergence, a temporal-optimize job's seeds and best
// sequence and a temporal-render job's phases against the edge model. Each renders a finished job's result
// into an empty container.

import { sweepRows, randomStatsRow, table3Rows, TABLE3_COLUMNS, comparisonRows, comparisonPrediction, predictionRatio, animationTable, convergenceTable, optimizeSeeds, comparisonImages, animationImages, fmt, fmtSeconds } from '../model.js';
import { apiImageUrl } from '../api.js';
import { drawScatter, scatterLegend } from '../scatter-plot.js';
import { drawSequence } from './temporal.js';

function node(tag, attrs = {}, children = []) {
  const n = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'text') n.textContent = v;
    else if (k === 'className') n.className = v;
    else n.setAttribute(k, v);
  }
  for (const c of children) n.append(c);
  return n;
}

function evaluateLink(href, text) {
  return node('a', { href, text });
}

/* A table with a caption, a header row and body rows; cells are strings or nodes; columns from
 * numeric onwards are right-aligned numbers. */
export function table({ id, caption, head, rows, numericFrom = 1, compact = false }) {
  const t = node('table', { className: compact ? 'data compact' : 'data', ...(id ? { id } : {}) });
  if (caption) t.append(node('caption', { text: caption }));
  t.append(node('thead', {}, [node('tr', {}, head.map((h) => node('th', { scope: 'col', text: h })))]));
  const body = node('tbody');
  for (const r of rows) {
    const tr = node('tr');
    r.forEach((c, i) => {
      const td = node('td', i >= numericFrom ? { className: 'num' } : {});
      td.append(c == null ? '—' : c);
      tr.append(td);
    });
    body.append(tr);
  }
  t.append(body);
  return t;
}

function sweep(holder, job) {
  const rows = sweepRows(job.result);
  const r = job.result;
  holder.append(
    node('p', { className: 'hint', text: `${r.configurations} configurations of cost ${r.cost} samples/pixel, ${r.seeds_per_config} seeds each, ranked by E2. A row opens its best pattern in Evaluate.` }),
    table({
      id: 'jd-sweep-table',
      caption: 'Configurations ranked by E2',
      head: ['Rank', 'Configuration', 'Family', 'E2', 'Pattern'],
      numericFrom: 3,
      rows: rows.map((x) => [String(x.rank), x.config, x.family, fmt(x.e2, 6), evaluateLink(`#/evaluate?job=${encodeURIComponent(job.id)}&rank=${x.rank}`, 'Open in Evaluate')]),
    }),
  );
  for (const [i, tr] of [...holder.querySelectorAll('#jd-sweep-table tbody tr')].entries()) tr.dataset.rank = String(rows[i].rank);
}

function randomStats(holder, job) {
  const x = randomStatsRow(job.result);
  const link = (pick, v) => (v == null ? '—' : evaluateLink(`#/evaluate?job=${encodeURIComponent(job.id)}&pick=${pick}`, fmt(v, 4)));
  holder.append(
    node('p', { className: 'hint', text: `E2 of ${x.count} random ${x.distribution} patterns of ${x.family} (weights from the filter), then the best of them optimized for weights only (Opt W, ${x.optWMethod}) and for weights and positions (Opt W+P, ${x.optWPMethod}), as in Laine & Aila Table 3.` }),
    table({
      id: 'jd-stats-table',
      caption: 'Random patterns and their optimization (E2)',
      head: ['Family', 'Distribution', 'Min', 'Avg', 'Max', 'Opt W', 'Opt W+P'],
      numericFrom: 2,
      rows: [[x.family, x.distribution, fmt(x.min, 4), fmt(x.avg, 4), fmt(x.max, 4), link('opt_w', x.optW), link('opt_wp', x.optWP)]],
    }),
  );
  pointMetrics(holder, [[null, job.result.point_metrics]]);
}

/* Spearman's ρ of each point-set figure with E2 over the random patterns, when the spec asked
 * for metrics (point_metrics.json): one table, a row per figure (and distribution for table3). */
function pointMetrics(holder, blocks) {
  const rows = [];
  for (const [label, pm] of blocks) {
    for (const e of (pm && pm.spearman) || []) {
      const p = e.p_value == null ? null : (e.p_value === 0 || e.p_value >= 1e-3 ? e.p_value.toPrecision(2) : e.p_value.toExponential(1));
      rows.push([...(label == null ? [] : [label]), e.metric, fmt(e.rho, 3), String(e.n), p]);
    }
  }
  if (!rows.length) return;
  const labelled = blocks.some(([label]) => label != null);
  holder.append(table({
    id: 'jd-point-metrics',
    caption: 'Spearman ρ of each point-set figure with E2 over the random patterns',
    head: [...(labelled ? ['Distribution'] : []), 'Figure', 'ρ', 'n', 'p-value'],
    numericFrom: labelled ? 2 : 1,
    rows,
  }));
}

/* table3: the paper's table with a ± column after each figure (sd over the seeds) and, under
 * each distribution, the paper's row where the paper has one. */
function table3(holder, job) {
  const x = table3Rows(job.result);
  const head = ['Distribution'];
  for (const [, label] of TABLE3_COLUMNS) head.push(label, '±');
  const rows = [];
  for (const r of x.rows) {
    rows.push([r.distribution, ...r.cols.flatMap((c) => [fmt(c.mean, 4), fmt(c.sd, 4)])]);
    if (r.cols.some((c) => c.paper != null)) rows.push([`${r.distribution} (paper)`, ...r.cols.flatMap((c) => [fmt(c.paper, 3), ''])]);
  }
  const gens = x.rows.map((r) => `${r.distribution}: ${r.generator}${r.radius != null ? ` (radius ${fmt(r.radius, 3)} px)` : ''}`).join('; ');
  holder.append(
    node('p', { className: 'hint', text: `Laine & Aila Table 3 for ${x.family} over ${x.seeds.length} rng_seeds (${x.seeds.join(', ')}), ${x.count} random patterns each: mean ± sample standard deviation over the seeds, the paper's values below. Generators: ${gens}. Acuity ${x.acuity}.` }),
    table({ id: 'jd-table3', caption: 'Table 3: E2 mean ± sd over seeds, beside the paper', head, rows, compact: true }),
  );
  pointMetrics(holder, (job.result.rows || []).map((r) => [r.distribution, r.point_metrics]));
}

/* Comparison rows as RMSE and E2 against samples per pixel (a pattern's cost; its CPU render
 * time here says nothing about a GPU) and a table. Shared with the Tiles view. */
/* prediction: comparisonPrediction of the result (null: no caption line about it). */
export function drawComparison({ plot, plotE2, legend, tableHolder, tableId, rows, prediction = null }) {
  const series = rows.map((r) => ({ label: r.label, points: [{ x: r.spp, y: r.rmse, title: `${r.label}: RMSE ${fmt(r.rmse, 3)} at ${r.spp} samples/pixel` }] }));
  drawScatter(plot, { series, xLabel: 'samples per pixel', yLabel: 'RMSE (0..255)', labels: true, width: 560, height: 300, title: 'RMSE against samples per pixel' });
  const e2 = rows.map((r) => ({ label: r.label, points: [{ x: r.spp, y: r.e2, title: `${r.label}: E2 ${fmt(r.e2, 4)} at ${r.spp} samples/pixel` }] }));
  drawScatter(plotE2, { series: e2, xLabel: 'samples per pixel', yLabel: 'E2', labels: true, width: 560, height: 300, title: 'E2 against samples per pixel' });
  scatterLegend(legend, rows.map((r) => r.label));
  // The edge model's prediction beside each measured row (docs/predict.md), after the columns
  // that were there before it.
  const caption = prediction
    ? `Predicted RMSE against measured: Spearman ρ ${fmt(prediction.spearman, 3)} over ${rows.length} patterns${prediction.subpixelAreaShare > 0 ? `; ${(prediction.subpixelAreaShare * 100).toFixed(1)} % of the image is below the pixel scale, its error not predicted` : ''}`
    : null;
  const t = table({
    id: tableId,
    compact: true,
    caption,
    head: ['Pattern', 'Samples/pixel', 'E2', 'RMSE', 'Max dev.', 'Render time', 'Predicted RMSE', 'Measured/predicted'],
    rows: rows.map((r) => [r.label, r.spp == null ? '—' : String(r.spp), fmt(r.e2, 4), fmt(r.rmse, 3), fmt(r.maxDev, 1), fmtSeconds(r.seconds), fmt(r.predicted, 3), fmt(predictionRatio(r.rmse, r.predicted), 3)]),
  });
  tableHolder.replaceChildren(t);
}

/* A row of small images (tiles of the job's renders), fetched with the token as blob URLs. */
function thumbs(id, items) {
  const box = node('div', { className: 'thumbs', id });
  for (const it of items) {
    if (!it.image) continue;
    const img = node('img', { alt: it.caption, width: 96, height: 96 });
    img.dataset.tile = it.image.url;
    apiImageUrl(it.image.url)
      .then((u) => {
        img.src = u;
      })
      .catch(() => {
        img.alt = `${it.caption} (image no longer stored)`;
      });
    box.append(node('figure', {}, [img, node('figcaption', { text: it.caption })]));
  }
  return box;
}

function optimize(holder, job) {
  const x = optimizeSeeds(job.result);
  if (!x.rows.length) return;
  holder.append(
    node('p', { className: 'hint', text: `Each seed starts from its own random pattern; the job's best (E2 ${fmt(job.result.e2, 6)}, after any final refinement) comes from the seed marked best.` }),
    table({
      id: 'jd-seeds-table',
      caption: 'Per seed: E2 before and after optimization',
      head: ['Seed', 'Distribution', 'Initial E2', 'E2', 'Iterations'],
      numericFrom: 2,
      rows: x.rows.map((r, i) => [`${r.seed}${i === x.best ? ' (best)' : ''}`, r.distribution, fmt(r.initial, 6), fmt(r.e2, 6), r.iterations == null ? '—' : String(r.iterations)]),
    }),
  );
}

function compare(holder, job) {
  const plot = node('div', { id: 'jd-cmp-plot', className: 'plot-holder' });
  const plotE2 = node('div', { id: 'jd-cmp-plot-e2', className: 'plot-holder' });
  const legend = node('p', { className: 'legend' });
  const tableHolder = node('div');
  const s = job.result.scene;
  holder.append(node('p', { className: 'hint', text: `${s.name}, ${s.width}×${s.height}, reference ${job.result.reference.spp} spp.` }), node('div', { className: 'plots-2' }, [plot, plotE2]), legend, tableHolder);
  drawComparison({ plot, plotE2, legend, tableHolder, tableId: 'jd-cmp-table', rows: comparisonRows(job.result), prediction: comparisonPrediction(job.result) });
  const im = comparisonImages(job.result);
  holder.append(
    node('h3', { text: 'Renders: the reference, then each pattern and its difference to the reference' }),
    thumbs('jd-cmp-images', [{ image: im.reference, caption: 'reference' }, ...im.rows.flatMap((r) => [{ image: r.pattern, caption: r.label }, { image: r.difference, caption: `${r.label} difference` }])]),
  );
}

function animation(holder, job) {
  const a = animationTable(job.result);
  const rows = a.frames.map((f) => [String(f.frame), fmt(f.rmse, 3), fmt(f.maxDev, 1), String(f.recomputed), fmtSeconds(f.patternSeconds), fmtSeconds(f.referenceSeconds)]);
  if (a.total) rows.push(['all frames', fmt(a.total.rmse, 3), fmt(a.total.maxDev, 1), `${a.recomputed} of ${a.allPixels}`, '', '']);
  holder.append(
    node('p', { className: 'hint', text: `${job.result.scene.name}, ${a.frames.length} frames, pattern ${a.family} (${a.spp} samples/pixel, E2 ${fmt(a.e2, 4)}); only pixels the moving content touches are recomputed.` }),
    table({ id: 'jd-anim-table', caption: 'Error per frame (0..255)', head: ['Frame', 'RMSE', 'Max dev.', 'Pixels recomputed', 'Pattern time', 'Reference time'], rows }),
  );
  // The first frames' renders (a long animation shows 8).
  const frames = animationImages(job.result).slice(0, 8);
  holder.append(
    node('h3', { text: 'Frames: pattern, reference and difference' }),
    thumbs('jd-anim-images', frames.flatMap((f) => [{ image: f.pattern, caption: `frame ${f.frame}` }, { image: f.reference, caption: `frame ${f.frame} reference` }, { image: f.difference, caption: `frame ${f.frame} difference` }])),
  );
}

function convergence(holder, job) {
  const c = convergenceTable(job.result);
  const plot = node('div', { id: 'jd-conv-plot', className: 'plot-holder' });
  holder.append(plot);
  const pts = c.rows.filter((r) => r.rmse != null && r.rmse > 0 && r.spp > 0);
  drawScatter(plot, {
    series: [{ label: 'RMSE', line: true, points: pts.map((r) => ({ x: r.spp, y: r.rmse, title: `${r.spp} spp: RMSE ${fmt(r.rmse, 3)}` })) }],
    xLabel: 'reference samples per pixel',
    yLabel: 'RMSE (0..255)',
    xLog: true,
    yLog: true,
    width: 560,
    height: 300,
    title: `Reference RMSE against samples per pixel (baseline ${c.baselineSpp} spp)`,
  });
  holder.append(
    node('p', { className: 'hint', text: `Each reference against one at ${c.baselineSpp} spp (rendered in ${fmtSeconds(c.baselineSeconds)}, independent seed).` }),
    table({
      id: 'jd-conv-table',
      caption: 'Reference error against samples per pixel (0..255)',
      head: ['Reference spp', 'RMSE', 'Max dev.', 'Render time', 'Samples'],
      rows: c.rows.map((r) => [String(r.spp), fmt(r.rmse, 3), fmt(r.maxDev, 2), fmtSeconds(r.seconds), String(r.samples)]),
    }),
  );
}

function blendText(b) {
  if (!b || !b.kind) return '—';
  return b.kind === 'exponential' ? `exponential, α ${b.alpha}` : b.kind;
}

/* temporal-optimize (issue 30): the best sequence drawn with its frame numbers (the worst phase
 * marked), its figures, E2 per phase and a row per seed; "Open in Temporal" loads it there. */
function temporalOptimize(holder, job) {
  const r = job.result;
  const t = (r.best && r.best.temporal) || {};
  const phaseE2 = r.phase_e2 || [];
  const worst = phaseE2.reduce((w, v, i) => (v != null && (w < 0 || v > phaseE2[w]) ? i : w), -1);
  const seq = node('div', { id: 'jd-tseq', className: 'pattern-holder small' });
  const figures = table({
    id: 'jd-topt-figures',
    caption: `Best sequence ${r.family}: ${blendText(t.blend)}`,
    head: ['Figure', 'Value'],
    rows: [
      ['E2, worst phase', fmt(r.e2, 6)],
      ['E2, mean over phases', fmt(r.mean_phase_e2, 6)],
      ['Flicker F2', fmt(r.f2, 6)],
      ['Frames to settle (5 %)', r.frames_to_settle == null ? 'not within 4N' : String(r.frames_to_settle)],
      ['Objective', r.objective || '—'],
      ['Start E2', fmt(r.start_e2, 6)],
      ['Seeds run', String(r.seeds_run)],
      ['Evaluations', String(r.evaluations)],
    ],
  });
  const open = node('a', { id: 'jd-open-temporal', href: `#/temporal?job=${encodeURIComponent(job.id)}`, text: 'Open in Temporal' });
  holder.append(
    node('p', { className: 'hint', text: `The best jitter sequence over ${r.seeds_run} seeds (frame numbers beside its offsets, the worst phase larger); ${open.textContent} evaluates it there with its polars and after-cut curve.` }),
    node('div', { className: 'plots-2' }, [node('figure', {}, [seq, node('figcaption', { text: `${(t.jitter || []).length} offsets in frame order` })]), node('div', {}, [figures, open])]),
    table({
      id: 'jd-topt-phases',
      caption: 'E2 per phase (the newest frame uses offset p)',
      head: ['Phase', 'E2'],
      compact: true,
      rows: phaseE2.map((v, i) => [`${i}${i === worst ? ' (worst)' : ''}`, fmt(v, 6)]),
    }),
    table({
      id: 'jd-topt-seeds',
      caption: 'Per seed: the objective before and after the search',
      head: ['Seed', 'Start', 'Initial score', 'Score', 'E2', 'F2'],
      numericFrom: 2,
      rows: (r.per_seed || []).map((x) => [String(x.seed), x.start, fmt(x.initial_score, 6), fmt(x.score, 6), fmt(x.e2, 6), fmt(x.f2, 6)]),
    }),
  );
  drawSequence(seq, { jitter: t.jitter || [], argmax: { phase: worst } });
}

/* temporal-render (issue 30): a row per phase with the edge model's prediction and the ratio,
 * the RMSE after a cut against the steady state, the flicker, and the worst phase's images. */
function temporalRender(holder, job) {
  const r = job.result;
  const st = r.steady || {};
  const fl = r.flicker || {};
  const p = r.pattern || {};
  const plot = node('div', { id: 'jd-trender-plot', className: 'plot-holder' });
  holder.append(
    node('p', { className: 'hint', text: `${r.scene.name}, ${r.scene.width}×${r.scene.height}, ${p.family}${p.preset ? ` (${p.preset})` : ''}, ${p.samples_per_pixel} spp a frame, blend ${blendText(p.blend)}; reference ${r.reference.spp} spp. E2 ${fmt(r.e2, 4)} (mean ${fmt(r.mean_phase_e2, 4)}), F2 ${fmt(r.f2, 4)}.` }),
    table({
      id: 'jd-trender-phases',
      caption: 'Steady-state error per phase (0..255): rendered against the edge model',
      head: ['Phase', 'E2', 'RMSE', 'Max dev.', 'Predicted RMSE', 'Predicted / rendered'],
      rows: (r.phases || []).map((x) => [`${x.phase}${x.phase === st.worst_phase ? ' (worst)' : ''}`, fmt(x.e2, 4), fmt(x.rmse, 3), fmt(x.max_dev, 1), fmt(x.predicted_rmse, 3), fmt(x.ratio, 3)]),
    }),
    table({
      id: 'jd-trender-summary',
      caption: 'Steady state and flicker (0..255)',
      head: ['Figure', 'Rendered', 'Predicted', 'Ratio'],
      rows: [
        ['RMSE, worst phase', fmt(st.rmse, 3), '', ''],
        ['RMSE, RMS over phases', fmt(st.mean_rmse, 3), fmt(st.predicted_rmse, 3), fmt(st.ratio, 3)],
        ['Flicker, frame to frame', fmt(fl.step_rmse, 3), fmt(fl.predicted_step_rmse, 3), fmt(fl.step_ratio, 3)],
        ['Flicker, about the mean', fmt(fl.mean_rmse, 3), fmt(fl.predicted_mean_rmse, 3), fmt(fl.ratio, 3)],
        ['Frames to 5 % after a cut', r.frames_to_5pct == null ? 'none' : String(r.frames_to_5pct), '', ''],
      ],
    }),
    plot,
    node('p', { className: 'hint', text: `The history k frames after a cut (history = the first frame) against the steady state; within 5 % of it from frame ${r.frames_to_5pct ?? '— (never)'} on.` }),
  );
  const cut = r.after_cut || [];
  drawScatter(plot, {
    series: [
      { label: 'after a cut', line: true, points: cut.map((v, k) => ({ x: k + 1, y: v, title: `frame ${k + 1}: RMSE ${fmt(v, 3)}` })) },
      { label: 'steady state (RMS over phases)', line: true, points: cut.length ? [{ x: 1, y: st.mean_rmse }, { x: cut.length, y: st.mean_rmse }] : [] },
    ],
    xLabel: 'frames after the cut',
    yLabel: 'RMSE (0..255)',
    width: 560,
    height: 300,
    title: 'RMSE after a cut',
  });
  const tiles = r.tiles || {};
  holder.append(
    node('h3', { text: `Worst phase (${st.worst_phase}) in the steady state: render, reference and difference` }),
    thumbs('jd-trender-images', [{ image: tiles.pattern, caption: `phase ${st.worst_phase}` }, { image: tiles.reference, caption: 'reference' }, { image: tiles.difference, caption: 'difference' }]),
  );
}

const BY_KIND = { optimize, 'family-sweep': sweep, 'random-stats': randomStats, table3, compare, animation, 'reference-convergence': convergence, 'temporal-optimize': temporalOptimize, 'temporal-render': temporalRender };

/* Fills holder with the kind's view of a done job's result; false when the kind has none. */
export function renderKindDetail(holder, job) {
  const f = BY_KIND[job.kind];
  if (!f || job.state !== 'done' || !job.result) return false;
  holder.dataset.kind = job.kind;
  f(holder, job);
  return true;
}
