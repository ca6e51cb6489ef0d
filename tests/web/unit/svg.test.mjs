// Axis ticks (web/js/svg.js): finite, ordered, and no endless loop on degenerate ranges.

import test from 'node:test';
import assert from 'node:assert/strict';
import { niceTicks, logTicks } from '../../../web/js/svg.js';
import { traceAxes } from '../../../web/js/trace-axes.js';
import { ringLabel } from '../../../web/js/polar-plot.js';

test('nice ticks of an ordinary range', () => {
  assert.deepEqual(niceTicks(0, 1, 5), [0, 0.2, 0.4, 0.6, 0.8, 1]);
});

test('a range of one ulp (E2 values equal up to rounding) gives one tick', () => {
  const lo = 0.3591;
  const hi = lo + Number.EPSILON * lo;
  assert.ok(hi > lo);
  assert.deepEqual(niceTicks(lo, hi, 5), [lo]);
  assert.deepEqual(niceTicks(1e6, 1e6 + 1e-7, 5), [1e6]);
});

test('log ticks inside less than a decade fall back to linear ticks, all positive', () => {
  const t = logTicks(0.3591 / 1.25, 0.3591 * 1.25);
  assert.ok(t.length >= 2 && t.length < 20, String(t));
  assert.ok(t.every((v) => v > 0));
  const u = logTicks(0.3591 / 1.25, (0.3591 + 1e-17) * 1.25);
  assert.ok(u.length < 20);
});

test('logTicks labels a range of about a decade with at least four ticks (issue 34)', () => {
  // Families' E2 axis: from 0.15 to 0.9 the 1-2-5 steps gave 0.2 and 0.5 only.
  const t = logTicks(0.15, 0.9);
  assert.ok(t.length >= 4, `ticks ${t}`);
  assert.ok(t.every((v) => v >= 0.15 * 0.999 && v <= 0.9 * 1.001), `ticks ${t}`);
  // A converged trace tail between 0.159 and 0.2 gets ticks inside it.
  const tail = logTicks(0.159, 0.45);
  assert.ok(tail.some((v) => v >= 0.159 && v < 0.2), `no tick in the tail: ${tail}`);
});

test('a trace converging to 0.159 has a y tick below 0.2 on the log axis (issue 34)', () => {
  const a = traceAxes([0.01, 0.1, 1, 6], [0.45, 0.25, 0.17, 0.159], 'log');
  assert.ok(a.y.ticks.some((v) => v >= a.y.range[0] && v < 0.2), `y ticks ${a.y.ticks} in ${a.y.range}`);
});

test('polar ring labels are plain numbers: 200, not 2.0e+2 (issue 34 defect 7)', () => {
  assert.equal(ringLabel(200), '200');
  assert.equal(ringLabel(0.05), '0.05');
  assert.equal(ringLabel(0.30000000000000004), '0.3');
  assert.equal(ringLabel(1500), '1500');
  assert.equal(ringLabel(2e-5), '2.0e-5');
});
