// Polar plot of a per-angle error, one closed curve per kernel (E1 is even in θ+180°, so the
// computed half-turn is drawn twice). Kernels differ by dash pattern as well as colour; the
// maximum is marked with a ring and a text label; optional marks are dots at given angles.

import { el, text, clear, COLOURS, DASHES, niceTicks, enlargeSmallText } from './svg.js';
import { addPlotTools } from './plot-tools.js';

const SIZE = 360;
const PAD = 40;

/* only: the index of the one series to draw (the kernel picker), or null for all; its colour and
 * dash stay those of its index, and the radius scale fits what is drawn. */
export function drawPolar(container, { title, series, argmax, valueLabel, marks = [], only = null, tools = true }) {
  clear(container);
  const svg = el('svg', { viewBox: `0 0 ${SIZE} ${SIZE + 24}`, class: 'polar-svg', role: 'img' }, container);
  const shown = (k) => only == null || k === only;
  if (only != null) svg.dataset.kernel = String(only);
  if (argmax && argmax.kernel != null && !shown(argmax.kernel)) argmax = null;
  const rMaxData = Math.max(1e-9, ...series.filter((_, k) => shown(k)).flatMap((s) => s.points.map((p) => p.r ?? 0)));
  const ticks = niceTicks(0, rMaxData, 4).filter((t) => t > 0);
  const rTop = Math.max(rMaxData, ticks[ticks.length - 1] || rMaxData);
  const R = SIZE / 2 - PAD;
  const cx = SIZE / 2;
  const cy = SIZE / 2 + 6;
  const toXY = (deg, r) => {
    const a = (deg * Math.PI) / 180;
    const rr = (r / rTop) * R;
    return [cx + rr * Math.cos(a), cy - rr * Math.sin(a)];
  };
  svg.setAttribute('aria-label', `${title}; maximum ${argmax ? `${argmax.value.toFixed(4)} at ${argmax.angle}°${argmax.kernel != null ? ` in kernel ${argmax.kernel}` : ''}` : 'n/a'}`);
  text(svg, 6, 16, title, { class: 'plot-title' });
  for (const t of ticks) el('circle', { cx, cy, r: (t / rTop) * R, class: 'polar-ring' }, svg);
  for (let d = 0; d < 360; d += 45) {
    const [x, y] = toXY(d, rTop);
    el('line', { x1: cx, y1: cy, x2: x, y2: y, class: 'polar-spoke' }, svg);
    const [tx, ty] = toXY(d, rTop * 1.1);
    text(svg, tx, ty + 4, `${d}°`, { class: 'polar-tick', 'text-anchor': 'middle' });
  }
  series.forEach((s, k) => {
    if (!shown(k)) return;
    const pts = s.points.filter((p) => p.r != null);
    if (!pts.length) return;
    const full = [...pts, ...pts.map((p) => ({ angle: p.angle + 180, r: p.r }))];
    const d = full.map((p, i) => `${i ? 'L' : 'M'}${toXY(p.angle, p.r).map((v) => v.toFixed(1)).join(',')}`).join('') + 'Z';
    el('path', {
      d,
      class: 'polar-curve',
      stroke: COLOURS[k % COLOURS.length],
      'stroke-dasharray': DASHES[k % DASHES.length] || null,
      'data-kernel': k,
    }, svg);
  });
  // Ring labels between the 45° and 90° spokes, over a white halo (drawn after the spokes and
  // curves, so none crosses them), as plain numbers: 200, not 2.0e+2.
  for (const t of ticks) {
    const [lx, ly] = toXY(67.5, t);
    text(svg, lx + 3, ly - 2, ringLabel(t), { class: 'polar-tick polar-ring-label' });
  }
  // Marked angles (the Tiles view's costliest scene angles): a dot on each half-turn, titled.
  for (const m of marks) {
    for (const a of [m.angle, m.angle + 180]) {
      const [x, y] = toXY(a, m.r);
      const dot = el('circle', { cx: x, cy: y, r: 4, class: 'polar-mark', 'data-angle': m.angle }, svg);
      if (m.label) el('title', {}, dot).textContent = m.label;
    }
  }
  if (argmax && argmax.value != null) {
    const [x, y] = toXY(argmax.angle, argmax.value);
    el('circle', { cx: x, cy: y, r: 7, class: 'polar-argmax' }, svg);
    el('circle', { cx: x, cy: y, r: 2.5, class: 'polar-argmax-dot' }, svg);
    const label = `max ${argmax.value.toFixed(3)} @ ${argmax.angle}°${series.length > 1 ? `, kernel ${argmax.kernel}` : ''}`;
    text(svg, 6, SIZE + 18, label, { class: 'polar-argmax-label' });
  }
  if (valueLabel) text(svg, SIZE - 6, 16, valueLabel, { class: 'polar-tick', 'text-anchor': 'end' });
  enlargeSmallText(svg);
  if (tools)
    addPlotTools(container, svg, {
      title,
      // Each drawn series' half-turn as computed (E1 is even in θ+180°).
      csv: () => ({
        header: ['kernel', 'angle_deg', 'value'],
        rows: series.flatMap((s, k) => (shown(k) ? s.points.filter((p) => p.r != null).map((p) => [k, p.angle, p.r]) : [])),
      }),
    });
  return svg;
}

/* A legend of dash styles shared by both polar plots. */
export function polarLegend(container, count) {
  clear(container);
  for (let k = 0; k < count; k++) {
    const item = document.createElement('span');
    item.className = 'legend-item';
    const svg = el('svg', { width: 36, height: 10, 'aria-hidden': 'true' }, item);
    el('line', { x1: 0, y1: 5, x2: 36, y2: 5, stroke: COLOURS[k % COLOURS.length], 'stroke-width': 2.5, 'stroke-dasharray': DASHES[k % DASHES.length] || null }, svg);
    item.append(` kernel ${k}`);
    container.appendChild(item);
  }
}

/* A menu picking the kernel the polar plots draw: "all kernels" or one of them (16 curves in one
 * plot cannot be read apart). Shown only for more than one kernel; keeps the choice while the
 * count stays. onPick(k or null). Returns the current choice. */
export function polarKernelPicker(select, count, onPick) {
  const before = select.value;
  if (select.options.length !== count + 1) {
    select.replaceChildren();
    const all = document.createElement('option');
    all.value = 'all';
    all.textContent = `all ${count} kernels`;
    select.append(all);
    for (let k = 0; k < count; k++) {
      const o = document.createElement('option');
      o.value = String(k);
      o.textContent = `kernel ${k}`;
      select.append(o);
    }
    select.value = [...select.options].some((o) => o.value === before) ? before : 'all';
  }
  select.closest('label, .kernel-pick')?.toggleAttribute('hidden', count < 2);
  select.onchange = () => onPick(select.value === 'all' ? null : Number(select.value));
  return select.value === 'all' ? null : Number(select.value);
}

/* A ring's value as a plain number with at most 3 significant digits (200, 0.05, 1.5e-5 only
 * below 1e-4). */
export function ringLabel(v) {
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a < 1e-4 || a >= 1e6) return v.toExponential(1);
  return String(+v.toPrecision(3));
}
