// Axis ticks (web/js/svg.js): finite, ordered, and no endless loop on degenerate ranges.

import test from 'node:test';
import assert from 'node:assert/strict';
import { niceTicks, logTicks } from '../../../web/js/svg.js';

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
