// The 2-D periodogram P(k) of POST /v1/analyze as an image: one square cell per integer
// frequency (kx right, ky up), log10 colour scale (viridis, dark = low, so it reads in
// greyscale) with a labelled colour bar. DC (k = 0, where P = n) is left out of the scale and
// drawn white, ringed. The canvas sits under an SVG that draws the frame, axes and colour bar.

import { el, text, clear, niceTicks, enlargeSmallText } from './svg.js';

/* Viridis at nine evenly spaced stops (matplotlib); linear in between. */
const VIRIDIS = ['#440154', '#472d7b', '#3b528b', '#2c728e', '#21918c', '#28ae80', '#5ec962', '#addc30', '#fde725'];
const rgb = (hex) => [1, 3, 5].map((i) => parseInt(hex.slice(i, i + 2), 16));
const STOPS = VIRIDIS.map(rgb);

/* 256 colours: the scale is quantised to these, so a drawn cell is exactly one of them. */
export const LUT = Array.from({ length: 256 }, (_, i) => {
  const t = (i / 255) * (STOPS.length - 1);
  const j = Math.min(STOPS.length - 2, Math.floor(t));
  const f = t - j;
  return STOPS[j].map((c, ch) => Math.round(c + f * (STOPS[j + 1][ch] - c)));
});
export const DC_COLOUR = [255, 255, 255];
export const MISSING_COLOUR = [190, 190, 190]; // a null power (undefined): not on the scale

/* Decades shown: the colour bar spans hi / 10^DECADES .. hi. */
export const DECADES = 4;
/* Display size the image aims at, in canvas pixels (a whole number of pixels per frequency). */
const TARGET = 320;

/* Canvas pixels per frequency at a radius: the largest whole number that keeps the image within
 * TARGET pixels, at least 1. */
export function periodogramCell(radius) {
  return Math.max(1, Math.floor(TARGET / (2 * radius + 1)));
}

/* The colour scale of one periodogram: hi is the decade at or above the largest power off DC
 * (at least 10, so white noise's level P = 1 is always inside), lo = hi / 10^DECADES. */
export function colourScale(power) {
  const r = (power.length - 1) / 2;
  let max = 0;
  power.forEach((row, j) =>
    row.forEach((p, i) => {
      if ((i !== r || j !== r) && Number.isFinite(p) && p > max) max = p;
    }),
  );
  const hiExp = Math.max(1, Math.ceil(Math.log10(max) - 1e-12) || 1);
  return { loExp: hiExp - DECADES, hiExp, maxOffDc: max };
}

/* The LUT index of a power: 0 at or below 10^loExp (zero included), 255 at 10^hiExp. */
export function levelOf(p, scale) {
  if (!(p > 0)) return 0;
  const t = (Math.log10(p) - scale.loExp) / (scale.hiExp - scale.loExp);
  return Math.round(Math.min(1, Math.max(0, t)) * 255);
}

/* The colour a cell of power p is drawn in ([r, g, b]); DC and null apart. */
export function colourOf(p, scale, { dc = false } = {}) {
  if (dc) return DC_COLOUR;
  if (p == null || Number.isNaN(p)) return MISSING_COLOUR;
  return LUT[levelOf(p, scale)];
}

const SUP = { '-': '⁻', 0: '⁰', 1: '¹', 2: '²', 3: '³', 4: '⁴', 5: '⁵', 6: '⁶', 7: '⁷', 8: '⁸', 9: '⁹' };
export function powerOfTen(e) {
  if (e === 0) return '1';
  if (e === 1) return '10';
  return `10${String(e).replace(/./g, (c) => SUP[c])}`;
}

/* Fills the canvas with the periodogram (rows of power: ky = -r..r, columns kx = -r..r). */
export function paintPeriodogram(canvas, power, scale) {
  const side = power.length;
  const r = (side - 1) / 2;
  const cell = periodogramCell(r);
  canvas.width = side * cell;
  canvas.height = side * cell;
  const g = canvas.getContext('2d');
  const img = g.createImageData(canvas.width, canvas.height);
  const px = img.data;
  for (let row = 0; row < side; row++) {
    const ky = r - row; // top row is ky = +r
    const line = power[ky + r];
    for (let col = 0; col < side; col++) {
      const c = colourOf(line[col], scale, { dc: row === r && col === r });
      for (let y = row * cell; y < (row + 1) * cell; y++)
        for (let x = col * cell; x < (col + 1) * cell; x++) {
          const o = (y * canvas.width + x) * 4;
          px[o] = c[0];
          px[o + 1] = c[1];
          px[o + 2] = c[2];
          px[o + 3] = 255;
        }
    }
  }
  g.putImageData(img, 0, 0);
  canvas.dataset.radius = String(r);
  canvas.dataset.cell = String(cell);
  return cell;
}

/* Geometry of the drawing, in viewBox units: a square plot, the colour bar right of it. */
const W = 420;
const M = { l: 50, t: 28, b: 46 };
const PLOT = 270;
const H = M.t + PLOT + M.b;
const BAR = { x: M.l + PLOT + 22, w: 14 };

/* Draws the periodogram of spectrum (POST /v1/analyze's "spectrum") into container. Returns the
 * canvas and the colour scale. */
export function drawPeriodogram(container, spectrum) {
  clear(container);
  const r = spectrum.radius;
  const scale = colourScale(spectrum.power);
  const holder = document.createElement('div');
  holder.className = 'pgram-holder';
  container.appendChild(holder);
  const canvas = document.createElement('canvas');
  canvas.className = 'pgram-canvas';
  canvas.setAttribute('role', 'img');
  canvas.setAttribute('aria-label', `Periodogram P(k) for |kx|, |ky| ≤ ${r}, colour log10 P from ${powerOfTen(scale.loExp)} to ${powerOfTen(scale.hiExp)}; largest off DC ${scale.maxOffDc.toPrecision(4)}`);
  // Placed over the SVG's plot area, in percentages so it scales with it.
  Object.assign(canvas.style, { left: `${(100 * M.l) / W}%`, top: `${(100 * M.t) / H}%`, width: `${(100 * PLOT) / W}%`, height: `${(100 * PLOT) / H}%` });
  holder.appendChild(canvas);
  paintPeriodogram(canvas, spectrum.power, scale);

  const svg = el('svg', { viewBox: `0 0 ${W} ${H}`, class: 'pgram-svg', 'aria-hidden': 'true' }, holder);
  text(svg, 4, 17, 'Periodogram P(k)', { class: 'plot-title' });
  const X = (kx) => M.l + ((kx + r + 0.5) / (2 * r + 1)) * PLOT;
  const Y = (ky) => M.t + ((r + 0.5 - ky) / (2 * r + 1)) * PLOT;
  el('rect', { x: M.l, y: M.t, width: PLOT, height: PLOT, class: 'frame' }, svg);
  const ticks = niceTicks(-r, r, 4).filter((t) => Number.isInteger(t));
  for (const t of ticks) {
    el('line', { x1: X(t), x2: X(t), y1: M.t + PLOT, y2: M.t + PLOT + 5, class: 'tick-mark' }, svg);
    text(svg, X(t), M.t + PLOT + 18, String(t).replace('-', '−'), { 'text-anchor': 'middle', class: 'tick' });
    el('line', { x1: M.l - 5, x2: M.l, y1: Y(t), y2: Y(t), class: 'tick-mark' }, svg);
    text(svg, M.l - 8, Y(t) + 4, String(t).replace('-', '−'), { 'text-anchor': 'end', class: 'tick' });
  }
  text(svg, M.l + PLOT / 2, H - 8, 'kx (cycles per tile)', { 'text-anchor': 'middle', class: 'axis-label' });
  const yl = text(svg, 13, M.t + PLOT / 2, 'ky', { 'text-anchor': 'middle', class: 'axis-label' });
  yl.setAttribute('transform', `rotate(-90 13 ${M.t + PLOT / 2})`);
  // DC: ringed, over the canvas (the SVG is drawn on top of it).
  const dcR = Math.max(5, PLOT / (2 * r + 1));
  el('circle', { cx: X(0), cy: Y(0), r: dcR, class: 'pgram-dc-halo' }, svg);
  el('circle', { cx: X(0), cy: Y(0), r: dcR, class: 'pgram-dc' }, svg);

  // Colour bar: a gradient through the same stops, a tick per decade.
  const id = `pgram-grad-${Math.random().toString(36).slice(2, 8)}`;
  const grad = el('linearGradient', { id, x1: 0, y1: 1, x2: 0, y2: 0 }, el('defs', {}, svg));
  VIRIDIS.forEach((c, i) => el('stop', { offset: i / (VIRIDIS.length - 1), 'stop-color': c }, grad));
  el('rect', { x: BAR.x, y: M.t, width: BAR.w, height: PLOT, fill: `url(#${id})`, class: 'frame' }, svg);
  for (let e = scale.loExp; e <= scale.hiExp; e++) {
    const y = M.t + PLOT - ((e - scale.loExp) / (scale.hiExp - scale.loExp)) * PLOT;
    el('line', { x1: BAR.x + BAR.w, x2: BAR.x + BAR.w + 4, y1: y, y2: y, class: 'tick-mark' }, svg);
    text(svg, BAR.x + BAR.w + 6, y + 4, (e === scale.loExp ? '≤' : '') + powerOfTen(e), { class: 'tick' });
  }
  enlargeSmallText(svg);
  return { canvas, scale };
}
