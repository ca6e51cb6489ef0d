// Small helpers for building SVG by hand (pattern drawings and the plots that need focusable,
// labelled points, which canvas charts cannot give).

export const SVG_NS = 'http://www.w3.org/2000/svg';

export function el(name, attrs = {}, parent = null) {
  const e = document.createElementNS(SVG_NS, name);
  for (const [k, v] of Object.entries(attrs)) if (v != null) e.setAttribute(k, String(v));
  if (parent) parent.appendChild(e);
  return e;
}

export function text(parent, x, y, str, attrs = {}) {
  const t = el('text', { x, y, ...attrs }, parent);
  t.textContent = str;
  return t;
}

/* Marker shapes, so series differ by shape as well as colour. */
export const MARKERS = ['circle', 'square', 'triangle', 'diamond', 'cross', 'triangle-down', 'star', 'plus'];
export const COLOURS = ['#1f5fbf', '#c2410c', '#15803d', '#7e22ce', '#a16207', '#be123c', '#0f766e', '#4b5563'];
export const DASHES = ['', '6 3', '2 3', '8 3 2 3', '12 4', '1 2'];

export function marker(parent, shape, cx, cy, r, attrs = {}) {
  const pts = (list) => list.map(([x, y]) => `${cx + x * r},${cy + y * r}`).join(' ');
  switch (shape) {
    case 'square':
      return el('rect', { x: cx - r * 0.85, y: cy - r * 0.85, width: r * 1.7, height: r * 1.7, ...attrs }, parent);
    case 'triangle':
      return el('polygon', { points: pts([[0, -1.15], [1, 0.75], [-1, 0.75]]), ...attrs }, parent);
    case 'triangle-down':
      return el('polygon', { points: pts([[0, 1.15], [1, -0.75], [-1, -0.75]]), ...attrs }, parent);
    case 'diamond':
      return el('polygon', { points: pts([[0, -1.2], [1.2, 0], [0, 1.2], [-1.2, 0]]), ...attrs }, parent);
    case 'cross':
      return el('polygon', {
        points: pts([[-1, -0.6], [-0.6, -1], [0, -0.4], [0.6, -1], [1, -0.6], [0.4, 0], [1, 0.6], [0.6, 1], [0, 0.4], [-0.6, 1], [-1, 0.6], [-0.4, 0]]),
        ...attrs,
      }, parent);
    case 'plus':
      return el('polygon', {
        points: pts([[-0.35, -1], [0.35, -1], [0.35, -0.35], [1, -0.35], [1, 0.35], [0.35, 0.35], [0.35, 1], [-0.35, 1], [-0.35, 0.35], [-1, 0.35], [-1, -0.35], [-0.35, -0.35]]),
        ...attrs,
      }, parent);
    case 'star': {
      const p = [];
      for (let i = 0; i < 10; i++) {
        const a = -Math.PI / 2 + (i * Math.PI) / 5;
        const rr = i % 2 ? 0.5 : 1.2;
        p.push([Math.cos(a) * rr, Math.sin(a) * rr]);
      }
      return el('polygon', { points: pts(p), ...attrs }, parent);
    }
    default:
      return el('circle', { cx, cy, r, ...attrs }, parent);
  }
}

/* "Nice" tick values for a linear range. */
export function niceTicks(lo, hi, count = 5) {
  // A range of a few ulps (two E2 values that differ only by rounding) has steps too small to
  // move v: one tick, not an endless loop.
  if (!(hi > lo) || hi - lo <= 1e-12 * Math.max(Math.abs(lo), Math.abs(hi))) return [lo];
  const raw = (hi - lo) / count;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
  const out = [];
  for (let v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9 && out.length <= 4 * count + 4; v += step)
    out.push(+v.toPrecision(12));
  return out;
}

export function logTicks(lo, hi) {
  const within = (mantissas) => {
    const out = [];
    for (let e = Math.floor(Math.log10(lo)); e <= Math.ceil(Math.log10(hi)); e++)
      for (const m of mantissas) {
        const v = +(m * 10 ** e).toPrecision(12);
        if (v >= lo * 0.999 && v <= hi * 1.001) out.push(v);
      }
    return out;
  };
  let out = within([1, 2, 5]);
  // About a decade (E2 from 0.15 to 0.9): 1-2-5 leaves two or three ticks; finer steps label it.
  if (out.length < 4) out = within([1, 1.5, 2, 3, 4, 5, 6, 8]);
  // Ends with no tick over more than a sixth of the axis (a converged tail at 0.159..0.2) get one
  // at the end's value to two digits, inside the range.
  const span = Math.log10(hi) - Math.log10(lo);
  const twoDigits = (v, round) => {
    const e = 10 ** (Math.floor(Math.log10(v)) - 1);
    return +(round(v / e) * e).toPrecision(2);
  };
  if (out.length && Math.log10(out[0]) - Math.log10(lo) > span / 6) {
    const v = twoDigits(lo, Math.ceil);
    if (Math.log10(out[0]) - Math.log10(v) > span / 12) out.unshift(v);
  }
  if (out.length && Math.log10(hi) - Math.log10(out[out.length - 1]) > span / 6) {
    const v = twoDigits(hi, Math.floor);
    if (Math.log10(v) - Math.log10(out[out.length - 1]) > span / 12) out.push(v);
  }
  // Less than a decade: 1-2-5 steps give too few ticks, use linear nice ticks inside the range.
  if (out.length < 3) return niceTicks(lo, hi, 4).filter((v) => v > 0);
  return out;
}

export function clear(node) {
  while (node.firstChild) node.removeChild(node.firstChild);
}

/* How many screen pixels one viewBox unit of svg takes (1 while it is not laid out). */
export function screenScale(svg) {
  const vb = svg.viewBox && svg.viewBox.baseVal;
  const r = svg.getBoundingClientRect();
  if (!vb || !vb.width || !r.width) return 1;
  return Math.min(r.width / vb.width, r.height / vb.height);
}

/* A plot drawn smaller than its viewBox shrinks its text with it: text that would be under
 * minPx on screen is set larger, so labels stay readable (issue 34: 7 px labels). */
export function enlargeSmallText(svg, minPx = 11) {
  const scale = screenScale(svg);
  if (scale >= 1) return;
  for (const t of svg.querySelectorAll('text')) {
    const size = parseFloat(getComputedStyle(t).fontSize);
    if (size * scale < minPx) t.style.fontSize = `${(minPx / scale).toFixed(2)}px`;
  }
}
