// The pixel and its neighbours as SVG: dot area proportional to |weight| (Hasselgren et al.
// Fig. 3); negative weights hollow, dashed and labelled with a minus sign, so they read without
// colour. Samples of the centre pixel can be dragged with the mouse or moved with arrow keys.

import { el, text, clear, screenScale } from './svg.js';
import { layoutDots, moveSample, editableSamples, kernelsOf, placeWeightLabels } from './pattern-geometry.js';

const SIZE = 420;
const HALF = 1.5; // three pixels across

export class PatternView {
  constructor(container, { editable = false, onChange = null, onCommit = null, label = 'Sample pattern' } = {}) {
    this.container = container;
    this.editable = editable;
    this.onChange = onChange;
    this.onCommit = onCommit;
    this.label = label;
    this.kernel = 0;
    this.keepSites = true;
    this.pattern = null;
    this.drag = null;
    this.svg = el('svg', { viewBox: `0 0 ${SIZE} ${SIZE}`, class: 'pattern-svg', role: 'group', 'aria-label': label });
    container.appendChild(this.svg);
    // Move and release are handled on the svg (which holds the pointer capture), because the
    // dots are redrawn while they move.
    this.svg.addEventListener('pointermove', (evt) => {
      if (!this.drag || this.drag.pointerId !== evt.pointerId) return;
      const [x, y] = this.fromScreen(evt);
      this.applyMove(this.drag.index, x, y, false);
    });
    const end = (evt) => {
      if (!this.drag || this.drag.pointerId !== evt.pointerId) return;
      this.drag = null;
      if (this.onCommit) this.onCommit(this.pattern);
    };
    this.svg.addEventListener('pointerup', end);
    this.svg.addEventListener('pointercancel', end);
  }

  toScreen(x, y) {
    const s = SIZE / (2 * HALF);
    return [(x + HALF) * s, (HALF - y) * s];
  }

  fromScreen(evt) {
    const pt = this.svg.createSVGPoint();
    pt.x = evt.clientX;
    pt.y = evt.clientY;
    const p = pt.matrixTransform(this.svg.getScreenCTM().inverse());
    const s = SIZE / (2 * HALF);
    return [p.x / s - HALF, HALF - p.y / s];
  }

  setPattern(pattern, kernel = this.kernel) {
    this.pattern = pattern;
    this.kernel = Math.max(0, Math.min(kernel, kernelsOf(pattern).length - 1));
    this.render();
  }

  render() {
    const svg = this.svg;
    clear(svg);
    if (!this.pattern) return;
    const s = SIZE / (2 * HALF);
    // Pixel grid: the centre pixel framed strongly, neighbours lightly.
    for (let j = -1; j <= 1; j++)
      for (let i = -1; i <= 1; i++) {
        const [x0, y0] = this.toScreen(i - 0.5, j + 0.5);
        el('rect', { x: x0, y: y0, width: s, height: s, class: i || j ? 'px-neighbour' : 'px-centre' }, svg);
      }
    const [cx, cy] = this.toScreen(0, 0);
    el('path', { d: `M${cx - 6},${cy}h12M${cx},${cy - 6}v12`, class: 'px-origin' }, svg);

    const dots = layoutDots(this.pattern, this.kernel);
    const maxW = Math.max(1e-12, ...dots.map((d) => Math.abs(d.w)));
    // A dense kernel (64 samples of a P(16,16,4)) gets smaller dots, so they do not merge.
    const nPrimary = dots.filter((d) => d.primary).length;
    const rMax = s * Math.min(0.13, 0.42 / Math.sqrt(Math.max(1, nPrimary)));
    const samples = editableSamples(this.pattern, this.kernel);
    // Neighbours first, so centre dots sit on top.
    dots.sort((a, b) => a.primary - b.primary);
    // Weight labels on top of every dot, only where they cover no other label and no dot
    // (placeWeightLabels); each weight stays in the sample's accessible name and tooltip.
    const fontPx = Math.max(12, 11 / screenScale(svg)); // at least 11 px on screen
    const circles = dots.map((d) => {
      const [x, y] = this.toScreen(d.x, d.y);
      return { x, y, r: Math.max(2.5, rMax * Math.sqrt(Math.abs(d.w) / maxW)) };
    });
    const groups = [];
    dots.forEach((d, k) => {
      const { x, y, r } = circles[k];
      const neg = d.w < 0;
      const g = el('g', { class: `dot ${d.primary ? 'dot-primary' : 'dot-neighbour'} ${neg ? 'dot-negative' : 'dot-positive'}` }, svg);
      groups.push(g);
      el('circle', { cx: x, cy: y, r, class: 'dot-shape' }, g);
      if (neg) text(g, x, y + 4, '−', { class: 'dot-sign', 'text-anchor': 'middle' });
      if (d.primary) {
        g.dataset.index = d.index;
        const [sx, sy] = samples[d.index];
        g.setAttribute('aria-label', `sample ${d.index + 1}: x ${sx.toFixed(3)}, y ${sy.toFixed(3)}, weight ${formatWeight(d.w)}`);
        el('title', {}, g).textContent = `weight ${formatWeight(d.w)}`;
        if (this.editable) this.makeEditable(g, d.index);
      }
    });
    const wanted = dots.map((d, i) => ({ i, text: formatWeight(d.w), primary: d.primary })).filter((l) => l.primary);
    // A label is a child of its dot's group (the group is re-appended last, so labels sit on top).
    for (const p of placeWeightLabels(circles, wanted, fontPx)) {
      const g = groups[p.i];
      svg.appendChild(g);
      const t = text(g, p.x, p.y, formatWeight(dots[p.i].w), { class: 'dot-label', 'text-anchor': p.anchor });
      t.style.fontSize = `${fontPx.toFixed(2)}px`;
    }
  }

  makeEditable(g, index) {
    g.setAttribute('tabindex', '0');
    g.setAttribute('role', 'button');
    g.classList.add('draggable');
    g.addEventListener('pointerdown', (evt) => {
      evt.preventDefault();
      this.svg.setPointerCapture(evt.pointerId);
      this.drag = { index, pointerId: evt.pointerId };
    });
    g.addEventListener('keydown', (evt) => {
      const step = evt.shiftKey ? 1 / 16 : evt.altKey ? 1 / 256 : 1 / 64;
      const d = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, step], ArrowDown: [0, -step] }[evt.key];
      if (!d) return;
      evt.preventDefault();
      const [x, y] = editableSamples(this.pattern, this.kernel)[index];
      this.applyMove(index, x + d[0], y + d[1], true);
    });
  }

  applyMove(index, x, y, refocus) {
    const before = editableSamples(this.pattern, this.kernel)[index].slice(0, 2).join();
    moveSample(this.pattern, this.kernel, index, x, y, this.keepSites);
    if (editableSamples(this.pattern, this.kernel)[index].slice(0, 2).join() === before) return; // held by its site
    this.render();
    const g = this.svg.querySelector(`g.dot-primary[data-index="${index}"]`);
    if (g && refocus) g.focus();
    if (this.onChange) this.onChange(this.pattern);
    if (refocus && this.onCommit) this.onCommit(this.pattern);
  }
}

export function formatWeight(w) {
  const s = Math.abs(w) >= 0.01 ? w.toFixed(3).replace(/0+$/, '').replace(/\.$/, '') : w.toPrecision(2);
  return w < 0 ? s.replace('-', '−') : s;
}
