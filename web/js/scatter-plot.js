// Scatter/line plot in SVG with linear or log axes whose points are links (keyboard focusable,
// with a title), one marker shape per series so series read without colour.

import { el, text, clear, marker, MARKERS, COLOURS, DASHES, niceTicks, logTicks, enlargeSmallText } from './svg.js';
import { addPlotTools } from './plot-tools.js';

/* tools: the zoom/reset and PNG/SVG/CSV toolbar under the plot (plot-tools.js). */
export function drawScatter(container, { series, xLabel, yLabel, xLog = false, yLog = false, width = 640, height = 360, lines = false, title = '', labels = false, tools = true }) {
  clear(container);
  // Drawn at the width it is shown at (a 560-unit plot in a 290 px column had its text scaled
  // up after the labels were placed, and they overprinted): one viewBox unit is one pixel.
  const fitW = container.clientWidth;
  if (fitW > 0 && fitW < width) {
    height = Math.round(Math.max(220, (height * fitW) / width));
    width = Math.max(240, fitW);
  }
  const m = { l: 56, r: 16, t: title ? 30 : 12, b: 44 };
  const svg = el('svg', { viewBox: `0 0 ${width} ${height}`, class: 'scatter-svg', role: 'group', 'aria-label': title || `${yLabel} against ${xLabel}` }, container);
  const all = series.flatMap((s) => s.points).filter((p) => Number.isFinite(p.x) && Number.isFinite(p.y) && (!xLog || p.x > 0) && (!yLog || p.y > 0));
  if (title) text(svg, 6, 16, title, { class: 'plot-title' });
  if (!all.length) {
    text(svg, width / 2, height / 2, 'no data yet', { 'text-anchor': 'middle', class: 'plot-empty' });
    return svg;
  }
  const range = (vals, log) => {
    let lo = Math.min(...vals);
    let hi = Math.max(...vals);
    if (log) {
      lo /= 1.25;
      hi *= 1.25;
    } else {
      // Values equal up to rounding count as one value (the padding of a few ulps gives no axis).
      const span = hi - lo > 1e-9 * Math.max(Math.abs(lo), Math.abs(hi)) ? hi - lo : 0;
      const pad = span * 0.08 || Math.abs(hi) * 0.1 || 1;
      lo -= pad;
      hi += pad;
    }
    return [lo, hi];
  };
  const [x0, x1] = range(all.map((p) => p.x), xLog);
  const [y0, y1] = range(all.map((p) => p.y), yLog);
  const f = (log) => (log ? Math.log10 : (v) => v);
  const fx = f(xLog);
  const fy = f(yLog);
  const X = (v) => m.l + ((fx(v) - fx(x0)) / (fx(x1) - fx(x0))) * (width - m.l - m.r);
  const Y = (v) => height - m.b - ((fy(v) - fy(y0)) / (fy(y1) - fy(y0))) * (height - m.t - m.b);
  // At least four labelled ticks on a linear axis (1-2-5 steps over 0.13..1.3 gave 0.5 and 1).
  const linTicks = (lo, hi, n) => {
    const t = niceTicks(lo, hi, n);
    return t.length >= 4 ? t : niceTicks(lo, hi, 2 * n);
  };
  // A log axis over many decades (a trace from 1e-7 s): powers of ten, then every k-th, so
  // that labels do not overprint.
  const logAxis = (lo, hi, max) => {
    const t = logTicks(lo, hi);
    if (t.length <= max) return t;
    const dec = t.filter((v) => Math.abs(Math.log10(v) - Math.round(Math.log10(v))) < 1e-9);
    const k = Math.ceil(dec.length / max);
    return dec.filter((_, i) => i % k === (dec.length - 1) % k);
  };
  const xt = xLog ? logAxis(x0, x1, Math.max(3, Math.floor((width - m.l - m.r) / 60))) : linTicks(x0, x1, 6);
  const yt = yLog ? logAxis(y0, y1, Math.max(3, Math.floor((height - m.t - m.b) / 28))) : linTicks(y0, y1, 5);
  for (const t of xt) {
    el('line', { x1: X(t), x2: X(t), y1: m.t, y2: height - m.b, class: 'grid' }, svg);
    text(svg, X(t), height - m.b + 16, fmtTick(t), { 'text-anchor': 'middle', class: 'tick' });
  }
  for (const t of yt) {
    el('line', { x1: m.l, x2: width - m.r, y1: Y(t), y2: Y(t), class: 'grid' }, svg);
    text(svg, m.l - 6, Y(t) + 4, fmtTick(t), { 'text-anchor': 'end', class: 'tick' });
  }
  el('rect', { x: m.l, y: m.t, width: width - m.l - m.r, height: height - m.t - m.b, class: 'frame' }, svg);
  text(svg, (m.l + width - m.r) / 2, height - 8, xLabel + (xLog ? ' (log scale)' : ' (linear)'), { 'text-anchor': 'middle', class: 'axis-label' });
  const yl = text(svg, 14, (m.t + height - m.b) / 2, yLabel + (yLog ? ' (log scale)' : ' (linear)'), { 'text-anchor': 'middle', class: 'axis-label' });
  yl.setAttribute('transform', `rotate(-90 14 ${(m.t + height - m.b) / 2})`);
  // Point labels go right, left, above or below their point, whichever covers no label placed
  // before; none fits: the label is left out (the point's tooltip names it). Boxes in viewBox
  // units for 12 px text, ~0.6 em a character.
  const placed = [];
  const free = (b) => !placed.some((p) => b.x0 < p.x1 && p.x0 < b.x1 && b.y0 < p.y1 && p.y0 < b.y1);
  const placeLabel = (px, py, label) => {
    const w = 0.62 * 12 * label.length;
    const right = px < m.l + 0.75 * (width - m.l - m.r);
    const spots = [
      right ? { x: px + 9, y: py + 4, anchor: 'start', x0: px + 8, x1: px + 10 + w } : { x: px - 9, y: py + 4, anchor: 'end', x0: px - 10 - w, x1: px - 8 },
      { x: px, y: py - 10, anchor: 'middle', x0: px - w / 2 - 1, x1: px + w / 2 + 1, above: true },
      { x: px, y: py + 20, anchor: 'middle', x0: px - w / 2 - 1, x1: px + w / 2 + 1, below: true },
      right ? { x: px - 9, y: py + 4, anchor: 'end', x0: px - 10 - w, x1: px - 8 } : { x: px + 9, y: py + 4, anchor: 'start', x0: px + 8, x1: px + 10 + w },
    ];
    for (const sp of spots) {
      const box = { x0: sp.x0, x1: sp.x1, y0: sp.y - 11, y1: sp.y + 3 };
      // Inside the frame: a label never covers a tick, an axis label or the title.
      if (box.x0 < m.l || box.x1 > width - m.r || box.y0 < m.t || box.y1 > height - m.b || !free(box)) continue;
      placed.push(box);
      text(svg, sp.x, sp.y, label, { class: 'point-label', 'text-anchor': sp.anchor });
      return;
    }
  };
  series.forEach((s, k) => {
    const colour = COLOURS[k % COLOURS.length];
    const shape = MARKERS[k % MARKERS.length];
    const pts = s.points.filter((p) => all.includes(p));
    if (s.envelope && pts.length > 1) {
      // The best (lowest) y at each x, joined: the family's frontier.
      const best = new Map();
      for (const p of pts) if (!best.has(p.x) || p.y < best.get(p.x)) best.set(p.x, p.y);
      const env = [...best].sort((a, b) => a[0] - b[0]);
      if (env.length > 1)
        el('path', { d: env.map(([x, y], i) => `${i ? 'L' : 'M'}${X(x).toFixed(1)},${Y(y).toFixed(1)}`).join(''), class: 'series-line', stroke: colour, 'stroke-dasharray': DASHES[k % DASHES.length] || null }, svg);
    }
    if (s.step && pts.length > 1) {
      // Best so far: constant until the next improvement, a step after each point.
      const sorted = [...pts].sort((a, b) => a.x - b.x);
      const d = sorted.map((p, i) => (i ? `H${X(p.x).toFixed(1)}V${Y(p.y).toFixed(1)}` : `M${X(p.x).toFixed(1)},${Y(p.y).toFixed(1)}`)).join('');
      el('path', { d, class: 'series-line', stroke: colour, 'stroke-dasharray': DASHES[k % DASHES.length] || null, 'data-series': s.label }, svg);
    } else if ((lines || s.line) && pts.length > 1) {
      const sorted = [...pts].sort((a, b) => a.x - b.x);
      el('path', { d: sorted.map((p, i) => `${i ? 'L' : 'M'}${X(p.x).toFixed(1)},${Y(p.y).toFixed(1)}`).join(''), class: 'series-line', stroke: colour, 'stroke-dasharray': DASHES[k % DASHES.length] || null }, svg);
    }
    if (s.reference) {
      // Reference marks (published values): a black bar across the point, titled with its
      // source; no marker shape, so they read apart from measured points.
      for (const p of pts) {
        const g = el('g', { class: 'ref-mark' }, svg);
        el('path', { d: `M${(X(p.x) - 9).toFixed(1)},${Y(p.y).toFixed(1)}h18M${X(p.x).toFixed(1)},${(Y(p.y) - 5).toFixed(1)}v10`, class: 'ref-mark-shape' }, g);
        el('title', {}, g).textContent = p.title || `${s.label}: ${p.x}, ${p.y}`;
      }
      return;
    }
    for (const p of pts) {
      const holder = p.href ? el('a', { href: p.href, class: 'point-link' }, svg) : el('g', { class: 'point' }, svg);
      const t = el('title', {}, holder);
      t.textContent = p.title || `${s.label}: ${p.x}, ${p.y}`;
      if (p.href) holder.setAttribute('aria-label', t.textContent);
      marker(holder, shape, X(p.x), Y(p.y), 6, { fill: p.hollow ? 'white' : colour, stroke: colour, 'stroke-width': 1.5, class: 'point-marker' });
      if (labels) placeLabel(X(p.x), Y(p.y), s.label);
    }
  });
  enlargeSmallText(svg);
  if (tools)
    addPlotTools(container, svg, {
      title: title || `${yLabel} against ${xLabel}`,
      csv: () => ({
        header: ['series', fileField(xLabel), fileField(yLabel), 'title'],
        rows: series.flatMap((s) => s.points.map((p) => [s.label, p.x, p.y, p.title || ''])),
      }),
    });
  return svg;
}

/* A CSV column name from an axis label: ASCII, lower case, words joined by _. */
function fileField(label) {
  const s = String(label).normalize('NFKD').replace(/[^\x20-\x7e]/g, '').toLowerCase().replace(/[^a-z0-9]+/g, '_').replace(/^_+|_+$/g, '');
  return s || 'value';
}

export function scatterLegend(container, labels) {
  clear(container);
  labels.forEach((label, k) => {
    const item = document.createElement('span');
    item.className = 'legend-item';
    const svg = el('svg', { width: 16, height: 16, 'aria-hidden': 'true' }, item);
    marker(svg, MARKERS[k % MARKERS.length], 8, 8, 5.5, { fill: COLOURS[k % COLOURS.length], stroke: COLOURS[k % COLOURS.length] });
    item.append(` ${label}`);
    container.appendChild(item);
  });
}

function fmtTick(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-4) return v.toExponential(0);
  return String(+v.toPrecision(3));
}
