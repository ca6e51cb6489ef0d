// A small SVG line chart for sampled curves (the radial spectrum, the anisotropy, the pair
// correlation function): linear axes, one path per series (null values break the line),
// dashed horizontal reference lines and dotted vertical markers. The only text inside is the
// title, the tick labels and the axis labels, placed so they cannot overprint; what the lines
// mean is said in the legend under the plot.

import { el, text, clear, COLOURS, DASHES, niceTicks, enlargeSmallText } from './svg.js';

function fmtTick(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  const s = a >= 1e5 || a < 1e-3 ? v.toExponential(0) : String(+v.toPrecision(3));
  return s.replace('-', '−');
}

function range(vals, { include = [], pad = 0.05 } = {}) {
  const all = [...vals, ...include].filter(Number.isFinite);
  if (!all.length) return [0, 1];
  let lo = Math.min(...all);
  let hi = Math.max(...all);
  if (!(hi - lo > 1e-12 * Math.max(1, Math.abs(hi)))) {
    lo -= 0.5;
    hi += 0.5;
  }
  const p = (hi - lo) * pad;
  return [lo - (lo < 0 || lo - p >= 0 ? p : 0), hi + p];
}

/* series: [{label, xs, ys}]; refLines: [{y}]; markers: [{x}]. Returns the svg. */
export function drawLinePlot(container, { title, xLabel, yLabel, series, refLines = [], markers = [], width = 420, height = 250, yInclude = [], xRange = null }) {
  clear(container);
  const m = { l: 56, r: 14, t: 28, b: 44 };
  const svg = el('svg', { viewBox: `0 0 ${width} ${height}`, class: 'line-svg', role: 'img', 'aria-label': title }, container);
  text(svg, 4, 17, title, { class: 'plot-title' });
  const xs = series.flatMap((s) => s.xs);
  const ys = series.flatMap((s) => s.ys.filter((v, i) => v != null && Number.isFinite(s.xs[i])));
  const [x0, x1] = xRange || range(xs, { pad: 0 });
  const [y0, y1] = range(ys, { include: [...yInclude, ...refLines.map((l) => l.y)] });
  const pw = width - m.l - m.r;
  const ph = height - m.t - m.b;
  const X = (v) => m.l + ((v - x0) / (x1 - x0 || 1)) * pw;
  const Y = (v) => m.t + ph - ((v - y0) / (y1 - y0 || 1)) * ph;
  for (const t of niceTicks(x0, x1, 5).filter((t) => t >= x0 && t <= x1)) {
    el('line', { x1: X(t), x2: X(t), y1: m.t, y2: m.t + ph, class: 'grid' }, svg);
    text(svg, X(t), m.t + ph + 16, fmtTick(t), { 'text-anchor': 'middle', class: 'tick' });
  }
  for (const t of niceTicks(y0, y1, 4).filter((t) => t >= y0 && t <= y1)) {
    el('line', { x1: m.l, x2: m.l + pw, y1: Y(t), y2: Y(t), class: 'grid' }, svg);
    text(svg, m.l - 6, Y(t) + 4, fmtTick(t), { 'text-anchor': 'end', class: 'tick' });
  }
  el('rect', { x: m.l, y: m.t, width: pw, height: ph, class: 'frame' }, svg);
  for (const l of refLines) el('line', { x1: m.l, x2: m.l + pw, y1: Y(l.y), y2: Y(l.y), class: 'ref-line' }, svg);
  for (const k of markers) if (k.x >= x0 && k.x <= x1) el('line', { x1: X(k.x), x2: X(k.x), y1: m.t, y2: m.t + ph, class: `marker-line ${k.className || ''}` }, svg);
  series.forEach((s, k) => {
    let d = '';
    let pen = false;
    s.ys.forEach((v, i) => {
      if (v == null || !Number.isFinite(v) || !Number.isFinite(s.xs[i])) {
        pen = false;
        return;
      }
      d += `${pen ? 'L' : 'M'}${X(s.xs[i]).toFixed(2)},${Y(v).toFixed(2)}`;
      pen = true;
    });
    // A lone point between gaps has no segment: a dot shows it.
    s.ys.forEach((v, i) => {
      const lone = v != null && Number.isFinite(v) && (i === 0 || s.ys[i - 1] == null) && (i === s.ys.length - 1 || s.ys[i + 1] == null);
      if (lone) el('circle', { cx: X(s.xs[i]), cy: Y(v), r: 2.5, fill: COLOURS[k % COLOURS.length] }, svg);
    });
    if (d) el('path', { d, class: 'series-line', stroke: COLOURS[k % COLOURS.length], 'stroke-dasharray': DASHES[k % DASHES.length] || null, 'data-series': s.label }, svg);
  });
  text(svg, m.l + pw / 2, height - 8, xLabel, { 'text-anchor': 'middle', class: 'axis-label' });
  const yl = text(svg, 14, m.t + ph / 2, yLabel, { 'text-anchor': 'middle', class: 'axis-label' });
  yl.setAttribute('transform', `rotate(-90 14 ${m.t + ph / 2})`);
  enlargeSmallText(svg);
  return svg;
}
