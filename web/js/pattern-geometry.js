// What the page can draw and edit: explicit kernels and the mirrored P(4,1+,n) form.
// Coordinates are relative to the output pixel centre; the pixel is [-0.5, 0.5]^2.

const EPS = 1e-9;

export function clonePattern(p) {
  return JSON.parse(JSON.stringify(p));
}

export function isDrawable(p) {
  return !!p && (Array.isArray(p.kernels) || Array.isArray(p.mirrored));
}

/* What to draw for a pattern: itself when editable here, or (read-only) the explicit kernels the
 * server adds to patterns it encodes ("kernels_expanded", e.g. for the tile form). */
export function drawableOf(p) {
  if (isDrawable(p)) return { pattern: p, readOnly: false };
  if (p && Array.isArray(p.kernels_expanded)) return { pattern: { kernels: p.kernels_expanded }, readOnly: true };
  return null;
}

/* Reconstruction kernels of a drawable pattern (mirrored: the pixel mirrored in x, y, xy). */
export function kernelsOf(p) {
  if (Array.isArray(p.kernels)) return p.kernels;
  const m = p.mirrored;
  return [m, m.map(([x, y, w]) => [-x, y, w]), m.map(([x, y, w]) => [x, -y, w]), m.map(([x, y, w]) => [-x, -y, w])];
}

/* The samples whose positions the user edits: the selected kernel, or the mirrored pixel. */
export function editableSamples(p, kernel) {
  return Array.isArray(p.mirrored) ? p.mirrored : p.kernels[Math.min(kernel, p.kernels.length - 1)];
}

/* Dots to draw for the pixel and its eight neighbours. Neighbours are the mirrored pixel
 * (mirrored form) or the same kernel repeated (kernels form); a neighbour's dot that lands on a
 * dot of the centre pixel is a shared sample and is drawn once. */
export function layoutDots(p, kernel) {
  const mirrored = Array.isArray(p.mirrored);
  const centre = editableSamples(p, kernel);
  const dots = centre.map(([x, y, w], index) => ({ x, y, w, index, primary: true }));
  for (let j = -1; j <= 1; j++)
    for (let i = -1; i <= 1; i++) {
      if (!i && !j) continue;
      const sx = mirrored && i % 2 ? -1 : 1;
      const sy = mirrored && j % 2 ? -1 : 1;
      for (const [x, y, w] of centre) {
        const X = sx * x + i;
        const Y = sy * y + j;
        if (Math.abs(X) > 1.5 + EPS || Math.abs(Y) > 1.5 + EPS) continue;
        if (dots.some((d) => Math.abs(d.x - X) < 1e-6 && Math.abs(d.y - Y) < 1e-6)) continue;
        dots.push({ x: X, y: Y, w, index: -1, primary: false });
      }
    }
  return dots;
}

/* Moves one editable sample. With keepSites, a sample on a pixel edge stays on that edge and a
 * corner sample stays put, as the optimizer's family constraints do. */
export function moveSample(p, kernel, index, x, y, keepSites) {
  const s = editableSamples(p, kernel)[index];
  const limit = Array.isArray(p.mirrored) ? 0.5 : 1.5;
  const onX = Math.abs(Math.abs(s[0]) - 0.5) < EPS;
  const onY = Math.abs(Math.abs(s[1]) - 0.5) < EPS;
  let nx = Math.max(-limit, Math.min(limit, x));
  let ny = Math.max(-limit, Math.min(limit, y));
  if (keepSites && onX) nx = s[0];
  if (keepSites && onY) ny = s[1];
  s[0] = +nx.toFixed(6);
  s[1] = +ny.toFixed(6);
  return s;
}

export function extentOf(p) {
  let m = 0.5;
  for (const k of kernelsOf(p)) for (const [x, y] of k) m = Math.max(m, Math.abs(x), Math.abs(y));
  return m;
}

/* Where the weight labels go: circles [{x, y, r}] are every drawn dot (screen units), labels
 * [{i, text}] the dots to label (i indexes circles). A label sits beside its dot (right above,
 * right below, left above, left below: the first that fits) where it covers no other label and
 * no dot; else it is left out (its weight stays in the dot's name and tooltip). A P(16,16,4)
 * kernel has 64 samples in the pixel: most labels would overprint or hide under dots (issue 34).
 * Boxes assume digits about 0.62 em wide. Returns [{i, x, y, anchor, box}]. */
export function placeWeightLabels(circles, labels, fontPx) {
  const placed = [];
  const hitsBox = (b) => placed.some((p) => b.x0 < p.box.x1 && p.box.x0 < b.x1 && b.y0 < p.box.y1 && p.box.y0 < b.y1);
  const hitsCircle = (b) =>
    circles.some((c) => {
      const dx = Math.max(b.x0 - c.x, 0, c.x - b.x1);
      const dy = Math.max(b.y0 - c.y, 0, c.y - b.y1);
      return dx * dx + dy * dy < c.r * c.r;
    });
  for (const { i, text } of labels) {
    const c = circles[i];
    const w = 0.62 * fontPx * text.length;
    const tries = [
      { x: c.x + c.r + 3, y: c.y - c.r - 1, anchor: 'start' },
      { x: c.x + c.r + 3, y: c.y + c.r + fontPx - 1, anchor: 'start' },
      { x: c.x - c.r - 3, y: c.y - c.r - 1, anchor: 'end' },
      { x: c.x - c.r - 3, y: c.y + c.r + fontPx - 1, anchor: 'end' },
    ];
    for (const t of tries) {
      const x0 = t.anchor === 'start' ? t.x - 1 : t.x - w - 1;
      const box = { x0, x1: x0 + w + 2, y0: t.y - fontPx, y1: t.y + 3 };
      if (!hitsBox(box) && !hitsCircle(box)) {
        placed.push({ i, ...t, box });
        break;
      }
    }
  }
  return placed;
}
