// Tools under every SVG plot (drawScatter, drawPolar): zoom by dragging a rectangle over the
// plot and reset, and downloads of the plot as PNG and SVG and of its data as CSV (issue 34:
// plots of paper quality). The styles the page's CSS gives the plot are written into the
// downloaded SVG, so it looks the same on its own.

const STYLE_PROPS = ['fill', 'fill-opacity', 'stroke', 'stroke-width', 'stroke-dasharray', 'stroke-opacity', 'opacity', 'font-size', 'font-family', 'font-weight', 'paint-order', 'text-anchor', 'dominant-baseline'];

/* CSV text of a header and rows (RFC 4180: quoted where needed, CRLF records). */
export function csvText(header, rows) {
  const cell = (v) => {
    const s = v == null || (typeof v === 'number' && !Number.isFinite(v)) ? '' : String(v);
    return /[",\r\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
  };
  return [header, ...rows].map((r) => r.map(cell).join(',')).join('\r\n') + '\r\n';
}

/* A file name from a plot's title: "e2-against-samples-per-pixel". */
export function fileStem(title) {
  const s = String(title || 'plot')
    .normalize('NFKD')
    .replace(/[^\x20-\x7e]/g, '')
    .toLowerCase()
    .replace(/[^a-z0-9]+/g, '-')
    .replace(/^-+|-+$/g, '');
  return s || 'plot';
}

/* The plot as a standalone SVG document, with the page's computed styles inlined. */
export function standaloneSvg(svg) {
  const clone = svg.cloneNode(true);
  const src = [svg, ...svg.querySelectorAll('*')];
  const dst = [clone, ...clone.querySelectorAll('*')];
  src.forEach((node, i) => {
    const cs = getComputedStyle(node);
    const style = STYLE_PROPS.map((p) => `${p}:${cs.getPropertyValue(p)}`).join(';');
    dst[i].setAttribute('style', `${dst[i].getAttribute('style') || ''};${style}`);
  });
  clone.setAttribute('xmlns', 'http://www.w3.org/2000/svg');
  const vb = svg.viewBox.baseVal;
  clone.setAttribute('width', String(vb.width));
  clone.setAttribute('height', String(vb.height));
  clone.removeAttribute('class');
  // A white ground: a PNG or a paper's page should not show through.
  const bg = document.createElementNS('http://www.w3.org/2000/svg', 'rect');
  for (const [k, v] of Object.entries({ x: vb.x, y: vb.y, width: vb.width, height: vb.height, fill: '#fff' })) bg.setAttribute(k, String(v));
  clone.insertBefore(bg, clone.firstChild);
  return `<?xml version="1.0" encoding="UTF-8"?>\n${new XMLSerializer().serializeToString(clone)}\n`;
}

function download(name, blob) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

/* The SVG drawn at 2x onto a canvas, as a PNG blob. */
export function svgToPng(svg, scale = 2) {
  const text = standaloneSvg(svg);
  const vb = svg.viewBox.baseVal;
  return new Promise((resolve, reject) => {
    const img = new Image();
    img.onload = () => {
      const c = document.createElement('canvas');
      c.width = Math.round(vb.width * scale);
      c.height = Math.round(vb.height * scale);
      const g = c.getContext('2d');
      g.fillStyle = '#fff';
      g.fillRect(0, 0, c.width, c.height);
      g.drawImage(img, 0, 0, c.width, c.height);
      c.toBlob((b) => (b ? resolve(b) : reject(new Error('PNG encoding failed'))), 'image/png');
    };
    img.onerror = () => reject(new Error('the SVG could not be drawn'));
    img.src = `data:image/svg+xml;charset=utf-8,${encodeURIComponent(text)}`;
  });
}

/* Drag a rectangle over the plot to zoom into it (the viewBox); Reset restores it. */
function makeZoomable(svg, reset) {
  const vb0 = svg.viewBox.baseVal;
  const original = [vb0.x, vb0.y, vb0.width, vb0.height];
  svg.dataset.viewBox = original.join(' ');
  let start = null;
  let box = null;
  const toSvg = (evt) => {
    const pt = svg.createSVGPoint();
    pt.x = evt.clientX;
    pt.y = evt.clientY;
    return pt.matrixTransform(svg.getScreenCTM().inverse());
  };
  svg.addEventListener('pointerdown', (evt) => {
    if (evt.button !== 0 || evt.target.closest('a')) return; // points stay links
    start = toSvg(evt);
    box = document.createElementNS('http://www.w3.org/2000/svg', 'rect');
    box.setAttribute('class', 'zoom-box');
    svg.append(box);
    svg.setPointerCapture(evt.pointerId);
  });
  svg.addEventListener('pointermove', (evt) => {
    if (!start) return;
    const p = toSvg(evt);
    const x = Math.min(p.x, start.x);
    const y = Math.min(p.y, start.y);
    for (const [k, v] of Object.entries({ x, y, width: Math.abs(p.x - start.x), height: Math.abs(p.y - start.y) })) box.setAttribute(k, String(v));
  });
  const end = (evt) => {
    if (!start) return;
    const p = toSvg(evt);
    const w = Math.abs(p.x - start.x);
    const h = Math.abs(p.y - start.y);
    box.remove();
    // A click (or a sliver) is not a zoom.
    if (w > 8 && h > 8) {
      svg.setAttribute('viewBox', `${Math.min(p.x, start.x)} ${Math.min(p.y, start.y)} ${w} ${h}`);
      svg.dataset.zoomed = 'true';
      reset.disabled = false;
    }
    start = null;
  };
  svg.addEventListener('pointerup', end);
  svg.addEventListener('pointercancel', end);
  reset.onclick = () => {
    svg.setAttribute('viewBox', original.join(' '));
    delete svg.dataset.zoomed;
    reset.disabled = true;
  };
}

/* Adds the toolbar under svg in container: Reset zoom, PNG, SVG and (with csv) CSV. csv: a
 * function returning {header, rows}. */
export function addPlotTools(container, svg, { title = '', csv = null } = {}) {
  const bar = document.createElement('div');
  bar.className = 'plot-tools';
  const button = (label, action, aria) => {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = label;
    b.dataset.action = action;
    b.setAttribute('aria-label', `${aria} (${title || 'plot'})`);
    bar.append(b);
    return b;
  };
  const reset = button('Reset zoom', 'reset', 'Reset the zoom');
  reset.disabled = true;
  reset.title = 'Drag a rectangle over the plot to zoom in';
  const stem = fileStem(title || svg.getAttribute('aria-label'));
  button('PNG', 'png', 'Download the plot as PNG').onclick = () => svgToPng(svg).then((b) => download(`${stem}.png`, b));
  button('SVG', 'svg', 'Download the plot as SVG').onclick = () => download(`${stem}.svg`, new Blob([standaloneSvg(svg)], { type: 'image/svg+xml' }));
  if (csv)
    button('CSV', 'csv', 'Download the plot data as CSV').onclick = () => {
      const d = csv();
      download(`${stem}.csv`, new Blob([csvText(d.header, d.rows)], { type: 'text/csv' }));
    };
  makeZoomable(svg, reset);
  container.append(bar);
  return bar;
}

/* The same toolbar for a canvas chart (uPlot): Reset zoom (reset()), PNG of its canvas and CSV
 * of its data. uPlot zooms by dragging over it already. */
export function addCanvasPlotTools(container, { title = '', canvas, reset = null, csv = null }) {
  container.querySelector(':scope > .plot-tools')?.remove();
  const bar = document.createElement('div');
  bar.className = 'plot-tools';
  const stem = fileStem(title);
  const button = (label, action, onclick) => {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = label;
    b.dataset.action = action;
    b.setAttribute('aria-label', `${label} (${title || 'plot'})`);
    b.onclick = onclick;
    bar.append(b);
  };
  if (reset) button('Reset zoom', 'reset', reset);
  button('PNG', 'png', () => canvas().toBlob((b) => b && download(`${stem}.png`, b), 'image/png'));
  if (csv)
    button('CSV', 'csv', () => {
      const d = csv();
      download(`${stem}.csv`, new Blob([csvText(d.header, d.rows)], { type: 'text/csv' }));
    });
  container.append(bar);
  return bar;
}
