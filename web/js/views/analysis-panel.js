// Evaluate's Analysis panel: the point-set figures of the pattern just evaluated
// (POST /v1/analyze, docs/analysis.md): the 2-D periodogram as an image, the radial spectrum with
// the anisotropy under it (as PSA draws them), the pair correlation function and a table of the
// discrepancies, spacing and spectral figures.
//
// It never slows Evaluate: a request goes out only a moment after an evaluation succeeded with
// no newer one pending, a new evaluation aborts it (AbortController), and a collapsed panel asks
// nothing until it is opened again.

import { apiPost } from '../api.js';
import { drawPeriodogram, powerOfTen } from '../periodogram-image.js';
import { drawLinePlot } from '../line-plot.js';

const $ = (id) => document.getElementById(id);
const OPEN_KEY = 'aalab.analysis.open';
/* Quiet time after an evaluation before the analysis is asked for: a drag evaluates every few
 * milliseconds, and each new evaluation cancels the wait. */
const SETTLE_MS = 150;

const st = {
  pattern: null, // the wire pattern of the last successful evaluation
  controller: null,
  timer: null,
  shownKey: null, // request the shown result answers (JSON), null when nothing is shown
  busyRetries: 0,
};

/* The inputs, the request fields they set and the per-field error line. */
const FIELDS = [
  { input: 'an-radius', field: 'spectrum.radius', error: 'an-radius-error' },
  { input: 'an-bins', field: 'pcf.bins', error: 'an-bins-error' },
];

export function initAnalysisPanel() {
  const details = $('ev-analysis');
  try {
    if (localStorage.getItem(OPEN_KEY) === 'false') details.open = false;
  } catch {
    /* storage disabled: open */
  }
  setState(details.open ? 'idle' : 'collapsed');
  details.addEventListener('toggle', () => {
    try {
      localStorage.setItem(OPEN_KEY, String(details.open));
    } catch {
      /* not kept */
    }
    if (!details.open) {
      cancelAnalysis();
      setState('collapsed');
    } else if (st.pattern) {
      // Drawn while collapsed nothing was laid out: draw (and ask, if stale) now.
      requestAnalysis();
    } else setState('idle');
  });
  $('an-form').addEventListener('submit', (e) => {
    e.preventDefault();
    requestAnalysis({ force: true });
  });
  for (const f of FIELDS) $(f.input).addEventListener('change', () => requestAnalysis());
  // Plot text is sized for the plots' scale on screen (at least 11 px): a new window size redraws.
  let resizeTimer = null;
  window.addEventListener('resize', () => {
    clearTimeout(resizeTimer);
    resizeTimer = setTimeout(() => details.open && !details.closest('[hidden]') && redraw(), 150);
  });
}

/* A new evaluation starts: whatever the panel waits for or asks is for an old pattern. */
export function cancelAnalysis() {
  clearTimeout(st.timer);
  st.timer = null;
  if (st.controller) st.controller.abort();
  st.controller = null;
  $('ev-analysis').setAttribute('aria-busy', 'false');
}

/* Evaluate answered for pattern (the wire form it sent): analyse it once things settle. */
export function analysisAfterEvaluate(pattern) {
  cancelAnalysis();
  st.pattern = pattern;
  if (!$('ev-analysis').open) {
    setState('collapsed');
    return;
  }
  setState('waiting');
  st.timer = setTimeout(() => requestAnalysis(), SETTLE_MS);
}

/* Evaluate refused the pattern: nothing of the previous pattern's analysis stays. */
export function analysisEvaluateFailed() {
  cancelAnalysis();
  st.pattern = null;
  clearResults();
  showErrors([]);
  setStatus('no analysis: the pattern did not evaluate (see the message above)');
  setState('idle');
}

function setState(s) {
  $('ev-analysis').dataset.state = s;
}

function setStatus(msg, error = false) {
  const s = $('an-status');
  s.textContent = msg;
  s.classList.toggle('error-text', error);
}

/* Field errors beside their inputs; an error of any other field in the status line. */
function showErrors(errors) {
  for (const f of FIELDS) {
    const e = errors.find((x) => x.field === f.field);
    $(f.error).textContent = e ? e.message : '';
    $(f.input).setAttribute('aria-invalid', String(!!e));
  }
  const other = errors.filter((x) => !FIELDS.some((f) => f.field === x.field));
  if (other.length) setStatus(other.map((x) => x.message).join('; '), true);
}

/* The request the controls describe, or the errors that keep it from being sent. Only the
 * form is checked here (a whole number); the ranges are the daemon's, whose 400 names the field. */
function readOptions() {
  const errors = [];
  const values = {};
  for (const f of FIELDS) {
    const raw = $(f.input).value.trim();
    if (!/^[0-9]+$/.test(raw)) errors.push({ field: f.field, message: `${f.field}: give a whole number${raw ? ` (not "${raw}")` : ''}` });
    else values[f.field] = Number(raw);
  }
  return { errors, radius: values['spectrum.radius'], bins: values['pcf.bins'] };
}

function requestAnalysis({ force = false } = {}) {
  cancelAnalysis();
  if (!$('ev-analysis').open) {
    setState('collapsed');
    return;
  }
  if (!st.pattern) {
    setState('idle');
    return;
  }
  const opts = readOptions();
  if (opts.errors.length) {
    clearResults();
    setStatus('');
    showErrors(opts.errors);
    setState('error');
    return;
  }
  const body = { pattern: st.pattern, spectrum: { radius: opts.radius }, pcf: { bins: opts.bins } };
  const key = JSON.stringify(body);
  if (!force && key === st.shownKey) {
    // The same answer is on screen (the panel was closed and opened): lay it out again only.
    redraw();
    setState('done');
    return;
  }
  const controller = new AbortController();
  st.controller = controller;
  setState('running');
  setStatus('analysing…');
  $('ev-analysis').setAttribute('aria-busy', 'true');
  apiPost('/v1/analyze', body, { signal: controller.signal })
    .then((resp) => {
      if (controller.signal.aborted) return;
      st.busyRetries = 0;
      showErrors([]);
      setStatus('');
      showResult(resp, key);
      setState('done');
    })
    .catch((e) => {
      if (controller.signal.aborted || (e && e.name === 'AbortError')) return;
      if (e.status === 429 && st.busyRetries < 3) {
        // The daemon counts analyses in the evaluate share: an evaluation still running holds it.
        st.busyRetries++;
        setStatus('server busy, asking again in 1 s…');
        st.timer = setTimeout(() => requestAnalysis({ force }), 1000);
        return;
      }
      st.busyRetries = 0;
      clearResults();
      setStatus('');
      showErrors([{ field: e.field || '', message: e.message }]);
      setState('error');
    })
    .finally(() => {
      if (st.controller === controller) {
        st.controller = null;
        $('ev-analysis').setAttribute('aria-busy', 'false');
      }
    });
}

let shown = null; // the answer on screen, for redrawing after the panel opens

function clearResults() {
  shown = null;
  st.shownKey = null;
  for (const id of ['an-periodogram', 'an-radial', 'an-anisotropy', 'an-pcf']) $(id).replaceChildren();
  for (const id of ['an-periodogram-legend', 'an-spectrum-legend', 'an-pcf-legend']) $(id).textContent = '';
  for (const td of $('an-figures').querySelectorAll('td[data-key]')) {
    td.textContent = '—';
    td.dataset.value = '';
  }
  $('an-points').textContent = '—';
}

function showResult(a, key) {
  shown = a;
  st.shownKey = key;
  redraw();
}

/* Six significant digits, or scientific below 10^-3. */
export function fmtFigure(v) {
  if (v == null || !Number.isFinite(v)) return '—';
  if (v === 0) return '0';
  const a = Math.abs(v);
  return a < 1e-3 || a >= 1e6 ? v.toExponential(5) : String(+v.toPrecision(6));
}

function redraw() {
  const a = shown;
  if (!a) return;
  $('an-points').textContent = `${a.points} points (tile ${a.tile} × ${a.tile} pixels scaled to the unit torus), family ${a.family}`;
  for (const td of $('an-figures').querySelectorAll('td[data-key]')) {
    const [group, name] = td.dataset.key.split('.');
    const v = a[group] ? a[group][name] : undefined;
    td.textContent = fmtFigure(v);
    td.dataset.value = v == null ? '' : String(v);
    td.title = v == null ? 'not defined for this point set' : String(v);
  }
  const s = a.spectrum;
  if (s) {
    const { scale } = drawPeriodogram($('an-periodogram'), s);
    $('an-periodogram-legend').textContent =
      `Colour: log₁₀ P(k) from ${powerOfTen(scale.loExp)} (and below, 0 included) to ${powerOfTen(scale.hiExp)}; P = 1 is uniform random points' level. ` +
      `Ringed white centre: DC (k = 0, P = n = ${a.points}), left out of the scale. kx, ky in cycles per tile, |k| ≤ ${s.radius}.`;
    const xs = s.radial.map((_, i) => i).slice(1);
    const markers = [];
    if (s.effective_nyquist != null) markers.push({ x: s.effective_nyquist, className: 'nyquist' });
    markers.push({ x: s.frequency_unit, className: 'unit' });
    drawLinePlot($('an-radial'), {
      title: 'Radial average P̄(|k|)',
      xLabel: '|k| (cycles per tile)',
      yLabel: 'mean power',
      series: [{ label: 'radial', xs, ys: s.radial.slice(1) }],
      refLines: [{ y: 1 }],
      markers,
      yInclude: [0],
      xRange: [0, s.radius],
    });
    drawLinePlot($('an-anisotropy'), {
      title: 'Anisotropy',
      xLabel: '|k| (cycles per tile)',
      yLabel: 'dB',
      series: [{ label: 'anisotropy', xs, ys: s.anisotropy_db.slice(1) }],
      refLines: [{ y: 0 }],
      markers,
      xRange: [0, s.radius],
      height: 200,
    });
    $('an-spectrum-legend').textContent =
      `Annuli |k| rounding to 1…${s.radius}; DC (annulus 0) left out. Dashed: P̄ = 1 and 0 dB, the levels of uniform random points (one periodogram). ` +
      `Dotted: effective Nyquist ν_eff = ${fmtFigure(s.effective_nyquist)}; dash-dotted: √n = ${fmtFigure(s.frequency_unit)} (PSA's frequency unit)` +
      `${s.frequency_unit > s.radius ? ', beyond this radius' : ''}. Anisotropy: 10 log₁₀(variance / mean²) per annulus, gaps where undefined.`;
  }
  if (a.pcf) {
    const dhex = a.spacing ? a.spacing.packing_distance : null;
    drawLinePlot($('an-pcf'), {
      title: 'Pair correlation g(r)',
      xLabel: 'r (unit torus)',
      yLabel: 'g(r)',
      series: [{ label: 'pcf', xs: a.pcf.r, ys: a.pcf.g }],
      refLines: [{ y: 1 }],
      markers: dhex ? [{ x: dhex, className: 'unit' }] : [],
      yInclude: [0],
      xRange: [0, a.pcf.r_max],
    });
    $('an-pcf-legend').textContent =
      `${a.pcf.r.length} bins to r_max = ${fmtFigure(a.pcf.r_max)}, Gaussian kernel σ = ${fmtFigure(a.pcf.sigma)}. Dashed: g = 1 (uniform random points)` +
      `${dhex ? `; dash-dotted: packing distance d_hex = ${fmtFigure(dhex)}` : ''}.`;
  }
}
