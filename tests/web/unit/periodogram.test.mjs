// The periodogram image's colour scale (web/js/periodogram-image.js): the decades it spans, the
// colour a power maps to, and the cell size per radius, without a browser.

import test from 'node:test';
import assert from 'node:assert/strict';
import { colourScale, levelOf, colourOf, periodogramCell, powerOfTen, LUT, DC_COLOUR, MISSING_COLOUR, DECADES } from '../../../web/js/periodogram-image.js';

/* A (2r+1)^2 power array with P(0) = n and the given off-DC values at (kx, ky). */
function spectrum(r, n, values = {}) {
  const p = Array.from({ length: 2 * r + 1 }, () => new Array(2 * r + 1).fill(0));
  p[r][r] = n;
  for (const [k, v] of Object.entries(values)) {
    const [kx, ky] = k.split(',').map(Number);
    p[ky + r][kx + r] = v;
  }
  return p;
}

test('the scale leaves DC out and tops at the decade above the largest other power', () => {
  // An 8x8 grid: P = 64 at the multiples of 8 and at DC; the top decade is 10^2.
  const s = colourScale(spectrum(8, 64, { '8,0': 64, '0,8': 64, '1,0': 1e-30 }));
  assert.equal(s.hiExp, 2);
  assert.equal(s.loExp, 2 - DECADES);
  assert.equal(s.maxOffDc, 64);
  // DC alone would have set 10^4 were it counted: a set whose only large power is DC.
  assert.equal(colourScale(spectrum(4, 4096, { '1,1': 0.5 })).hiExp, 1);
  // An exact power of ten is its own top; the top is never under 10 (P = 1 stays inside).
  assert.equal(colourScale(spectrum(4, 100, { '2,0': 100 })).hiExp, 2);
  assert.equal(colourScale(spectrum(4, 2, {})).hiExp, 1);
});

test('levels: zero and anything under the bottom decade are the darkest colour, the top the brightest, monotone between', () => {
  const s = { loExp: -3, hiExp: 1 };
  assert.equal(levelOf(0, s), 0);
  assert.equal(levelOf(1e-30, s), 0);
  assert.equal(levelOf(1e-3, s), 0);
  assert.equal(levelOf(10, s), 255);
  assert.equal(levelOf(1e5, s), 255);
  assert.equal(levelOf(1, s), Math.round(0.75 * 255));
  let last = -1;
  for (let e = -3; e <= 1; e += 0.01) {
    const l = levelOf(10 ** e, s);
    assert.ok(l >= last, `level falls at 10^${e}`);
    last = l;
  }
  assert.deepEqual(colourOf(64, s, { dc: true }), DC_COLOUR);
  assert.deepEqual(colourOf(null, s), MISSING_COLOUR);
  assert.deepEqual(colourOf(0, s), LUT[0]);
});

test('the colour map gets lighter from bottom to top (readable in greyscale)', () => {
  const luma = ([r, g, b]) => 0.2126 * r + 0.7152 * g + 0.0722 * b;
  for (let i = 1; i < LUT.length; i++) assert.ok(luma(LUT[i]) >= luma(LUT[i - 1]) - 0.5, `luma falls at ${i}`);
  assert.ok(luma(LUT[255]) - luma(LUT[0]) > 150);
});

test('cells: a whole number of pixels per frequency, the image within 320 pixels', () => {
  assert.equal(periodogramCell(32), 4);
  assert.equal(periodogramCell(8), 18);
  assert.equal(periodogramCell(128), 1);
  for (let r = 1; r <= 128; r++) {
    const c = periodogramCell(r);
    assert.ok(Number.isInteger(c) && c >= 1 && (2 * r + 1) * c <= Math.max(320, 2 * r + 1), `radius ${r}: cell ${c}`);
  }
});

test('decade labels', () => {
  assert.deepEqual([-3, -1, 0, 1, 2, 12].map(powerOfTen), ['10⁻³', '10⁻¹', '1', '10', '10²', '10¹²']);
});
