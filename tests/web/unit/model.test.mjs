// Unit tests of the dashboard's pure modules (answer reading, trace axes, pattern geometry):
// run with `node --test`, no browser needed. The answers are real daemon answers saved by
// tests/web/fixtures/capture.mjs (rerun it when a response shape changes).

import test from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import {
  normEvaluation, normJob, jobsFrom, traceCurve, traceXLabel, sweepRows, randomStatsRow, table3Rows, TABLE3_COLUMNS, comparisonRows, comparisonPrediction, animationTable, convergenceTable,
  renderImages, renderStats, presetsFrom, normPreset, filtersFrom, acuityFrom, acuityLabel, wirePattern, jobPattern, familySeries,
  executionText, predictionFrom, predictionRatio, costliestAngles, fmtShare,
} from '../../../web/js/model.js';
import { traceAxes, tickLabels } from '../../../web/js/trace-axes.js';
import { kernelsOf, layoutDots, moveSample, drawableOf, placeWeightLabels } from '../../../web/js/pattern-geometry.js';

const FIXTURES = path.join(path.dirname(fileURLToPath(import.meta.url)), '..', 'fixtures');
const load = (name) => JSON.parse(fs.readFileSync(path.join(FIXTURES, `${name}.json`), 'utf8'));

test('evaluation with detail: one row list per kernel, kernels numbered from 0', () => {
  const raw = load('evaluate-flipquad-detail');
  const ev = normEvaluation(raw);
  assert.equal(ev.e2, raw.e2);
  assert.equal(ev.argmaxKernel, raw.argmax.kernel);
  assert.equal(ev.argmaxAngle, raw.argmax.angle_deg);
  assert.equal(ev.family, raw.family);
  assert.equal(ev.cost, raw.cost_spp);
  assert.equal(ev.kernels.length, raw.kernel_count);
  assert.equal(ev.kernels[0].length, raw.angle_count);
  const k = raw.detail[1].kernel;
  assert.deepEqual(ev.kernels[k][3], { angle: raw.detail[1].angles[3].angle_deg, weight: raw.detail[1].angles[3].weight, e1: raw.detail[1].angles[3].e1, weighted: raw.detail[1].angles[3].weighted });
  // The maximum of the weighted error over kernels and angles is E2, at argmax.
  const max = Math.max(...ev.kernels.flat().map((r) => r.weighted));
  assert.equal(max, ev.e2);
  assert.equal(ev.kernels[ev.argmaxKernel].find((r) => r.angle === ev.argmaxAngle).weighted, ev.e2);
});

test('evaluation without detail has no kernels rather than a crash', () => {
  const raw = { ...load('evaluate-flipquad-detail') };
  delete raw.detail;
  assert.deepEqual(normEvaluation(raw).kernels, []);
});

test('presets, filters and acuity tables', () => {
  const presets = presetsFrom(load('presets'));
  const raw = load('presets').presets;
  assert.equal(presets.length, raw.length);
  const rgss = presets.find((p) => p.name === 'rgss');
  assert.equal(rgss.published, raw.find((p) => p.name === 'rgss').published_e2);
  assert.equal(presets.find((p) => p.name === 'centroid').published, null);
  const q = normPreset(load('preset-quincunx'));
  assert.deepEqual(q.pattern, { kernels: load('preset-quincunx').pattern.kernels });
  const filters = filtersFrom(load('filters'));
  const mitchell = filters.find((f) => f.name === 'mitchell');
  assert.deepEqual(Object.keys(mitchell.params).sort(), ['B', 'C']);
  assert.equal(mitchell.isDefault, true);
  assert.deepEqual(filters.find((f) => f.name === 'gaussian').params, { sigma: 0.5, radius: 2 });
  const acuity = acuityFrom(load('acuity'));
  assert.deepEqual(acuity.names, load('acuity').tables.map((t) => t.name));
  assert.equal(acuity.default, 'naiman');
  // Both Naiman tables, by name and version, each with its one-sentence description.
  const naiman = acuity.tables.find((t) => t.name === 'naiman');
  const envelope = acuity.tables.find((t) => t.name === 'naiman-envelope');
  assert.equal(naiman.version, 2);
  assert.equal(envelope.version, 1);
  assert.equal(acuityLabel(naiman), 'naiman v2');
  assert.ok(naiman.description.length > 20 && envelope.description.length > 20);
});

test('job list: summaries carry kind, state, family and best E2; no detail needed', () => {
  const raw = load('jobs-list');
  const jobs = jobsFrom(raw);
  assert.equal(jobs.length, raw.jobs.length);
  for (const [i, j] of jobs.entries()) {
    assert.equal(j.id, raw.jobs[i].id);
    assert.equal(j.kind, raw.jobs[i].kind);
    assert.equal(j.bestE2, raw.jobs[i].best_e2 ?? null);
    assert.equal(j.family, raw.jobs[i].family ?? '');
    assert.equal(j.label, raw.jobs[i].label ?? '');
  }
  const opt = jobs.find((j) => j.kind === 'optimize');
  assert.equal(opt.bestE2, load('job-optimize').result.e2);
  assert.equal(opt.label, load('job-optimize').label);
  assert.ok(opt.label.length > 0, 'the fixture optimize job carries a label');
});

test('optimize job: best pattern and E2 from the result; the trace curve runs to the end', () => {
  const raw = load('job-optimize');
  const j = normJob(raw);
  assert.equal(j.bestE2, raw.result.e2);
  assert.deepEqual(j.best.pattern, { mirrored: raw.result.best.mirrored });
  assert.equal(j.best.family, raw.result.best.family);
  assert.equal(j.family, raw.family);
  assert.equal(j.trace.length, raw.trace.length);
  const c = traceCurve(j);
  assert.equal(c.points, raw.trace.length);
  assert.equal(c.endSeconds, raw.finished - raw.started);
  assert.ok(c.endSeconds > raw.trace[raw.trace.length - 1].seconds);
  assert.equal(c.xs.length, raw.trace.length + 1);
  assert.equal(c.xs[c.xs.length - 1], c.endSeconds);
  assert.equal(c.ys[c.ys.length - 1], raw.trace[raw.trace.length - 1].best_e2);
});

test('a running job: the trace curve runs to now; a job not started has no end', () => {
  const raw = { ...load('job-optimize'), state: 'running', finished: null };
  const now = raw.started + 5;
  const c = traceCurve(normJob(raw), now);
  assert.equal(c.endSeconds, 5);
  assert.equal(c.xs[c.xs.length - 1], 5);
  const queued = traceCurve(normJob({ ...raw, state: 'queued', started: null, trace: [] }), now);
  assert.deepEqual([queued.xs, queued.endSeconds], [[], null]);
});

test('table3: the trace is Opt W+P work, its curve ends at its last point, not the wall time (issue 34)', () => {
  const raw = { ...load('job-optimize'), kind: 'table3' };
  raw.finished = raw.started + raw.trace[raw.trace.length - 1].seconds * 5;
  const c = traceCurve(normJob(raw));
  assert.equal(c.endSeconds, null);
  assert.equal(c.xs.length, raw.trace.length);
  assert.equal(Math.max(...c.xs), Math.max(...raw.trace.map((p) => p.seconds)));
  assert.match(traceXLabel('table3'), /Opt W\+P seconds/);
  assert.equal(traceXLabel('optimize'), 'seconds');
});

test('a running job whose best is newer than its trace: the curve ends at the best, as the header (issue 34)', () => {
  const raw = { ...load('job-optimize'), state: 'running', finished: null };
  const last = raw.trace[raw.trace.length - 1].best_e2;
  raw.best_e2 = last - 1e-6;
  raw.result = null;
  const c = traceCurve(normJob(raw), raw.started + 1000);
  assert.equal(c.ys[c.ys.length - 1], raw.best_e2);
  assert.equal(c.best, raw.best_e2);
  // A best that lags behind the trace does not lift the curve.
  const lag = traceCurve(normJob({ ...raw, best_e2: last + 1e-3 }), raw.started + 1000);
  assert.equal(lag.ys[lag.ys.length - 1], last);
  assert.equal(lag.best, last);
});

test('sleep job with a pattern: best {elapsed, pattern}, trace from 1 down', () => {
  const raw = load('job-sleep');
  const j = normJob(raw);
  assert.deepEqual(j.best.pattern, { kernels: raw.best.pattern.kernels });
  assert.equal(j.best.e2, null);
  assert.equal(jobPattern(j), j.best.pattern);
});

test('family-sweep: ranked rows with their configuration, E2 and pattern', () => {
  const raw = load('job-family-sweep');
  const rows = sweepRows(raw.result);
  assert.equal(rows.length, raw.result.configurations);
  assert.deepEqual(rows.map((r) => r.rank), raw.result.ranked.map((r) => r.rank));
  for (let i = 1; i < rows.length; i++) assert.ok(rows[i - 1].e2 <= rows[i].e2, 'ranked by E2');
  const c = raw.result.ranked[0].config;
  assert.equal(rows[0].config, `corners ${c.corners.join('')} · edges ${c.edges.join('')} · interior ${c.interior}`);
  assert.deepEqual(rows[2].pattern, { mirrored: raw.result.ranked[2].best.mirrored });
  const j = normJob(raw);
  assert.deepEqual(jobPattern(j, { rank: 3 }), rows[2].pattern);
  assert.equal(j.bestE2, raw.result.e2);
});

test('table3: rows of mean and sd per column, the generator, the acuity by name and version', () => {
  const raw = load('job-table3');
  const x = table3Rows(raw.result);
  assert.equal(x.rows.length, raw.result.rows.length);
  assert.deepEqual(TABLE3_COLUMNS.map(([k]) => k), ['min', 'avg', 'max', 'opt_w', 'opt_wp']);
  for (const [i, row] of raw.result.rows.entries()) {
    assert.equal(x.rows[i].distribution, row.distribution);
    assert.deepEqual(x.rows[i].cols.map((c) => c.mean), TABLE3_COLUMNS.map(([k]) => row.columns[k].mean));
    assert.deepEqual(x.rows[i].cols.map((c) => c.sd), TABLE3_COLUMNS.map(([k]) => row.columns[k].sd));
  }
  assert.equal(x.rows[0].generator, 'dart-throwing-torus');
  assert.ok(x.rows[0].radius > 0);
  assert.equal(x.acuity, 'naiman v2');
  assert.deepEqual(x.seeds, raw.result.seeds);
});

test('random-stats: the Table 3 row (min, avg, max, Opt W, Opt W+P)', () => {
  const raw = load('job-random-stats');
  const x = randomStatsRow(raw.result);
  assert.deepEqual([x.min, x.avg, x.max], [raw.result.random.min, raw.result.random.avg, raw.result.random.max]);
  assert.equal(x.optW, raw.result.opt_w.e2);
  assert.equal(x.optWP, raw.result.opt_wp.e2);
  assert.equal(x.family, raw.result.family);
  assert.equal(x.count, raw.result.count);
  assert.ok(x.min <= x.avg && x.avg <= x.max);
  const j = normJob(raw);
  // A tile pattern is sent back whole and drawn read-only from kernels_expanded.
  assert.deepEqual(jobPattern(j, { pick: 'opt_w' }), { tile: raw.result.opt_w.pattern.tile, kernels_expanded: raw.result.opt_w.pattern.kernels_expanded });
  assert.equal(drawableOf(j.best.pattern).readOnly, true);
});

test('compare: one row per pattern with samples per pixel, E2, RMSE, max deviation', () => {
  const raw = load('job-compare');
  const rows = comparisonRows(raw.result);
  assert.equal(rows.length, raw.spec.patterns.length);
  assert.deepEqual(rows.map((r) => r.label), raw.result.rows.map((r) => r.name));
  const r = raw.result.rows[1];
  assert.deepEqual(rows[1], { label: r.name, family: r.family, spp: r.samples_per_pixel, e2: r.e2, rmse: r.rmse, maxDev: r.max_dev, seconds: r.render_seconds, predicted: r.predicted_rmse });
  assert.ok(rows[1].predicted > 0, 'the compare job predicts each row');
  assert.deepEqual(comparisonPrediction(raw.result), { spearman: raw.result.prediction.spearman, subpixelAreaShare: raw.result.prediction.subpixel_area_share });
  assert.equal(comparisonPrediction({ rows: [] }), null);
  assert.equal(normJob(raw).best, null);
});

test('animation: frames and the whole animation', () => {
  const raw = load('job-animation');
  const a = animationTable(raw.result);
  assert.equal(a.frames.length, raw.spec.scene.frames);
  assert.equal(a.frames[1].rmse, raw.result.frames[1].rmse);
  assert.equal(a.frames[1].recomputed, raw.result.frames[1].pixels_recomputed);
  assert.equal(a.total.rmse, raw.result.total.rmse);
  assert.equal(a.e2, raw.result.e2);
  assert.equal(a.family, raw.result.pattern.family);
  // Animation's best names only the pattern's family and cost: nothing to draw or export.
  assert.equal(normJob(raw).best, null);
  assert.equal(normJob(raw).bestE2, raw.result.e2);
});

test('reference-convergence: one row per level against the baseline', () => {
  const raw = load('job-reference-convergence');
  const c = convergenceTable(raw.result);
  assert.deepEqual(c.rows.map((r) => r.spp), raw.spec.levels);
  assert.equal(c.baselineSpp, raw.spec.baseline_spp);
  assert.equal(c.rows[0].rmse, raw.result.rows[0].rmse);
  assert.ok(c.rows[1].rmse < c.rows[0].rmse, 'more samples, less error');
});

test('render answer: image URLs and statistics', () => {
  const raw = load('render-quincunx');
  assert.deepEqual(renderImages(raw), { pattern: raw.tiles.pattern.url, reference: raw.tiles.reference.url, difference: raw.tiles.difference.url });
  const s = renderStats(raw);
  assert.deepEqual(
    [s.rmse, s.maxDev, s.e2, s.patternSeconds, s.referenceSeconds, s.supersampled, s.totalPixels],
    [raw.stats.rmse, raw.stats.max_dev, raw.e2, raw.times.pattern_seconds, raw.times.reference_seconds, raw.pixels.supersampled, raw.pixels.total],
  );
  assert.deepEqual(s.histogram, raw.stats.penalised_histogram);
});

test('wire patterns by form', () => {
  assert.deepEqual(wirePattern({ form: 'mirrored', mirrored: [[0, 0, 1]], kernels_expanded: [] }), { mirrored: [[0, 0, 1]] });
  assert.deepEqual(wirePattern({ form: 'kernels', kernels: [[[0, 0, 1]]] }), { kernels: [[[0, 0, 1]]] });
  assert.equal(wirePattern({ family: 'P(1,1+,2)', samples_per_pixel: 2 }), null); // animation's best
});

test('trace axes: a narrow E2 range gets several distinct ticks, on log and linear axes', () => {
  const raw = load('job-random-stats'); // E2 improves by 1e-4 over most of its trace
  const c = traceCurve(normJob(raw));
  for (const mode of ['log', 'linear']) {
    const a = traceAxes(c.xs, c.ys, mode);
    assert.ok(a.y.ticks.length >= 3, `${mode}: ${a.y.ticks.length} y ticks`);
    assert.equal(new Set(tickLabels(a.y.ticks)).size, a.y.ticks.length, `${mode}: labels tell ticks apart`);
    assert.ok(a.x.ticks.length >= 3);
    for (const t of [...a.x.ticks, ...a.y.ticks]) assert.ok(Number.isFinite(t));
    assert.ok(a.y.range[0] < Math.min(...c.ys) && a.y.range[1] > Math.max(...c.ys));
  }
  const narrow = traceAxes([0.1, 1, 2], [0.30912, 0.30911, 0.309105], 'log');
  assert.ok(narrow.y.ticks.length >= 3, String(narrow.y.ticks));
});

test('trace axes: log axes leave out t = 0 and never get an empty or non-positive range', () => {
  const a = traceAxes([0, 0.5, 1], [1, 0.5, 0.5], 'log');
  assert.deepEqual(a.xs, [0.5, 1]);
  assert.ok(a.x.range[0] > 0 && a.x.range[1] > a.x.range[0]);
  const one = traceAxes([0.2], [0.5], 'log');
  assert.ok(one.x.range[1] > one.x.range[0] && one.y.range[1] > one.y.range[0] && one.y.range[0] > 0);
  const none = traceAxes([0], [0.5], 'log');
  assert.deepEqual(none.xs, []);
  assert.ok(none.x.ticks.length > 0);
  const lin = traceAxes([0, 0], [0.5, 0.5], 'linear');
  assert.ok(lin.x.range[1] > lin.x.range[0] && lin.y.range[1] > lin.y.range[0]);
});

test('trace axes: a trace over many decades of time keeps its labels apart', () => {
  const raw = load('job-sleep'); // first point after about 1e-7 s, last after 0.3 s
  const c = traceCurve(normJob(raw));
  const a = traceAxes(c.xs, c.ys, 'log');
  assert.ok(a.x.range[1] / a.x.range[0] > 1e5, `x range ${a.x.range}`);
  assert.ok(a.x.ticks.length >= 3 && a.x.ticks.length <= 9, String(a.x.ticks));
  for (let i = 1; i < a.x.ticks.length; i++) assert.ok(a.x.ticks[i] / a.x.ticks[i - 1] >= 10 - 1e-9, String(a.x.ticks));
});

test('family series label', () => {
  assert.equal(familySeries('P(4,1+,1.25)'), 'P(4,1+,n)');
  assert.equal(familySeries('P(1, 1, 4)'), 'P(1,1,n)');
  assert.equal(familySeries(''), 'other');
});

test('mirrored pattern: four mirrored kernels; shared edge samples drawn once', () => {
  const p = { mirrored: [[-0.5, 1 / 6, 0.25], [0.5, -1 / 6, 0.25], [1 / 6, 0.5, 0.25], [-1 / 6, -0.5, 0.25]] };
  const k = kernelsOf(p);
  assert.equal(k.length, 4);
  assert.deepEqual(k[1][0], [0.5, 1 / 6, 0.25]);
  const dots = layoutDots(p, 0);
  assert.equal(dots.filter((d) => d.primary).length, 4);
  const keys = dots.map((d) => `${d.x.toFixed(6)},${d.y.toFixed(6)}`);
  assert.equal(new Set(keys).size, keys.length);
  assert.ok(!dots.some((d) => !d.primary && Math.abs(d.x + 0.5) < 1e-9 && Math.abs(d.y - 1 / 6) < 1e-9));
});

test('moving samples: edge samples stay on their edge, mirrored samples stay in the pixel', () => {
  const p = { mirrored: [[-0.5, 0.1, 0.5], [0.2, 0.2, 0.5]] };
  moveSample(p, 0, 0, 0.3, 0.3, true);
  assert.deepEqual(p.mirrored[0], [-0.5, 0.3, 0.5]);
  moveSample(p, 0, 1, 0.9, -0.1, true);
  assert.deepEqual(p.mirrored[1], [0.5, -0.1, 0.5]);
  const q = { kernels: [[[0, 0, 0.5], [-0.5, -0.5, 0.5]]] };
  moveSample(q, 0, 1, 0.1, 0.1, true);
  assert.deepEqual(q.kernels[0][1], [-0.5, -0.5, 0.5]);
  moveSample(q, 0, 1, 0.1, 0.1, false);
  assert.deepEqual(q.kernels[0][1], [0.1, 0.1, 0.5]);
});

test('execution: where an optimizer job ran and whether its result is reproducible', () => {
  const raw = load('job-family-sweep');
  const r = raw.result;
  assert.equal(typeof r.executor, 'string', 'optimizer results say their executor');
  const expect = `${r.executor}, ${r.shards} shard${r.shards === 1 ? '' : 's'}, ${r.reproducible ? 'reproducible' : 'best effort (time budget)'}`;
  assert.equal(normJob(raw).execution, expect);
  assert.equal(executionText({ executor: 'slurm' }, { executor: 'slurm', shards: 8, reproducible: true }), 'slurm, 8 shards, reproducible');
  assert.equal(executionText({ executor: 'slurm' }, null), 'slurm', 'running: the spec says');
  assert.equal(executionText({}, { e2: 0.1 }), null, 'kinds without an executor');
});

test('prediction: the scene histogram, the pattern E1 at every angle, the costliest angles', () => {
  const raw = load('predict-rgss-half-plane');
  const p = predictionFrom(raw);
  const q = raw.predictions[0];
  assert.equal(p.rmse, q.predicted_rmse);
  assert.equal(p.lockedShare, q.locked_share);
  assert.equal(p.subpixelAreaShare, q.subpixel_area_share);
  assert.equal(p.subpixelEstimated, false);
  assert.equal(p.edgeLength.length, 180);
  assert.equal(p.e1ByAngle.length, 180);
  assert.equal(p.totalLength, raw.edges.total_length);
  assert.equal(p.filter, raw.reference.filter);
  // A 27° half-plane: all its length in bin 27, where the pattern's E1 is angles[0]'s.
  assert.equal(p.angles[0].angle, 27);
  assert.equal(p.edgeLength[27], raw.edges.total_length);
  assert.ok(Math.abs(p.e1ByAngle[27] - q.angles[0].e1_rms) <= 1e-12 * q.angles[0].e1_rms, 'E1 by angle is the prediction\'s E1');
  assert.ok(p.e1ByAngle.every((v) => v > 0), 'RGSS has an error at every angle');
  assert.equal(predictionFrom({ predictions: [] }), null);
  assert.equal(predictionFrom({ predictions: [{ predicted_rmse: 1 }] }).e1ByAngle, null, 'no e1_by_angle asked');
});

test('prediction ratio and costliest angles', () => {
  assert.equal(predictionRatio(2, 4), 0.5);
  assert.equal(predictionRatio(2, 0), null);
  assert.equal(predictionRatio(null, 4), null);
  const angles = [0.5, 0.2, 0.15, 0.1, 0.05].map((share, i) => ({ angle: i * 10, share }));
  const c = costliestAngles(angles, 2);
  assert.deepEqual(c.top.map((a) => a.angle), [0, 10]);
  assert.equal(c.restCount, 3);
  assert.ok(Math.abs(c.rest - 0.3) < 1e-12);
  assert.equal(fmtShare(0.1234), '12.3 %');
  assert.equal(fmtShare(null), '—');
});

test('weight labels of a 64-sample kernel cover no dot and no other label (issue 34: P(16,16,4) drawings)', () => {
  // An 8x8 grid in a 140-unit pixel, as the job view draws a P(16,16,4) kernel, plus neighbours.
  const circles = [];
  for (let j = -8; j < 16; j++) for (let i = -8; i < 16; i++) circles.push({ x: 140 + i * 17.5 + 8, y: 140 + j * 17.5 + 8, r: 4 + ((i * 7 + j) % 3) });
  const primary = circles.map((c, i) => ({ c, i })).filter(({ c }) => c.x > 140 && c.x < 280 && c.y > 140 && c.y < 280);
  assert.equal(primary.length, 64);
  const labels = primary.map(({ i }) => ({ i, text: '0.016' }));
  const placed = placeWeightLabels(circles, labels, 12);
  for (const [k, p] of placed.entries()) {
    for (const c of circles) {
      const dx = Math.max(p.box.x0 - c.x, 0, c.x - p.box.x1);
      const dy = Math.max(p.box.y0 - c.y, 0, c.y - p.box.y1);
      assert.ok(dx * dx + dy * dy >= c.r * c.r, `label of dot ${p.i} covers a dot at ${c.x},${c.y}`);
    }
    for (const q of placed.slice(k + 1)) assert.ok(!(p.box.x0 < q.box.x1 && q.box.x0 < p.box.x1 && p.box.y0 < q.box.y1 && q.box.y0 < p.box.y1), `labels ${p.i} and ${q.i} overlap`);
  }
  // A sparse kernel (4 samples far apart) keeps every label.
  const sparse = [{ x: 100, y: 100, r: 20 }, { x: 300, y: 100, r: 20 }, { x: 100, y: 300, r: 20 }, { x: 300, y: 300, r: 20 }];
  assert.equal(placeWeightLabels(sparse, sparse.map((_, i) => ({ i, text: '0.25' })), 12).length, 4);
});
