// The Tiles view's prediction (docs/predict.md): POST /v1/predict for the tile's pattern and
// scene, shown beside the measured RMSE, with the scene's edge histogram L(θ) and the pattern's
// unweighted E1(θ) as polar plots and the angles that cost most with this pattern. The
// prediction renders nothing, so it is asked for whenever the scene or the pattern changes;
// the ratio to the measured RMSE is shown only while both belong to the same tile.

import { apiPost } from '../api.js';
import { predictionFrom, predictionRatio, costliestAngles, fmt, fmtShare } from '../model.js';
import { drawPolar } from '../polar-plot.js';

const $ = (id) => document.getElementById(id);
const TOP_ANGLES = 6;

let seq = 0; // the latest request; older answers are dropped
let predicted = null; // { key, p }
let measured = null; // { key, rmse }

/* The tile a request describes: scene, size and pattern (the reference filter is the default). */
export function tileKey(body) {
  return JSON.stringify([body.scene, body.pattern]);
}

/* Asks for the prediction of a render request's tile and shows it. Never throws: a failure is
 * shown in the view, naming the field the daemon names. */
export async function predictTile(renderBody) {
  const mine = ++seq;
  const key = tileKey(renderBody);
  predicted = null;
  $('tile-pred-status').classList.remove('error-text');
  $('tile-pred-status').textContent = 'predicting…';
  $('tile-pred').dataset.state = 'loading';
  showFigures();
  try {
    const r = await apiPost('/v1/predict', { scene: renderBody.scene, pattern: renderBody.pattern, reference: renderBody.reference, e1_by_angle: true });
    if (mine !== seq) return;
    const p = predictionFrom(r);
    if (!p) throw new Error('the answer holds no prediction');
    predicted = { key, p };
    const sc = renderBody.scene;
    $('tile-pred-status').textContent = `${sc.name}, ${sc.width}×${sc.height}, ${p.filter || 'default'} reference filter`;
    $('tile-pred').dataset.state = 'done';
    showFigures();
    drawPlots(p);
    showAngles(p);
  } catch (e) {
    if (mine !== seq) return;
    $('tile-pred-status').classList.add('error-text');
    $('tile-pred-status').textContent = `prediction failed: ${e.message}`;
    $('tile-pred').dataset.state = 'failed';
    clearPlots();
  }
}

/* The measured RMSE of a finished render of renderBody's tile. */
export function setMeasured(renderBody, rmse) {
  measured = { key: tileKey(renderBody), rmse };
  showFigures();
}

function showFigures() {
  const p = predicted ? predicted.p : null;
  const same = p && measured && measured.key === predicted.key;
  $('tile-pred-rmse').textContent = p ? fmt(p.rmse, 3) : '—';
  const ratio = same ? predictionRatio(measured.rmse, p.rmse) : null;
  $('tile-pred-ratio').textContent = ratio == null ? '—' : fmt(ratio, 3);
  $('tile-pred-ratio').title = same ? '' : 'render this tile to compare';
  $('tile-pred-locked').textContent = p ? (p.lockedShare > 0 ? `${fmtShare(p.lockedShare)} of the predicted error` : 'none') : '—';
  $('tile-pred-subpixel').textContent = p
    ? p.subpixelAreaShare > 0
      ? `${fmtShare(p.subpixelAreaShare)} of the image${p.subpixelEstimated ? '' : ', its error not predicted'}`
      : 'none'
    : '—';
}

function clearPlots() {
  for (const id of ['tile-polar-edges', 'tile-polar-e1', 'tile-pred-angles']) $(id).replaceChildren();
}

function argmaxOf(values) {
  let best = null;
  values.forEach((v, d) => {
    if (v != null && v > 0 && (!best || v > best.value)) best = { kernel: null, angle: d, value: v };
  });
  return best;
}

function drawPlots(p) {
  if (p.edgeLength) {
    drawPolar($('tile-polar-edges'), {
      title: 'Scene: edge length L(θ)',
      series: [{ points: p.edgeLength.map((r, d) => ({ angle: d, r })) }],
      argmax: argmaxOf(p.edgeLength),
      valueLabel: `${fmt(p.totalLength, 0)} px in all`,
    });
  } else $('tile-polar-edges').textContent = 'no edge histogram in the answer';
  // The scene's costliest angles are marked on the pattern's curve.
  const marks = costliestAngles(p.angles, TOP_ANGLES).top.filter((a) => a.e1 != null).map((a) => ({ angle: a.angle, r: a.e1, label: `${a.angle}°: ${fmtShare(a.share)} of the predicted error` }));
  if (p.e1ByAngle) {
    drawPolar($('tile-polar-e1'), {
      title: 'Pattern: E1(θ), RMS over kernels',
      series: [{ points: p.e1ByAngle.map((r, d) => ({ angle: d, r })) }],
      argmax: argmaxOf(p.e1ByAngle),
      marks,
    });
  } else $('tile-polar-e1').textContent = 'no per-angle E1 in the answer';
}

/* The angles that cost most, as bars of their share of the predicted squared error. */
function showAngles(p) {
  const { top, rest, restCount } = costliestAngles(p.angles, TOP_ANGLES);
  const table = document.createElement('table');
  table.className = 'data';
  table.id = 'tile-pred-angles-table';
  table.createCaption().textContent = 'Costliest angles with this pattern';
  const head = table.createTHead().insertRow();
  for (const h of ['Normal angle', 'Share of predicted error', 'L (px)', 'E1 RMS']) {
    const th = document.createElement('th');
    th.scope = 'col';
    th.textContent = h;
    head.appendChild(th);
  }
  const body = table.createTBody();
  const row = (cells, share) => {
    const tr = body.insertRow();
    cells.forEach((c, i) => {
      const td = tr.insertCell();
      if (i === 1) {
        const bar = document.createElement('span');
        bar.className = 'share-bar';
        bar.style.width = `${Math.max(0, Math.min(1, share ?? 0)) * 100}%`;
        bar.setAttribute('aria-hidden', 'true');
        const holder = document.createElement('span');
        holder.className = 'share-track';
        holder.appendChild(bar);
        td.append(holder, ` ${c}`);
      } else {
        td.textContent = c;
        if (i > 1) td.className = 'num';
      }
    });
    return tr;
  };
  for (const a of top) row([`${a.angle}°`, fmtShare(a.share), fmt(a.length, 1), fmt(a.e1, 4)], a.share).dataset.angle = a.angle;
  if (restCount) row([`${restCount} other angle${restCount === 1 ? '' : 's'}`, fmtShare(rest), '', ''], rest);
  if (!top.length) row(['no edges', '—', '', ''], 0);
  $('tile-pred-angles').replaceChildren(table);
}
