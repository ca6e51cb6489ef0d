// Tiles: render a scene with a pattern beside the reference and their difference, with zoom,
// RMSE / max deviation / penalised histogram and the edge model's predicted RMSE beside it
// (tile-prediction.js); and the comparison job as RMSE and E2 against samples per pixel.

import uPlot from '../../vendor/uplot/uPlot.esm.js';
import { addCanvasPlotTools } from '../plot-tools.js';
import { apiPost, apiImageUrl } from '../api.js';
import { renderImages, renderStats, comparisonRows, comparisonPrediction, fmt, fmtSeconds, ACTIVE_STATES } from '../model.js';
import { drawComparison } from './kind-details.js';
import { predictTile, setMeasured } from './tile-prediction.js';
import { loadPresets, loadJob, jobKinds, loadFinishedWithBest } from '../store.js';

const $ = (id) => document.getElementById(id);
// Scene names of the renderer.
export const SCENES = ['siemens-star', 'checkerboard', 'rings', 'sliver', 'spiral', 'half-plane'];
const CMP_DEFAULT = new Set(['centroid', 'quincunx', 'rgss', 'flipquad', 'fliptri', 'grid-2x2']);

let ctx = null;
let hist = null;
let patterns = new Map(); // option value -> wire pattern
let imageUrls = [];
let cmpTimer = null;
let renderClock = null;

export async function init(context) {
  ctx = context;
  $('tile-scene').replaceChildren(...SCENES.map((s) => new Option(s, s)));
  $('tile-form').addEventListener('submit', (e) => {
    e.preventDefault();
    renderTile();
  });
  $('tile-zoom').addEventListener('input', applyZoom);
  // A prediction costs no render: a new one for every change of the tile.
  for (const id of ['tile-scene', 'tile-pattern', 'tile-size'])
    $(id).addEventListener('change', () => {
      const body = tileRequest();
      if (body.pattern) predictTile(body);
    });
  $('cmp-form').addEventListener('submit', (e) => {
    e.preventDefault();
    startComparison();
  });
  // Scroll the three zoomed frames together so the same region stays side by side.
  const frames = [...document.querySelectorAll('#tile-images .tile-frame')];
  let syncing = false;
  frames.forEach((f) =>
    f.addEventListener('scroll', () => {
      if (syncing) return;
      syncing = true;
      for (const g of frames) if (g !== f) {
        g.scrollLeft = f.scrollLeft;
        g.scrollTop = f.scrollTop;
      }
      syncing = false;
    }),
  );
  window.addEventListener('resize', () => hist && hist.setSize(histSize()));
}

export async function show() {
  await fillPatterns();
  const body = tileRequest();
  if (body.pattern) predictTile(body);
  const kinds = await jobKinds().catch(() => null);
  const missing = kinds && !kinds.includes('compare');
  $('cmp-start').disabled = !!missing;
  if (missing) $('cmp-status').textContent = `this daemon runs no compare jobs (its job kinds: ${kinds.join(', ')})`;
}

export function hide() {
  clearTimeout(cmpTimer);
}

/* The render request of the form's tile (server/tiles/tile_render.h): scene and reference
 * objects; POST /v1/predict takes the same scene, pattern and reference. */
function tileRequest() {
  const n = +$('tile-size').value;
  return {
    pattern: patterns.get($('tile-pattern').value),
    scene: { name: $('tile-scene').value, width: n, height: n },
    reference: { spp: +$('tile-ref').value },
  };
}

/* The render is one synchronous request: the page shows that it runs and for how long. */
function renderRunning(on) {
  clearInterval(renderClock);
  $('tile-progress').hidden = !on;
  if (!on) return;
  const t0 = performance.now();
  $('tile-elapsed').textContent = '0.0 s';
  renderClock = setInterval(() => {
    $('tile-elapsed').textContent = `${((performance.now() - t0) / 1000).toFixed(1)} s`;
  }, 100);
}

async function fillPatterns() {
  const presets = await loadPresets();
  const jobs = await loadFinishedWithBest().catch(() => []);
  const prev = $('tile-pattern').value;
  patterns = new Map();
  const opts = [];
  for (const p of presets) {
    patterns.set(`preset:${p.name}`, { preset: p.name });
    opts.push(new Option(`${p.name} (${p.family})`, `preset:${p.name}`));
  }
  for (const j of jobs) {
    patterns.set(`job:${j.id}`, { job: j.id }); // the finished job's best pattern, resolved by the daemon
    opts.push(new Option(`job #${j.id} best (${j.family || j.kind})`, `job:${j.id}`));
  }
  $('tile-pattern').replaceChildren(...opts);
  $('tile-pattern').value = patterns.has(prev) ? prev : patterns.has('preset:quincunx') ? 'preset:quincunx' : opts[0]?.value;
  const checked = new Set([...document.querySelectorAll('#cmp-patterns input:checked')].map((i) => i.value));
  $('cmp-patterns').replaceChildren(
    ...[...patterns.keys()].map((key) => {
      const label = document.createElement('label');
      const input = document.createElement('input');
      input.type = 'checkbox';
      input.value = key;
      input.checked = checked.size ? checked.has(key) : CMP_DEFAULT.has(key.replace(/^preset:/, ''));
      label.append(input, ` ${key.replace(/^preset:/, '').replace(/^job:/, 'job #')}`);
      return label;
    }),
  );
}

async function renderTile() {
  const body = tileRequest();
  const n = body.scene.width;
  $('tile-render').disabled = true;
  $('tile-status').classList.remove('error-text');
  $('tile-status').textContent = 'rendering…';
  renderRunning(true);
  predictTile(body); // answers long before the render: shown while it runs
  try {
    const r = await apiPost('/v1/render', body);
    const urls = renderImages(r);
    const missing = ['pattern', 'reference', 'difference'].filter((k) => !urls[k]);
    if (missing.length) throw new Error(`the render answer names no ${missing.join(', ')} image`);
    for (const u of imageUrls) URL.revokeObjectURL(u);
    imageUrls = await Promise.all(['pattern', 'reference', 'difference'].map((k) => apiImageUrl(urls[k])));
    await Promise.all(
      ['pattern', 'reference', 'difference'].map(
        (k, i) =>
          new Promise((resolve, reject) => {
            const img = $(`tile-img-${k}`);
            img.onload = () => resolve();
            img.onerror = () => reject(new Error(`${k} image did not load`));
            img.dataset.loaded = 'false';
            img.src = imageUrls[i];
          }),
      ),
    );
    for (const k of ['pattern', 'reference', 'difference']) $(`tile-img-${k}`).dataset.loaded = 'true';
    applyZoom();
    const stats = renderStats(r);
    showStats(stats);
    setMeasured(body, stats.rmse);
    $('tile-status').textContent = `${body.scene.name} with ${$('tile-pattern').selectedOptions[0].textContent}, ${n}×${n}`;
  } catch (e) {
    $('tile-status').classList.add('error-text');
    $('tile-status').textContent = `render failed: ${e.message}`;
  } finally {
    renderRunning(false);
    $('tile-render').disabled = false;
  }
}

function applyZoom() {
  const z = +$('tile-zoom').value;
  $('tile-zoom-out').textContent = `${z}×`;
  $('tile-zoom').setAttribute('aria-valuetext', `${z}×`);
  for (const k of ['pattern', 'reference', 'difference']) {
    const img = $(`tile-img-${k}`);
    if (img.naturalWidth) img.style.width = `${img.naturalWidth * z}px`;
  }
}

function showStats(s) {
  $('tile-rmse').textContent = fmt(s.rmse, 3);
  $('tile-maxdev').textContent = fmt(s.maxDev, 1);
  $('tile-e2').textContent = fmt(s.e2, 4);
  $('tile-tpat').textContent = fmtSeconds(s.patternSeconds);
  $('tile-tref').textContent = fmtSeconds(s.referenceSeconds);
  $('tile-ss').textContent = s.supersampled == null ? '—' : `${s.supersampled}${s.totalPixels ? ` of ${s.totalPixels}` : ''}`;
  const holder = $('tile-hist');
  if (!s.histogram) {
    holder.textContent = 'no histogram in the answer';
    return;
  }
  const xs = s.histogram.map((_, i) => i);
  if (hist) hist.destroy();
  holder.replaceChildren();
  hist = new uPlot(
    {
      ...histSize(),
      scales: { x: { time: false } },
      axes: [{ label: 'absolute error i (0..255)' }, { label: 'C(i)·i²/n', size: 60 }],
      series: [
        { label: 'i' },
        { label: 'penalised count', stroke: '#c2410c', fill: 'rgba(194,65,12,0.35)', paths: uPlot.paths.bars({ size: [1, 100] }), points: { show: false } },
      ],
    },
    [xs, s.histogram],
    holder,
  );
  // Drag over it to zoom (uPlot); the toolbar resets, and downloads the chart and its counts.
  const h = s.histogram;
  addCanvasPlotTools(holder, {
    title: 'penalised histogram',
    canvas: () => holder.querySelector('canvas'),
    reset: () => hist && hist.setScale('x', { min: 0, max: xs.length - 1 }),
    csv: () => ({ header: ['abs_error', 'penalised_count'], rows: h.map((v, i) => [i, v]) }),
  });
}

function histSize() {
  const w = Math.max(280, $('tile-hist').clientWidth || 480);
  return { width: w, height: 220 };
}

async function startComparison() {
  clearTimeout(cmpTimer);
  const keys = [...document.querySelectorAll('#cmp-patterns input:checked')].map((i) => i.value);
  if (!keys.length) {
    $('cmp-status').textContent = 'choose at least one pattern';
    return;
  }
  const n = +$('tile-size').value;
  const spec = {
    kind: 'compare',
    scene: { name: $('tile-scene').value, width: n, height: n },
    reference: { spp: +$('tile-ref').value },
    patterns: keys.map((k) => patterns.get(k)),
  };
  $('cmp-start').disabled = true;
  try {
    const r = await apiPost('/v1/jobs', spec);
    $('cmp-status').textContent = `comparison job ${r.id} queued`;
    pollComparison(r.id, keys);
  } catch (e) {
    $('cmp-status').textContent = `comparison not started: ${e.message}`;
    $('cmp-start').disabled = false;
  }
}

async function pollComparison(id, keys) {
  try {
    const j = await loadJob(id);
    $('cmp-status').textContent = `comparison job ${id}: ${j.state} (${Math.round(j.progress * 100)}%)`;
    if (ACTIVE_STATES.has(j.state)) {
      cmpTimer = setTimeout(() => pollComparison(id, keys), 700);
      return;
    }
    $('cmp-start').disabled = false;
    if (j.state === 'done') showComparison(comparisonRows(j.result), comparisonPrediction(j.result));
    else if (j.error) $('cmp-status').textContent += `: ${j.error}`;
  } catch (e) {
    $('cmp-status').textContent = `comparison job ${id}: ${e.message}`;
    $('cmp-start').disabled = false;
  }
}

function showComparison(rows, prediction) {
  drawComparison({ plot: $('cmp-plot'), plotE2: $('cmp-plot-e2'), legend: $('cmp-legend'), tableHolder: $('cmp-table-holder'), tableId: 'cmp-table', rows, prediction });
}
