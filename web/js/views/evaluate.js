// Evaluate: pick or paste a pattern, see it drawn, drag samples, watch E2 and the per-angle
// error (POST /v1/evaluate with detail) update.

import { apiPost } from '../api.js';
import { normEvaluation, jobPattern, fmt, acuityLabel } from '../model.js';
import { loadPresets, findPreset, loadFilters, loadAcuity, loadJob } from '../store.js';
import { PatternView } from '../pattern-view.js';
import { drawableOf, kernelsOf, clonePattern } from '../pattern-geometry.js';
import { drawPolar, polarLegend, polarKernelPicker } from '../polar-plot.js';
import { setEvaluatePatternGetter } from './evaluate-bridge.js';
import { initAnalysisPanel, cancelAnalysis, analysisAfterEvaluate, analysisEvaluateFailed } from './analysis-panel.js';

const $ = (id) => document.getElementById(id);

const state = {
  presetName: null, // the preset the pattern came from (unedited: sent as {preset})
  edited: false,
  pattern: null, // the wire pattern, drawable or not
  source: '',
  filters: [],
  inFlight: false,
  pending: false,
  lastEvaluation: null,
  seq: 0,
};
let view = null;
let ctx = null;

export async function init(context) {
  ctx = context;
  // Listeners first and once: a failed load below (a wrong token, a stopped daemon) makes main.js
  // call init again, which then only loads the menus.
  if (!view) setupControls();
  await loadMenus();
}

function setupControls() {
  setEvaluatePatternGetter(() => (state.pattern ? (state.edited || !state.presetName ? clonePattern(state.pattern) : { preset: state.presetName }) : null));
  view = new PatternView($('ev-pattern'), {
    editable: true,
    label: 'Samples of the pixel and its neighbours',
    onChange: () => {
      markEdited();
      requestEvaluation();
    },
    onCommit: () => {
      writeJson();
      requestEvaluation();
    },
  });
  $('ev-preset').addEventListener('change', () => {
    if ($('ev-preset').value !== '__custom') ctx.navigate('evaluate', { preset: $('ev-preset').value });
  });
  $('ev-filter').addEventListener('change', () => {
    fillFilterParams();
    requestEvaluation();
  });
  $('ev-acuity').addEventListener('change', () => {
    describeAcuity();
    requestEvaluation();
  });
  $('ev-kernel').addEventListener('change', () => {
    const d = drawableOf(state.pattern);
    if (d) view.setPattern(d.pattern, +$('ev-kernel').value);
  });
  $('ev-keep-sites').addEventListener('change', () => (view.keepSites = $('ev-keep-sites').checked));
  $('ev-reset').addEventListener('click', () => state.presetName && usePreset(state.presetName));
  $('ev-apply').addEventListener('click', applyJson);
  $('ev-normalize').addEventListener('click', normalizeAndEvaluate);
  initAnalysisPanel();
}

/* One sentence on the selected table (GET /v1/acuity's description). */
function describeAcuity() {
  const t = (state.acuityTables || []).find((x) => x.name === $('ev-acuity').value);
  $('ev-acuity-hint').textContent = t ? t.description : '';
}

async function loadMenus() {
  const [presets, filters, acuity] = await Promise.all([loadPresets(), loadFilters(), loadAcuity()]);
  fillPresets(presets);
  state.filters = filters;
  const fsel = $('ev-filter');
  fsel.replaceChildren(...filters.map((f) => new Option(f.name, f.name)));
  const def = filters.find((f) => f.isDefault);
  if (def) fsel.value = def.name;
  state.defaultFilter = def ? def.name : '';
  fillFilterParams();
  state.acuityTables = acuity.tables || acuity.names.map((name) => ({ name, description: '' }));
  $('ev-acuity').replaceChildren(...state.acuityTables.map((t) => new Option(acuityLabel(t), t.name)));
  $('ev-acuity').value = acuity.default || acuity.names[0] || '';
  state.defaultAcuity = acuity.default;
  describeAcuity();
}

export async function show(params) {
  if (params.preset) await usePreset(params.preset);
  else if (params.job) await useJob(params.job, params);
  else if (state.pattern && $('ev-status').classList.contains('error-text')) requestEvaluation();
  else if (!state.pattern) {
    const presets = await loadPresets();
    const first = presets.find((p) => p.name === 'quincunx') || presets[0];
    if (first) await usePreset(first.name);
  }
}

function fillPresets(presets) {
  const sel = $('ev-preset');
  const groups = new Map();
  for (const p of presets) {
    if (!groups.has(p.family)) groups.set(p.family, []);
    groups.get(p.family).push(p);
  }
  const nodes = [];
  for (const [family, list] of groups) {
    const g = document.createElement('optgroup');
    g.label = family || 'other';
    for (const p of list) g.appendChild(new Option(`${p.name}${p.cost_spp != null ? ` (${p.cost_spp} spp)` : ''}`, p.name));
    nodes.push(g);
  }
  sel.replaceChildren(...nodes, new Option('custom', '__custom'));
}

function fillFilterParams() {
  const f = state.filters.find((x) => x.name === $('ev-filter').value);
  const box = $('ev-filter-params');
  box.replaceChildren();
  for (const [k, v] of Object.entries((f && f.params) || {})) {
    if (k === 'radius' && f.name !== 'gaussian') continue;
    const id = `ev-fp-${k}`;
    const label = document.createElement('label');
    label.htmlFor = id;
    label.textContent = k;
    const input = document.createElement('input');
    input.type = 'number';
    input.step = 'any';
    input.id = id;
    input.dataset.param = k;
    input.value = String(+v.toPrecision(6));
    input.defaultValue = input.value;
    input.addEventListener('change', requestEvaluation);
    box.append(label, input);
  }
}

async function usePreset(name) {
  const p = await findPreset(name);
  if (!p) {
    ctx.toast(`no preset named ${name}`);
    return;
  }
  state.presetName = name;
  state.edited = false;
  state.pattern = clonePattern(p.pattern);
  state.source = p.source + (p.note ? ` — ${p.note}` : '');
  $('ev-preset').value = name;
  $('ev-preset-source').textContent = state.source;
  setPatternView();
  writeJson();
  requestEvaluation();
}

async function useJob(id, { rank, pick } = {}) {
  const job = await loadJob(id);
  const pattern = jobPattern(job, { rank, pick });
  if (!pattern) {
    ctx.toast(`job ${id} has no such pattern (yet)`);
    return;
  }
  const what = rank != null ? `configuration ranked ${rank} of job ${id}` : pick === 'opt_w' ? `Opt W of job ${id}` : pick === 'opt_wp' ? `Opt W+P of job ${id}` : `best pattern of job ${id}`;
  state.presetName = null;
  state.edited = true;
  state.pattern = clonePattern(pattern);
  $('ev-preset').value = '__custom';
  $('ev-preset-source').textContent = `${what} (${job.family || job.kind})`;
  setPatternView();
  writeJson();
  requestEvaluation();
}

function setPatternView() {
  const d = drawableOf(state.pattern);
  $('ev-pattern').classList.toggle('undrawable', !d);
  const count = d ? kernelsOf(d.pattern).length : 1;
  $('ev-kernel').replaceChildren(...Array.from({ length: count }, (_, k) => new Option(`kernel ${k} (of ${count})`, k)));
  $('ev-kernel').disabled = count < 2 || Array.isArray(state.pattern.mirrored);
  view.editable = !!d && !d.readOnly;
  if (d) view.setPattern(d.pattern, 0);
  else view.svg.replaceChildren();
}

function markEdited() {
  if (!state.edited) {
    state.edited = true;
    $('ev-preset').value = '__custom';
    $('ev-preset-source').textContent = state.presetName ? `edited from ${state.presetName}` : 'edited';
  }
}

/* The JSON box shows one sample per line, which is easier to edit than a single line. */
function writeJson() {
  const p = state.pattern;
  if (!p) return;
  const line = (s) => `[${s.map((v) => +v.toFixed(6)).join(', ')}]`;
  const norm = p.normalize ? ', "normalize": true' : '';
  let txt;
  if (Array.isArray(p.mirrored)) txt = `{"mirrored": [\n  ${p.mirrored.map(line).join(',\n  ')}\n]${norm}}`;
  else if (Array.isArray(p.kernels)) txt = `{"kernels": [\n${p.kernels.map((k) => `  [\n    ${k.map(line).join(',\n    ')}\n  ]`).join(',\n')}\n]${norm}}`;
  else txt = JSON.stringify(p, null, 1);
  $('ev-json').value = txt;
}

function applyJson() {
  let p;
  try {
    p = JSON.parse($('ev-json').value);
  } catch (e) {
    setStatus(`not valid JSON: ${e.message}`, true);
    return;
  }
  if (p && p.pattern) p = p.pattern;
  state.pattern = p;
  state.presetName = typeof p.preset === 'string' ? p.preset : null;
  state.edited = !state.presetName;
  $('ev-preset').value = state.presetName || '__custom';
  $('ev-preset-source').textContent = 'pasted pattern';
  setPatternView();
  requestEvaluation();
}

function currentFilter() {
  const name = $('ev-filter').value;
  if (!name) return null;
  const f = { name };
  let changed = name !== state.defaultFilter;
  for (const input of $('ev-filter-params').querySelectorAll('input')) {
    const v = Number(input.value);
    if (Number.isFinite(v)) f[input.dataset.param] = v;
    if (input.value !== input.defaultValue) changed = true;
  }
  return changed ? f : null; // the server's default filter otherwise, as the API documents
}

function requestBody() {
  const body = {
    pattern: state.edited || !state.presetName ? state.pattern : { preset: state.presetName },
    detail: true,
  };
  const f = currentFilter();
  if (f) body.filter = f;
  const a = $('ev-acuity').value;
  if (a && a !== state.defaultAcuity) body.acuity = { name: a };
  return body;
}

/* At most one request in flight; moves made meanwhile coalesce into one follow-up request. */
function requestEvaluation() {
  if (state.inFlight) {
    state.pending = true;
    return;
  }
  state.inFlight = true;
  state.pending = false;
  const seq = ++state.seq;
  setStatus('evaluating…');
  cancelAnalysis(); // the analysis panel asks for its figures after this evaluation, not during it
  const body = requestBody();
  apiPost('/v1/evaluate', body)
    .then((resp) => {
      if (seq === state.seq) showEvaluation(normEvaluation(resp));
      setStatus('');
      if (seq === state.seq && !state.pending) analysisAfterEvaluate(body.pattern);
    })
    .catch((e) => {
      if (seq === state.seq) clearEvaluation();
      if (seq === state.seq) analysisEvaluateFailed();
      setStatus(e.message, true);
      // The daemon's message for a weight sum off 1 names it; the pattern may then be rescaled.
      $('ev-normalize').hidden = !/weights sum to/.test(e.message) || !state.pattern || typeof state.pattern !== 'object';
    })
    .finally(() => {
      state.inFlight = false;
      if (state.pending) requestEvaluation();
    });
}

/* An error leaves nothing of the previous pattern's result on screen. */
function clearEvaluation() {
  state.lastEvaluation = null;
  const out = $('ev-e2');
  out.textContent = '—';
  out.dataset.e2 = '';
  out.title = 'no result: see the message below';
  for (const id of ['ev-argmax', 'ev-family', 'ev-cost']) $(id).textContent = '—';
  for (const id of ['ev-polar-weighted', 'ev-polar-e1', 'ev-polar-legend']) $(id).replaceChildren();
}

/* Asks the daemon to rescale each kernel's weights to a sum of 1 ("normalize": true). */
function normalizeAndEvaluate() {
  if (!state.pattern || typeof state.pattern !== 'object') return;
  state.pattern = { ...state.pattern, normalize: true };
  state.edited = true;
  $('ev-preset').value = '__custom';
  $('ev-preset-source').textContent = 'weights rescaled to sum 1 per kernel (normalize)';
  writeJson();
  requestEvaluation();
}

function setStatus(msg, error = false) {
  if (!error) $('ev-normalize').hidden = true;
  const s = $('ev-status');
  s.textContent = msg;
  s.classList.toggle('error-text', error);
  $('ev-e2').setAttribute('aria-busy', String(msg === 'evaluating…'));
}

function showEvaluation(ev) {
  state.lastEvaluation = ev;
  const out = $('ev-e2');
  out.textContent = fmt(ev.e2, 6);
  out.dataset.e2 = ev.e2 == null ? '' : String(ev.e2);
  out.title = ev.e2 == null ? '' : String(ev.e2);
  $('ev-argmax').textContent = ev.argmaxAngle == null ? '—' : `kernel ${ev.argmaxKernel}, θ = ${ev.argmaxAngle}°`;
  $('ev-family').textContent = ev.family || '—';
  $('ev-cost').textContent = ev.cost == null ? '—' : String(ev.cost);
  const kernels = ev.kernels;
  if (!kernels.length) {
    $('ev-polar-weighted').textContent = 'the server returned no per-angle detail';
    $('ev-polar-e1').textContent = '';
    return;
  }
  // The kernel picker redraws the plots with the one kernel chosen (or all).
  const only = polarKernelPicker($('ev-polar-kernel'), kernels.length, () => showEvaluation(ev));
  drawPolar($('ev-polar-weighted'), {
    only,
    title: 'W(θ)·E1(θ)',
    series: kernels.map((rows) => ({ points: rows.map((r) => ({ angle: r.angle, r: r.weighted })) })),
    argmax: ev.argmaxAngle == null ? null : { kernel: ev.argmaxKernel, angle: ev.argmaxAngle, value: ev.e2 },
  });
  let best = null;
  kernels.forEach((rows, k) => rows.forEach((r) => {
    if (r.e1 != null && (!best || r.e1 > best.value)) best = { kernel: k, angle: r.angle, value: r.e1 };
  }));
  drawPolar($('ev-polar-e1'), {
    only,
    title: 'E1(θ)',
    series: kernels.map((rows) => ({ points: rows.map((r) => ({ angle: r.angle, r: r.e1 })) })),
    argmax: best,
  });
  polarLegend($('ev-polar-legend'), kernels.length);
}
