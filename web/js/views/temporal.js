// Temporal: a TAA jitter sequence under a blend (issue 30, docs/temporal.md), evaluated by
// POST /v1/evaluate as one kernel per phase. Pick a temporal preset or paste JSON; see the
// sequence with its frame numbers, E2 per phase, the W·E1 polar beside the flicker W·F1 polar and
// the E2 after a cut; the α slider re-evaluates live (debounced; a newer request aborts the one
// in flight, so an old answer never overwrites a newer one).

import { apiGet, apiPost } from '../api.js';
import { el, text, clear, COLOURS, niceTicks, enlargeSmallText } from '../svg.js';
import { drawPolar } from '../polar-plot.js';

/* The daemon's temporal presets (proto/temporal_presets.c; no route lists them yet). Each answer
 * carries its preset's provenance, shown under the menu. */
export const TEMPORAL_PRESETS = ['halton23-8', 'halton23-16', 'fsr2-1.5x', 'fsr2-1.7x', 'fsr2-2x', 'fsr2-3x', 'urp-like', 'filament-rgss4', 'filament-halton8', 'filament-halton16', 'filament-halton32'];
const DEFAULT_PRESET = 'halton23-8';
const DEBOUNCE_MS = 150;

const $ = (id) => document.getElementById(id);

const state = {
  preset: DEFAULT_PRESET, // the preset shown, or null for pasted JSON (custom)
  custom: null, // the pasted temporal object
  blendTouched: false, // the blend controls override the preset's or the JSON's blend
  controller: null, // the AbortController of the request in flight
  timer: null,
  seq: 0,
  result: null,
  built: false,
  job: null, // the job whose best sequence was last opened (?job=ID)
};
let ctx = null;

export async function init(context) {
  ctx = context;
  if (!state.built) build();
}

export async function show(params) {
  // ?job=ID: a temporal-optimize job's best sequence (its detail's "Open in Temporal").
  if (params.job && params.job !== state.job) {
    state.job = params.job;
    try {
      const j = await apiGet(`/v1/jobs/${encodeURIComponent(params.job)}`);
      const t = j.result && j.result.best && j.result.best.temporal;
      if (!t) throw new Error(`job ${params.job} has no best sequence`);
      loadCustom(t, `best sequence of job ${params.job}`);
    } catch (e) {
      ctx.toast(`cannot open job ${params.job}: ${e.message}`);
    }
    return;
  }
  const wanted = params.preset && TEMPORAL_PRESETS.includes(params.preset) ? params.preset : null;
  if (params.preset && !wanted) ctx.toast(`no temporal preset named ${params.preset}`);
  if (wanted && (wanted !== state.preset || state.custom)) selectPreset(wanted);
  else if (state.controller) return; // an answer is on its way
  else if (!state.result) evaluateNow(); // first visit, or retry after an error
  else draw(state.result); // sizes may have changed while hidden: labels are sized to the screen
}

export function hide() {
  clearTimeout(state.timer);
}

function build() {
  state.built = true;
  const root = $('view-temporal');
  // Static markup only; every value from the daemon or the user goes in through textContent.
  root.innerHTML = `
    <div class="temporal-grid">
      <div class="panel controls">
        <h2>Jitter sequence</h2>
        <label for="tp-preset">Temporal preset</label>
        <select id="tp-preset"></select>
        <p id="tp-source" class="hint"></p>
        <details id="tp-paste">
          <summary>Paste or edit temporal JSON</summary>
          <textarea id="tp-json" rows="9" spellcheck="false" aria-describedby="tp-json-hint"></textarea>
          <p id="tp-json-hint" class="hint">A temporal pattern as in the API (docs/api.md): <code>{"jitter":[[x,y],…],"blend":{"kind":"exponential","alpha":0.1}}</code>, a generator <code>{"jitter":{"generator":"halton","count":8}}</code> or a preset with overrides. Offsets in pixels from the pixel centre, x right, y up.</p>
          <button type="button" id="tp-apply">Evaluate this JSON</button>
        </details>
        <h2>Blend</h2>
        <label for="tp-blend">History blend</label>
        <select id="tp-blend">
          <option value="exponential">exponential (α)</option>
          <option value="box">box (1/N each)</option>
        </select>
        <label for="tp-alpha">α = <output id="tp-alpha-out" for="tp-alpha">0.10</output></label>
        <input type="range" id="tp-alpha" min="0.01" max="1" step="0.01" value="0.1" aria-describedby="tp-alpha-hint">
        <p id="tp-alpha-hint" class="hint">The frame j frames old weighs α(1−α)<sup>j</sup>/(1−(1−α)<sup>N</sup>). Moving the slider re-evaluates.</p>
      </div>
      <div class="panel results">
        <h2>Result</h2>
        <dl class="figures">
          <dt>E2, worst phase</dt><dd><output id="tp-e2" class="big" data-e2="">—</output></dd>
          <dt>argmax</dt><dd id="tp-argmax">—</dd>
          <dt>mean over phases</dt><dd id="tp-mean" data-value="">—</dd>
          <dt>flicker F2</dt><dd id="tp-f2" data-value="">—</dd>
          <dt>frames to 5 %</dt><dd id="tp-frames" data-value="">—</dd>
          <dt>phases, effective samples</dt><dd id="tp-phases">—</dd>
        </dl>
        <p id="tp-status" class="status" role="status" aria-live="polite"></p>
        <div class="tp-plots">
          <figure><div id="tp-sequence"></div><figcaption>The offsets in the pixel [−½, ½]² (x right, y up), numbered by frame; orange: the newest frame of the worst phase</figcaption></figure>
          <figure><div id="tp-phase-e2"></div><figcaption>E2 per phase (the phase's newest frame); orange: the worst, dashed: the mean</figcaption></figure>
          <figure><div id="tp-after-cut"></div><figcaption>E2 after k frames since a cut; grey band: ±5 % of the worst phase's steady state, dotted: frames to 5 %</figcaption></figure>
        </div>
        <div class="polars tp-polars">
          <figure><div id="tp-polar-e1"></div><figcaption>W(θ)·E1(θ): the worst phase (solid) and the mean over phases (dashed); ring = E2</figcaption></figure>
          <figure><div id="tp-polar-f1"></div><figcaption>Flicker W(θ)·F1(θ) between the phases; ring = F2</figcaption></figure>
        </div>
      </div>
    </div>`;
  $('tp-preset').replaceChildren(...TEMPORAL_PRESETS.map((n) => new Option(n, n)), new Option('custom (JSON)', '__custom'));
  $('tp-preset').value = state.preset;
  $('tp-preset').addEventListener('change', () => {
    const v = $('tp-preset').value;
    if (v === '__custom') {
      $('tp-paste').open = true;
      $('tp-json').focus();
    } else {
      // The URL may already name it (after pasted JSON): no hashchange then, so select it here.
      if (v !== state.preset || state.custom) selectPreset(v);
      ctx.navigate('temporal', { preset: v });
    }
  });
  $('tp-alpha').addEventListener('input', () => {
    state.blendTouched = true;
    if ($('tp-blend').value !== 'exponential') $('tp-blend').value = 'exponential';
    showAlpha();
    scheduleEvaluation();
  });
  $('tp-blend').addEventListener('change', () => {
    state.blendTouched = true;
    showAlpha();
    scheduleEvaluation(0);
  });
  $('tp-apply').addEventListener('click', applyJson);
  let resizeTimer = null;
  window.addEventListener('resize', () => {
    clearTimeout(resizeTimer);
    resizeTimer = setTimeout(() => !$('view-temporal').hidden && state.result && draw(state.result), 200);
  });
}

function showAlpha() {
  const box = $('tp-blend').value === 'box';
  $('tp-alpha').disabled = box;
  $('tp-alpha-out').textContent = box ? '— (box)' : Number($('tp-alpha').value).toFixed(2);
  $('tp-alpha').setAttribute('aria-valuetext', box ? 'not used by the box blend' : `alpha ${$('tp-alpha').value}`);
}

function selectPreset(name) {
  state.preset = name;
  state.custom = null;
  state.blendTouched = false;
  $('tp-preset').value = name;
  $('tp-source').textContent = '';
  evaluateNow();
}

/* The temporal object sent: the preset or the pasted JSON, with the blend controls over it once
 * they were touched. */
export function temporalObject() {
  const t = state.custom ? JSON.parse(JSON.stringify(state.custom)) : { preset: state.preset };
  if (state.blendTouched) t.blend = $('tp-blend').value === 'box' ? { kind: 'box' } : { kind: 'exponential', alpha: Number($('tp-alpha').value) };
  return t;
}

function scheduleEvaluation(delay = DEBOUNCE_MS) {
  clearTimeout(state.timer);
  state.timer = setTimeout(evaluateNow, delay);
}

/* Drops the request in flight (its answer would be stale). */
function cancelPending() {
  clearTimeout(state.timer);
  state.seq++;
  if (state.controller) state.controller.abort();
  state.controller = null;
}

async function evaluateNow() {
  cancelPending();
  const seq = state.seq;
  const controller = new AbortController();
  state.controller = controller;
  const t = temporalObject();
  if (document.activeElement !== $('tp-json')) $('tp-json').value = JSON.stringify(t, null, 1);
  setStatus('evaluating…');
  try {
    const answer = await apiPost('/v1/evaluate', { pattern: { temporal: t } }, { signal: controller.signal });
    if (seq !== state.seq) return;
    state.result = answer;
    syncBlend(answer.blend);
    draw(answer);
    setStatus('');
  } catch (e) {
    if ((e && e.name === 'AbortError') || seq !== state.seq) return;
    clearResult();
    setStatus(e.message, true);
  } finally {
    if (seq === state.seq) state.controller = null;
  }
}

/* The controls show the blend evaluated, unless the user has set them. */
function syncBlend(blend) {
  if (state.blendTouched || !blend) return;
  $('tp-blend').value = blend.kind === 'box' ? 'box' : 'exponential';
  if (blend.kind !== 'box' && typeof blend.alpha === 'number') $('tp-alpha').value = String(blend.alpha);
  showAlpha();
}

function applyJson() {
  let doc;
  try {
    doc = JSON.parse($('tp-json').value);
  } catch (e) {
    cancelPending();
    clearResult();
    setStatus(`not valid JSON: ${e.message}`, true);
    return;
  }
  if (doc && typeof doc === 'object' && doc.pattern && typeof doc.pattern === 'object') doc = doc.pattern;
  if (doc && typeof doc === 'object' && doc.temporal && typeof doc.temporal === 'object') doc = doc.temporal;
  if (!doc || typeof doc !== 'object' || Array.isArray(doc)) {
    cancelPending();
    clearResult();
    setStatus('the temporal pattern is a JSON object: {"jitter": …} or {"preset": …}', true);
    return;
  }
  loadCustom(doc, 'pasted JSON');
}

function loadCustom(doc, source) {
  state.custom = doc;
  state.preset = null;
  state.blendTouched = false;
  $('tp-json').value = JSON.stringify(doc, null, 1);
  $('tp-preset').value = '__custom';
  $('tp-source').textContent = source;
  evaluateNow();
}

function setStatus(msg, error = false) {
  const s = $('tp-status');
  s.textContent = msg;
  s.classList.toggle('error-text', error);
  $('tp-e2').setAttribute('aria-busy', String(msg === 'evaluating…'));
}

/* An error leaves nothing of an earlier result on screen. */
function clearResult() {
  state.result = null;
  const out = $('tp-e2');
  out.textContent = '—';
  out.dataset.e2 = '';
  out.dataset.alpha = '';
  for (const id of ['tp-argmax', 'tp-phases']) $(id).textContent = '—';
  for (const id of ['tp-mean', 'tp-f2', 'tp-frames']) {
    $(id).textContent = '—';
    $(id).dataset.value = '';
  }
  for (const id of ['tp-sequence', 'tp-phase-e2', 'tp-after-cut', 'tp-polar-e1', 'tp-polar-f1']) clear($(id));
}

const fixed = (v, d) => (typeof v === 'number' && Number.isFinite(v) ? v.toFixed(d) : '—');

/* The largest of each angle over the groups (output pixels) of one [group][angle] table. */
function maxOverGroups(rows) {
  const out = rows[0] ? rows[0].slice() : [];
  for (const row of rows.slice(1)) row.forEach((v, i) => (out[i] = Math.max(out[i], v)));
  return out;
}

function draw(r) {
  const out = $('tp-e2');
  out.textContent = fixed(r.e2, 6);
  out.dataset.e2 = String(r.e2);
  out.dataset.alpha = r.blend && r.blend.kind === 'exponential' ? String(r.blend.alpha) : 'box';
  out.title = String(r.e2);
  const am = r.argmax || {};
  $('tp-argmax').textContent = `phase ${am.phase}${r.group_count > 1 ? `, pixel ${am.group}` : ''}, θ = ${am.angle_deg}°`;
  const set = (id, v, text) => {
    $(id).textContent = text;
    $(id).dataset.value = v == null ? 'null' : String(v);
  };
  set('tp-mean', r.mean_phase_e2, fixed(r.mean_phase_e2, 6));
  set('tp-f2', r.f2, fixed(r.f2, 6));
  set('tp-frames', r.frames_to_5pct, r.frames_to_5pct == null ? `none within ${r.after_cut.length}` : String(r.frames_to_5pct));
  $('tp-phases').textContent = `${r.phase_count}, ${fixed(r.effective_samples, 2)}`;
  if (r.preset && r.preset.source) $('tp-source').textContent = r.preset.source;
  drawSequence($('tp-sequence'), r);
  drawPhaseBars($('tp-phase-e2'), r);
  drawAfterCut($('tp-after-cut'), r);
  drawPolars(r);
}

/* Text boxes already placed in one SVG, so labels that would overprint are left out (their
 * value stays in a tooltip). Boxes in viewBox units; digits ~0.6 em wide. */
function labelPlacer() {
  const placed = [];
  return (x, y, str, size, anchor = 'start') => {
    const w = 0.62 * size * str.length;
    const x0 = anchor === 'middle' ? x - w / 2 : anchor === 'end' ? x - w : x;
    const box = { x0, x1: x0 + w, y0: y - size, y1: y + 2 };
    if (placed.some((p) => box.x0 < p.x1 && p.x0 < box.x1 && box.y0 < p.y1 && p.y0 < box.y1)) return false;
    placed.push(box);
    return true;
  };
}

/* The sequence r.jitter drawn in its pixel with frame numbers (r.argmax.phase larger); also the
 * temporal-optimize job detail's. */
export function drawSequence(holder, r) {
  clear(holder);
  const S = 320;
  const M = 26;
  const svg = el('svg', { viewBox: `0 0 ${S} ${S}`, class: 'tp-svg', role: 'img' }, holder);
  const offs = r.jitter || [];
  const half = Math.max(0.5, ...offs.map(([x, y]) => Math.max(Math.abs(x), Math.abs(y))));
  const sc = (S / 2 - M) / half;
  const X = (x) => S / 2 + x * sc;
  const Y = (y) => S / 2 - y * sc;
  svg.setAttribute('aria-label', `jitter sequence of ${offs.length} frames`);
  el('rect', { x: X(-0.5), y: Y(0.5), width: sc, height: sc, class: 'tp-pixel' }, svg);
  el('path', { d: `M${X(0) - 6},${Y(0)}h12M${X(0)},${Y(0) - 6}v12`, class: 'px-origin' }, svg);
  if (offs.length > 1) el('path', { d: offs.map(([x, y], i) => `${i ? 'L' : 'M'}${X(x).toFixed(1)},${Y(y).toFixed(1)}`).join('') + 'Z', class: 'tp-order' }, svg);
  const worst = r.argmax ? r.argmax.phase : -1;
  const fits = labelPlacer();
  const size = 13;
  offs.forEach(([x, y], f) => {
    const g = el('g', { class: `tp-frame${f === worst ? ' tp-worst' : ''}`, 'data-frame': f }, svg);
    el('circle', { cx: X(x), cy: Y(y), r: f === worst ? 6.5 : 4.5 }, g);
    el('title', {}, g).textContent = `frame ${f}: (${x.toFixed(4)}, ${y.toFixed(4)})`;
    const lx = X(x) + 7;
    const ly = Y(y) - 5;
    if (fits(lx, ly, String(f), size)) text(g, lx, ly, String(f), { class: 'tp-label' });
  });
  enlargeSmallText(svg);
}

/* A value axis on the left (ticks and grid) and the plot frame; returns the y scale. */
function valueAxis(svg, box, hi, label) {
  const ticks = niceTicks(0, hi, 4);
  const top = Math.max(hi, ticks[ticks.length - 1]);
  const y = (v) => box.bottom - (v / top) * (box.bottom - box.top);
  for (const t of ticks) {
    el('line', { x1: box.left, x2: box.right, y1: y(t), y2: y(t), class: 'tp-grid' }, svg);
    text(svg, box.left - 6, y(t) + 4, String(+t.toPrecision(3)), { class: 'tp-tick', 'text-anchor': 'end' });
  }
  el('rect', { x: box.left, y: box.top, width: box.right - box.left, height: box.bottom - box.top, class: 'tp-frame-box' }, svg);
  text(svg, box.left - 6, box.top - 10, label, { class: 'tp-axis-label', 'text-anchor': 'start' });
  return y;
}

function drawPhaseBars(holder, r) {
  clear(holder);
  const W = 360;
  const H = 240;
  const box = { left: 52, right: W - 10, top: 30, bottom: H - 40 };
  const svg = el('svg', { viewBox: `0 0 ${W} ${H}`, class: 'tp-svg', role: 'img', 'aria-label': `E2 per phase; worst ${fixed(r.e2, 4)} in phase ${r.argmax && r.argmax.phase}` }, holder);
  const phases = (r.phases || []).slice().sort((a, b) => a.phase - b.phase);
  const n = phases.length;
  const y = valueAxis(svg, box, Math.max(1e-9, r.e2) * 1.1, 'E2');
  const slot = (box.right - box.left) / Math.max(1, n);
  const worst = r.argmax ? r.argmax.phase : -1;
  // One label every `step` phases, at least 30 units apart.
  const step = Math.max(1, Math.ceil(30 / slot));
  for (const p of phases) {
    const x = box.left + p.phase * slot;
    const bar = el('rect', { x: x + slot * 0.1, y: y(p.e2), width: slot * 0.8, height: box.bottom - y(p.e2), class: `tp-bar${p.phase === worst ? ' tp-worst' : ''}`, 'data-phase': p.phase, 'data-e2': p.e2 }, svg);
    el('title', {}, bar).textContent = `phase ${p.phase}: E2 ${p.e2.toFixed(6)}`;
    if (p.phase % step === 0) text(svg, x + slot / 2, box.bottom + 16, String(p.phase), { class: 'tp-tick', 'text-anchor': 'middle' });
  }
  if (typeof r.mean_phase_e2 === 'number') el('line', { x1: box.left, x2: box.right, y1: y(r.mean_phase_e2), y2: y(r.mean_phase_e2), class: 'tp-mean' }, svg);
  text(svg, (box.left + box.right) / 2, H - 6, 'phase (its newest frame)', { class: 'tp-axis-label', 'text-anchor': 'middle' });
  enlargeSmallText(svg);
}

function drawAfterCut(holder, r) {
  clear(holder);
  const W = 360;
  const H = 240;
  const box = { left: 52, right: W - 12, top: 30, bottom: H - 40 };
  const curve = r.after_cut || [];
  const K = curve.length;
  const svg = el('svg', { viewBox: `0 0 ${W} ${H}`, class: 'tp-svg', role: 'img', 'aria-label': `E2 after a cut over ${K} frames; within 5 % from frame ${r.frames_to_5pct ?? 'none'}` }, holder);
  if (!K) return;
  const y = valueAxis(svg, box, Math.max(1e-9, ...curve, r.e2) * 1.05, 'E2');
  const x = (k) => box.left + (K === 1 ? 0.5 : (k - 1) / (K - 1)) * (box.right - box.left);
  el('rect', { x: box.left, y: y(r.e2 * 1.05), width: box.right - box.left, height: Math.max(0, y(r.e2 * 0.95) - y(r.e2 * 1.05)), class: 'tp-band' }, svg);
  el('line', { x1: box.left, x2: box.right, y1: y(r.e2), y2: y(r.e2), class: 'tp-mean' }, svg);
  for (const t of niceTicks(1, K, 5).filter((t) => Number.isInteger(t) && t >= 1 && t <= K)) text(svg, x(t), box.bottom + 16, String(t), { class: 'tp-tick', 'text-anchor': 'middle' });
  if (r.frames_to_5pct != null) {
    const fx = x(r.frames_to_5pct);
    el('line', { x1: fx, x2: fx, y1: box.top, y2: box.bottom, class: 'tp-settle' }, svg);
    const right = fx > (box.left + box.right) / 2;
    text(svg, right ? fx - 4 : fx + 4, box.top + 14, `k = ${r.frames_to_5pct}`, { class: 'tp-tick tp-settle-label', 'text-anchor': right ? 'end' : 'start' });
  }
  el('path', { d: curve.map((v, i) => `${i ? 'L' : 'M'}${x(i + 1).toFixed(1)},${y(v).toFixed(1)}`).join(''), class: 'tp-curve' }, svg);
  if (K <= 128)
    curve.forEach((v, i) => {
      const c = el('circle', { cx: x(i + 1), cy: y(v), r: 2.5, class: 'tp-point', 'data-k': i + 1, 'data-e2': v }, svg);
      el('title', {}, c).textContent = `k = ${i + 1}: E2 ${v.toFixed(4)}`;
    });
  text(svg, (box.left + box.right) / 2, H - 6, 'frames since the cut (k)', { class: 'tp-axis-label', 'text-anchor': 'middle' });
  enlargeSmallText(svg);
}

function drawPolars(r) {
  const angles = r.angles_deg || [];
  const w = r.weights || [];
  const phases = (r.phases || []).slice().sort((a, b) => a.phase - b.phase);
  const worst = phases.find((p) => p.phase === (r.argmax && r.argmax.phase)) || phases[0];
  const weighted = (rows) => maxOverGroups(rows).map((v, i) => v * w[i]);
  const mean = angles.map((_, i) => phases.reduce((s, p) => s + weighted(p.e1)[i], 0) / Math.max(1, phases.length));
  const series = [
    { points: worst ? weighted(worst.e1).map((v, i) => ({ angle: angles[i], r: v })) : [] },
    { points: mean.map((v, i) => ({ angle: angles[i], r: v })) },
  ];
  const am = r.argmax || {};
  drawPolar($('tp-polar-e1'), { title: 'W·E1 per phase', series, argmax: { angle: am.angle_deg, value: r.e2, kernel: am.phase } });
  // polar-plot.js names the series kernels; here they are the worst phase and the mean.
  const label = $('tp-polar-e1').querySelector('.polar-argmax-label');
  if (label) label.textContent = `max ${r.e2.toFixed(3)} @ ${am.angle_deg}°, phase ${am.phase}`;
  const f1 = maxOverGroups(r.f1 || []).map((v, i) => ({ angle: angles[i], r: v * w[i] }));
  const fa = r.f2_argmax || {};
  drawPolar($('tp-polar-f1'), { title: 'flicker W·F1', series: [{ points: f1 }], argmax: fa.angle_deg == null ? null : { angle: fa.angle_deg, value: r.f2 } });
}
