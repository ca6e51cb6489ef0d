// Axes of the trace chart (best E2 against run time): ranges and ticks for log or linear
// scales, computed here so that a narrow E2 range still gets several labelled ticks and no
// range is empty, non-finite or (on a log axis) non-positive.

import { niceTicks, logTicks } from './svg.js';

function linearRange(vals, { fromZero = false } = {}) {
  let lo = Math.min(...vals);
  let hi = Math.max(...vals);
  if (fromZero) lo = Math.min(0, lo);
  const span = hi - lo;
  const pad = span > 1e-9 * Math.max(Math.abs(lo), Math.abs(hi)) ? span * 0.06 : Math.abs(hi) * 1e-3 || 1e-3;
  return [fromZero && lo === 0 ? 0 : lo - pad, hi + pad];
}

function logRange(vals) {
  const lo = Math.min(...vals);
  const hi = Math.max(...vals);
  const ratio = hi / lo;
  const pad = ratio > 1.0001 ? Math.min(1.5, ratio ** 0.06) : 1.001;
  return [lo / pad, hi * pad];
}

/* Labels with the fewest significant digits that still tell every tick apart. */
export function tickLabels(ticks) {
  for (let p = 2; p <= 10; p++) {
    const labels = ticks.map((t) => String(+t.toPrecision(p)));
    if (new Set(labels).size === labels.length) return labels;
  }
  return ticks.map((t) => String(t));
}

const MAX_TICKS = 9;

function ticksIn(range, log) {
  // logTicks takes finer steps inside about a decade and labels an end the steps leave bare (the
  // converged tail of a trace, 0.159..0.2).
  let t = log ? logTicks(range[0], range[1]) : niceTicks(range[0], range[1], 6);
  // A range of a few per cent: linear steps, as many as on a linear axis.
  if (log && t.filter((v) => v >= range[0] && v <= range[1]).length < 3) t = niceTicks(range[0], range[1], 6);
  t = t.filter((v) => v >= range[0] && v <= range[1]);
  if (t.length <= MAX_TICKS || !log) return t;
  // Many decades (a trace from microseconds to seconds): powers of ten only, then every k-th.
  const decades = t.filter((v) => Math.abs(Math.log10(v) - Math.round(Math.log10(v))) < 1e-9);
  const k = Math.ceil(decades.length / MAX_TICKS);
  return decades.filter((_, i) => i % k === (decades.length - 1) % k);
}

/* xs (seconds) and ys (best E2) of equal length; mode "log" or "linear". On log axes the points
 * at t <= 0 cannot be drawn and are left out. Returns {xs, ys, x: {range, ticks}, y: {...}}. */
export function traceAxes(xs, ys, mode) {
  const log = mode === 'log';
  const keep = xs.map((x, i) => Number.isFinite(x) && Number.isFinite(ys[i]) && (!log || (x > 0 && ys[i] > 0)));
  const px = xs.filter((_, i) => keep[i]);
  const py = ys.filter((_, i) => keep[i]);
  if (!px.length) {
    const x = log ? [1e-3, 1] : [0, 1];
    const y = log ? [0.1, 1] : [0, 1];
    return { xs: [], ys: [], x: { range: x, ticks: ticksIn(x, log) }, y: { range: y, ticks: ticksIn(y, log) } };
  }
  const x = log ? logRange(px) : linearRange(px, { fromZero: true });
  const y = log ? logRange(py) : linearRange(py);
  return { xs: px, ys: py, x: { range: x, ticks: ticksIn(x, log) }, y: { range: y, ticks: ticksIn(y, log) } };
}

/* An axis over a given range (a zoom): the range itself and ticks inside it. */
export function axisFor(range, mode) {
  const log = mode === 'log';
  const r = [Math.min(...range), Math.max(...range)];
  if (log && r[0] <= 0) r[0] = r[1] / 1e3;
  return { range: r, ticks: ticksIn(r, log) };
}
