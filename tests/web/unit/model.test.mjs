// Unit tests of the dashboard's pure modules (answer normalisation, pattern geometry): run with
// `node --test`, no browser needed.

import test from 'node:test';
import assert from 'node:assert/strict';
import { normEvaluation, normJob, normTrace, renderImages, renderStats, comparisonRows, familySeries, patternOf, listFrom } from '../../../web/js/model.js';
import { kernelsOf, layoutDots, moveSample, drawableOf } from '../../../web/js/pattern-geometry.js';

test('evaluation detail in the codec shape: one row list per kernel, in kernel order', () => {
  const ev = normEvaluation({
    e2: 0.36,
    argmax: { kernel: 2, angle_deg: 45 },
    family: 'P(4,1+,2)',
    cost_spp: 2,
    detail: [
      { kernel: 0, angles: [{ angle_deg: 5, weight: 3.55, e1: 0.1, weighted: 0.355 }, { angle_deg: 0, weight: 3.93, e1: 0.05, weighted: 0.1965 }] },
      { kernel: 1, angles: [{ angle_deg: 0, weight: 3.93, e1: 0.02, weighted: 0.0786 }] },
    ],
  });
  assert.equal(ev.e2, 0.36);
  assert.equal(ev.argmaxKernel, 2);
  assert.equal(ev.argmaxAngle, 45);
  assert.equal(ev.kernels.length, 2);
  assert.deepEqual(ev.kernels[0].map((r) => r.angle), [0, 5]); // sorted by angle
  assert.equal(ev.kernels[1][0].weighted, 0.0786);
});

test('evaluation detail as one flat list with a kernel index', () => {
  const ev = normEvaluation({
    e2: 1,
    argmax: { kernel: 0, angle_deg: 0 },
    per_angle: [
      { kernel: 1, angle_deg: 0, e1: 0.2, weight: 2 },
      { kernel: 0, angle_deg: 0, e1: 0.1, weight: 2 },
    ],
  });
  assert.equal(ev.kernels.length, 2);
  assert.equal(ev.kernels[0][0].e1, 0.1);
  assert.equal(ev.kernels[1][0].weighted, 0.4); // derived from weight * e1
});

test('no detail gives no kernels rather than a crash', () => {
  assert.deepEqual(normEvaluation({ e2: 0.5 }).kernels, []);
});

test('trace points as objects or as arrays in job_trace_point order', () => {
  assert.deepEqual(normTrace([[0.5, 10, 40, 0.4]]), [{ seconds: 0.5, iterations: 10, evaluations: 40, best_e2: 0.4 }]);
  assert.equal(normTrace([{ seconds: 1, best_e2: 0.3 }, { seconds: 2 }]).length, 1);
});

test('job: best pattern found under best_so_far or result.best; progress clamped', () => {
  const j = normJob({ id: 3, kind: 'optimize', state: 'done', progress: 1.2, spec: { family: 'P(4,1+,2)' }, result: { best: { e2: 0.36, mirrored: [[0, 0, 1]] } }, trace: [] });
  assert.equal(j.progress, 1);
  assert.equal(j.bestE2, 0.36);
  assert.deepEqual(j.best.pattern, { mirrored: [[0, 0, 1]] });
  assert.equal(j.family, 'P(4,1+,2)');
  const r = normJob({ id: 4, state: 'running', progress: 0.5, best_so_far: { e2: 0.4, pattern: { kernels: [[[0, 0, 1]]] } } });
  assert.deepEqual(r.best.pattern, { kernels: [[[0, 0, 1]]] });
});

test('patternOf keeps the server-expanded kernels of a tile pattern for drawing', () => {
  const p = patternOf({ family: 'P(16,16,4)', form: 'tile', tile: { size: 4 }, kernels_expanded: [[[0, 0, 1]]] });
  assert.deepEqual(p, { tile: { size: 4 }, kernels_expanded: [[[0, 0, 1]]] });
  const d = drawableOf(p);
  assert.equal(d.readOnly, true);
  assert.deepEqual(d.pattern, { kernels: [[[0, 0, 1]]] });
});

test('render answer: image URLs from ids, URLs or nested objects; stats', () => {
  assert.deepEqual(renderImages({ tiles: { pattern: 'a1', reference: '/v1/tiles/b2.png', difference: { id: 'c3' } } }), {
    pattern: '/v1/tiles/a1.png',
    reference: '/v1/tiles/b2.png',
    difference: '/v1/tiles/c3.png',
  });
  assert.deepEqual(renderImages({ pattern_tile: 7, reference_url: '/v1/tiles/8.png', difference_id: '9' }), {
    pattern: '/v1/tiles/7.png',
    reference: '/v1/tiles/8.png',
    difference: '/v1/tiles/9.png',
  });
  const s = renderStats({ stats: { rmse: 3.5, max_deviation: 120 }, penalised_histogram: [0, 1, 4], pattern_seconds: 0.01 });
  assert.equal(s.rmse, 3.5);
  assert.equal(s.maxDev, 120);
  assert.deepEqual(s.histogram, [0, 1, 4]);
  assert.equal(s.patternSeconds, 0.01);
});

test('comparison rows', () => {
  const rows = comparisonRows({ rows: [{ name: 'quincunx', samples_per_pixel: 2, e2: 0.518, rmse: 5, max_deviation: 90, render_seconds: 0.02 }] });
  assert.deepEqual(rows, [{ label: 'quincunx', spp: 2, e2: 0.518, rmse: 5, maxDev: 90, seconds: 0.02 }]);
});

test('family series label', () => {
  assert.equal(familySeries('P(4,1+,1.25)'), 'P(4,1+,n)');
  assert.equal(familySeries('P(1, 1, 4)'), 'P(1,1,n)');
  assert.equal(familySeries(''), 'other');
});

test('listFrom finds the list in an envelope or takes a bare array', () => {
  assert.deepEqual(listFrom({ presets: [1, 2] }, 'presets'), [1, 2]);
  assert.deepEqual(listFrom([3]), [3]);
  assert.deepEqual(listFrom({ items: [4] }, 'presets'), [4]);
});

test('mirrored pattern: four mirrored kernels; shared edge samples drawn once', () => {
  const p = { mirrored: [[-0.5, 1 / 6, 0.25], [0.5, -1 / 6, 0.25], [1 / 6, 0.5, 0.25], [-1 / 6, -0.5, 0.25]] };
  const k = kernelsOf(p);
  assert.equal(k.length, 4);
  assert.deepEqual(k[1][0], [0.5, 1 / 6, 0.25]);
  const dots = layoutDots(p, 0);
  assert.equal(dots.filter((d) => d.primary).length, 4);
  // No two dots at the same place: a shared sample is drawn once.
  const keys = dots.map((d) => `${d.x.toFixed(6)},${d.y.toFixed(6)}`);
  assert.equal(new Set(keys).size, keys.length);
  // The left neighbour (mirrored in x) shares the sample on the common edge x = -0.5.
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
  assert.deepEqual(q.kernels[0][1], [-0.5, -0.5, 0.5]); // a corner stays put
  moveSample(q, 0, 1, 0.1, 0.1, false);
  assert.deepEqual(q.kernels[0][1], [0.1, 0.1, 0.5]);
});

test('render answer in the renderer shape (server/tiles/tile_render.c)', () => {
  const r = {
    scene: { name: 'siemens-star', width: 64, height: 64 },
    pattern: { family: 'P(1,1+,2)', samples_per_pixel: 2, kernels: 1, kernel_size: 1, border: true, wire: { kernels: [[[0, 0, 1]]] } },
    reference: { spp: 256, seed: 1, filter: 'mitchell' },
    e2: 0.518,
    stats: { rmse: 9.5, max_dev: 140, pixels: 4096, histogram: [1, 2], penalised_histogram: [0, 0.5] },
    times: { pattern_seconds: 0.002, reference_seconds: 0.05 },
    pixels: { total: 4096, pattern_sampled: 900, supersampled: 800, reference_input_pixels_sampled: 1000, reference_samples: 5 },
    tiles: {
      pattern: { id: 'aa', url: '/v1/tiles/aa.png', width: 64, height: 64 },
      reference: { id: 'bb', url: '/v1/tiles/bb.png', width: 64, height: 64 },
      difference: { id: 'cc', url: '/v1/tiles/cc.png', width: 64, height: 64 },
    },
  };
  assert.deepEqual(renderImages(r), { pattern: '/v1/tiles/aa.png', reference: '/v1/tiles/bb.png', difference: '/v1/tiles/cc.png' });
  const s = renderStats(r);
  assert.deepEqual([s.rmse, s.maxDev, s.e2, s.patternSeconds, s.referenceSeconds, s.supersampled, s.totalPixels], [9.5, 140, 0.518, 0.002, 0.05, 800, 4096]);
  assert.deepEqual(s.histogram, [0, 0.5]);
});

test('job detail as the daemon sends it: best {elapsed, pattern:{family, form, ...}}', () => {
  const j = normJob({
    id: 1, kind: 'sleep', state: 'done', progress: 1,
    best: { elapsed: 1, pattern: { family: 'P(1,1,4)', cost_spp: 4, form: 'kernels', kernels: [[[0, 0, 1]]], kernels_expanded: [[[0, 0, 1]]] } },
    trace: [{ seconds: 5e-8, iterations: 0, evaluations: 0, best_e2: 1 }, { seconds: 0.1, iterations: 9, evaluations: 9, best_e2: 0.1 }],
  });
  assert.equal(j.family, 'P(1,1,4)');
  assert.equal(j.best.cost, 4);
  assert.deepEqual(j.best.pattern, { kernels: [[[0, 0, 1]]] });
  assert.equal(j.bestE2, 0.1); // no e2 in best: the last trace point
});

test('published E2 as a number (API) or an object by source (data file)', async () => {
  const { normPreset } = await import('../../../web/js/model.js');
  assert.equal(normPreset({ name: 'a', published_e2: 0.698 }).published, 0.698);
  assert.equal(normPreset({ name: 'b', published_e2: { 'laine-aila-table-2': 0.439 } }).published, 0.439);
  assert.equal(normPreset({ name: 'c', published_e2: null }).published, null);
});

test('a finished optimize job: the result best wins over a stale best-so-far', () => {
  const j = normJob({
    id: 1, kind: 'optimize', state: 'done', progress: 1,
    best: { pattern: { family: 'P(4,1+,2)', form: 'mirrored', mirrored: [[0.5, -0.5, 1]] }, e2: 0.94 },
    result: { best: { family: 'P(4,1+,2)', cost_spp: 2, form: 'mirrored', mirrored: [[0.5, 0.5, 1]] }, e2: 0.538, family: 'P(4,1+,2)' },
    trace: [{ seconds: 0.001, best_e2: 0.94 }, { seconds: 0.04, best_e2: 0.538 }],
  });
  assert.equal(j.bestE2, 0.538);
  assert.deepEqual(j.best.pattern, { mirrored: [[0.5, 0.5, 1]] });
  assert.equal(j.best.cost, 2);
  assert.equal(j.family, 'P(4,1+,2)');
});
