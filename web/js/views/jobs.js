// Jobs: start an optimization, list jobs (from GET /v1/jobs summaries alone) with state and
// progress, cancel, and for one job: the best-E2-against-seconds trace (uPlot, log or linear
// axes), the kind's own tables, the best pattern and its exports.

import uPlot from '../../vendor/uplot/uPlot.esm.js';
import { apiPost, apiDelete, apiGetText } from '../api.js';
import { ACTIVE_STATES, fmt, traceCurve, traceXLabel, jobSettings, jobTimings, timingsText } from '../model.js';
import { loadJobs, loadJob, jobKinds } from '../store.js';
import { PatternView } from '../pattern-view.js';
import { drawableOf } from '../pattern-geometry.js';
import { traceAxes, tickLabels, axisFor } from '../trace-axes.js';
import { drawScatter, scatterLegend } from '../scatter-plot.js';
import { csvText, standaloneSvg, fileStem } from '../plot-tools.js';
import { renderKindDetail } from './kind-details.js';
import { currentEvaluatePattern } from './evaluate-bridge.js';

const $ = (id) => document.getElementById(id);
const STATE_MARK = { queued: '… ', running: '▶ ', done: '✓ ', failed: '✗ ', cancelled: '⊘ ', interrupted: '! ' };

let ctx = null;
let timer = null;
let visible = false;
let selected = null; // id of the job whose detail is shown
let shown = null; // id the detail panel currently holds (cleared when another job is chosen)
let chart = null;
let lastJob = null;
let bestView = null;
let lastJobs = [];
const overlay = new Set(); // ids of the jobs whose traces the overlay plot draws
let overlayKey = '';

export async function init(context) {
  ctx = context;
  bestView = new PatternView($('jd-pattern'), { editable: false, label: 'Best pattern of the job' });
  $('job-start').addEventListener('change', syncForm);
  syncForm();
  $('job-form').addEventListener('submit', async (e) => {
    e.preventDefault();
    const spec = { kind: 'optimize', seeds: +$('job-seeds').value, max_seconds: +$('job-seconds').value, rng_seed: +$('job-rng').value };
    if ($('job-mode').value) spec.mode = $('job-mode').value;
    if ($('job-method').value) spec.method = $('job-method').value;
    if ($('job-label').value.trim()) spec.label = $('job-label').value.trim();
    if ($('job-start').value === 'pattern') {
      const p = currentEvaluatePattern();
      if (!p) {
        $('job-form-status').textContent = 'Evaluate has no pattern yet';
        return;
      }
      spec.pattern = p;
    } else spec.family = $('job-family').value.trim();
    $('job-submit').disabled = true;
    try {
      const r = await apiPost('/v1/jobs', spec);
      $('job-form-status').textContent = `job ${r.id} submitted`;
      select(String(r.id));
      await refresh();
    } catch (err) {
      $('job-form-status').textContent = `not started: ${err.message}`;
    } finally {
      $('job-submit').disabled = false;
    }
  });
  $('jobs-table').addEventListener('change', (e) => {
    const box = e.target.closest('input.overlay-pick');
    if (!box) return;
    const id = box.closest('tr').dataset.jobId;
    if (box.checked) overlay.add(id);
    else overlay.delete(id);
    drawOverlay(true);
  });
  $('jobs-overlay-axes').addEventListener('change', () => drawOverlay(true));
  $('jobs-table').addEventListener('click', async (e) => {
    const btn = e.target.closest('button');
    if (!btn) return;
    const id = btn.closest('tr').dataset.jobId;
    if (btn.dataset.action === 'show') ctx.navigate('jobs', { job: id });
    if (btn.dataset.action === 'cancel') {
      btn.disabled = true;
      try {
        await apiDelete(`/v1/jobs/${encodeURIComponent(id)}`);
      } catch (err) {
        ctx.toast(`cancel ${id}: ${err.message}`);
      }
      refresh();
    }
  });
  $('jd-export').addEventListener('click', (e) => {
    const fmtName = e.target.closest('button')?.dataset.format;
    if (fmtName && selected) exportPattern(selected, fmtName);
  });
  $('jd-open').addEventListener('click', () => selected && ctx.navigate('evaluate', { job: selected }));
  $('jd-axes').addEventListener('change', () => {
    if (chart) chart.destroy();
    chart = null;
    zoom = null;
    if (lastJob) drawTrace(lastJob);
  });
  $('jd-trace-tools').addEventListener('click', (e) => {
    const action = e.target.closest('button')?.dataset.action;
    if (!action || !lastJob) return;
    if (action === 'reset') {
      zoom = null;
      drawTrace(lastJob);
    } else traceDownload(lastJob, action);
  });
  window.addEventListener('resize', () => chart && chart.setSize(chartSize()));
}

function syncForm() {
  $('job-family').disabled = $('job-start').value !== 'family';
}

export async function show(params) {
  visible = true;
  const kinds = await jobKinds().catch(() => null);
  const missing = kinds && !kinds.includes('optimize');
  $('job-submit').disabled = !!missing;
  if (missing) $('job-form-status').textContent = `this daemon runs no optimize jobs (its job kinds: ${kinds.join(', ')})`;
  if (params.job) select(String(params.job));
  await refresh();
}

export function hide() {
  visible = false;
  clearTimeout(timer);
}

function select(id) {
  if (id === selected) return;
  selected = id;
  clearDetail();
}

/* Empties everything the detail panel shows of a job, so nothing of the previous job stays. */
function clearDetail() {
  shown = null;
  lastJob = null;
  if (chart) chart.destroy();
  chart = null;
  chartKey = '';
  zoom = null;
  $('jd-trace').replaceChildren();
  delete $('jd-trace').dataset.points;
  for (const id of ['jd-state', 'jd-label', 'jd-e2', 'jd-family', 'jd-points', 'jd-executor', 'jd-settings', 'jd-timings']) $(id).textContent = '—';
  $('jd-error').textContent = '';
  $('jd-kind').replaceChildren();
  delete $('jd-kind').dataset.kind;
  delete $('jd-kind').dataset.job;
  bestView.svg.replaceChildren();
  $('jd-export-text').textContent = '';
  const a = $('jd-download');
  if (a.href) URL.revokeObjectURL(a.href);
  a.removeAttribute('href');
  a.removeAttribute('download');
  a.textContent = 'Download';
  a.hidden = true;
  $('job-detail-title').textContent = 'Job detail';
  $('job-detail-body').hidden = true;
  $('job-detail-hint').hidden = false;
}

async function refresh() {
  clearTimeout(timer);
  try {
    lastJobs = await loadJobs();
    renderTable(lastJobs);
    if (selected) await renderDetail(selected);
    await drawOverlay(false);
  } catch (e) {
    $('job-form-status').textContent = `jobs: ${e.message}`;
  }
  const active = lastJobs.some((j) => ACTIVE_STATES.has(j.state));
  if (visible) timer = setTimeout(refresh, active ? 700 : 4000);
}

function renderTable(jobs) {
  const rows = jobs.map((j) => {
    const tr = document.createElement('tr');
    tr.dataset.jobId = j.id;
    tr.dataset.state = j.state;
    if (String(j.id) === String(selected)) tr.classList.add('selected');
    const pct = Math.round(j.progress * 100);
    tr.innerHTML = `
        <td class="nowrap"><input type="checkbox" class="overlay-pick" ${overlay.has(String(j.id)) ? 'checked' : ''} aria-label="overlay the trace of job ${esc(j.id)}" title="overlay this job's trace"> #${esc(j.id)}</td>
        <td>${esc(j.kind)}${j.family ? ` <span class="hint">${esc(j.family)}</span>` : ''}</td>
        <td class="label">${esc(j.label)}</td>
        <td class="state state-${esc(j.state)}">${STATE_MARK[j.state] || ''}${esc(j.state)}</td>
        <td><progress max="1" value="${j.progress}" aria-label="job ${esc(j.id)} progress">${pct}%</progress> <span class="pct">${pct}%</span></td>
        <td class="num best-e2">${fmt(j.bestE2, 4)}</td>
        <td class="actions"><button type="button" data-action="show">Show</button>
          <button type="button" data-action="cancel" ${ACTIVE_STATES.has(j.state) ? '' : 'disabled'} aria-label="Cancel job ${esc(j.id)}">Cancel</button></td>`;
    return tr;
  });
  $('jobs-table').tBodies[0].replaceChildren(...rows);
  if (!rows.length) $('jobs-table').tBodies[0].innerHTML = '<tr><td colspan="7" class="hint">no jobs yet</td></tr>';
}

async function renderDetail(id) {
  const j = await loadJob(id);
  if (String(id) !== String(selected)) return; // another job was chosen meanwhile
  if (shown !== String(j.id)) clearDetail();
  shown = String(j.id);
  lastJob = j;
  $('job-detail-hint').hidden = true;
  $('job-detail-body').hidden = false;
  $('job-detail-body').dataset.job = String(j.id);
  $('job-detail-title').textContent = `Job #${j.id} (${j.kind})`;
  $('jd-state').textContent = `${STATE_MARK[j.state] || ''}${j.state} (${Math.round(j.progress * 100)}%)`;
  $('jd-state').dataset.state = j.state;
  $('jd-label').textContent = j.label || '—';
  $('jd-e2').textContent = fmt(j.bestE2, 6);
  $('jd-family').textContent = j.family || '—';
  $('jd-points').textContent = String(j.trace.length);
  $('jd-executor').textContent = j.execution || j.executor || 'local';
  // The submitted settings (what the spec left out took the daemon's defaults) and timings.
  const settings = jobSettings(j.spec);
  const sd = $('jd-settings');
  sd.replaceChildren(...settings.flatMap(([k, v], i) => [...(i ? [' · '] : []), Object.assign(document.createElement('span'), { className: 'setting', textContent: `${k} ${v}` })]));
  if (!settings.length) sd.textContent = 'defaults';
  const t = jobTimings(j);
  $('jd-timings').textContent = timingsText(t);
  $('jd-timings').title = t.created == null ? '' : `submitted ${new Date(t.created * 1000).toISOString()}`;
  $('jd-error').textContent = j.error ? `error: ${j.error}` : '';
  $('jd-trace-figure').hidden = !j.trace.length;
  drawTrace(j);
  const holder = $('jd-kind');
  const key = `${j.id}:${j.state}`;
  if (holder.dataset.job !== key) {
    holder.replaceChildren();
    if (renderKindDetail(holder, j)) holder.dataset.job = key;
  }
  const d = j.best && drawableOf(j.best.pattern);
  $('jd-best').hidden = !j.best;
  if (d) bestView.setPattern(structuredClone(d.pattern), 0);
  else bestView.svg.replaceChildren();
  for (const b of $('jd-export').querySelectorAll('button')) b.disabled = !j.best;
}

/* The traces of the ticked jobs in one plot (best E2 against each job's seconds). Redrawn
 * when the choice or the axes change, or while a ticked job runs (force: redraw anyway). */
async function drawOverlay(force) {
  const ids = [...overlay].filter((id) => lastJobs.some((j) => String(j.id) === id));
  $('jobs-overlay-figure').hidden = !ids.length;
  if (!ids.length) {
    overlayKey = '';
    $('jobs-overlay').replaceChildren();
    return;
  }
  const active = lastJobs.some((j) => ids.includes(String(j.id)) && ACTIVE_STATES.has(j.state));
  const key = `${ids.join()}|${$('jobs-overlay-axes').value}`;
  if (!force && !active && key === overlayKey) return;
  overlayKey = key;
  const jobs = await Promise.all(ids.map((id) => loadJob(id).catch(() => null)));
  const log = $('jobs-overlay-axes').value === 'log';
  const series = jobs.filter(Boolean).map((j) => {
    const c = traceCurve(j);
    const label = `#${j.id} ${j.kind}${j.family ? ` ${j.family}` : ''}${j.spec.method ? ` ${j.spec.method}` : ''}${j.spec.rng_seed != null ? ` seed ${j.spec.rng_seed}` : ''}`;
    return { label, step: true, points: c.xs.map((x, i) => ({ x, y: c.ys[i], title: `${label}: E2 ${fmt(c.ys[i], 6)} at ${+x.toPrecision(4)} s` })).filter((p) => !log || (p.x > 0 && p.y > 0)) };
  });
  drawScatter($('jobs-overlay'), { series, xLabel: 'seconds', yLabel: 'best E2', xLog: log, yLog: log, width: 640, height: 340, title: 'Best E2 against run time' });
  scatterLegend($('jobs-overlay-legend'), series.map((s) => s.label));
}

function chartSize() {
  const w = Math.max(280, $('jd-trace').clientWidth || 560);
  return { width: w, height: Math.round(Math.min(320, w * 0.55)) };
}

let axes = null; // the trace chart's ranges and ticks, read by its scale and axis callbacks
let chartKey = '';
let marked = 0; // points of the curve drawn with a marker (the trace's own, not the end)
let zoom = null; // {x: [lo, hi], y: [lo, hi]} chosen by dragging over the chart; null: all

/* The trace as a file: CSV of its points, PNG of the chart's canvas, or SVG drawn from the same
 * points (scatter-plot.js, off screen so the page's styles can be read and inlined). */
function traceDownload(j, what) {
  const stem = `aalab-job-${j.id}-trace`;
  const save = (blob, ext) => {
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `${stem}.${ext}`;
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  };
  if (what === 'csv') {
    const rows = j.trace.map((p) => [p.seconds, p.iterations, p.evaluations, p.best_e2]);
    save(new Blob([csvText(['seconds', 'iterations', 'evaluations', 'best_e2'], rows)], { type: 'text/csv' }), 'csv');
  } else if (what === 'png') {
    const canvas = $('jd-trace').querySelector('canvas');
    if (canvas) canvas.toBlob((b) => b && save(b, 'png'), 'image/png');
  } else if (what === 'svg') {
    const c = traceCurve(j);
    const log = $('jd-axes').value === 'log';
    const off = document.createElement('div');
    off.style.cssText = 'position:absolute;left:-10000px;top:0;width:720px';
    document.body.append(off);
    const svg = drawScatter(off, {
      series: [{ label: `job ${j.id}`, line: true, points: c.xs.map((x, i) => ({ x, y: c.ys[i] })) }],
      xLabel: traceXLabel(j.kind),
      yLabel: 'best E2',
      xLog: log,
      yLog: log,
      width: 720,
      height: 400,
      title: `Job ${j.id} (${j.kind}): best E2 against ${traceXLabel(j.kind)}`,
      tools: false,
    });
    const text = standaloneSvg(svg);
    off.remove();
    save(new Blob([text], { type: 'image/svg+xml' }), 'svg');
  }
}

function drawTrace(j) {
  const curve = traceCurve(j);
  // The header shows the E2 the curve ends at (a running job's best may be newer than its trace).
  $('jd-e2').textContent = fmt(curve.best ?? j.bestE2, 6);
  const mode = $('jd-axes').value;
  axes = traceAxes(curve.xs, curve.ys, mode);
  // A zoom keeps its ranges (ticks inside them) until reset, another job or other axes.
  if (zoom) axes = { ...axes, x: axisFor(zoom.x, mode), y: axisFor(zoom.y, mode) };
  $('jd-trace-tools').querySelector('[data-action="reset"]').disabled = !zoom;
  $('jd-trace').dataset.zoomed = zoom ? 'true' : '';
  const holder = $('jd-trace');
  holder.dataset.points = String(curve.points);
  holder.dataset.end = curve.endSeconds == null ? '' : String(curve.endSeconds);
  holder.dataset.yTicks = String(axes.y.ticks.length);
  holder.dataset.xLabel = traceXLabel(j.kind);
  $('jd-trace-caption').textContent = curve.endSeconds == null && j.kind === 'table3'
    ? 'Best Opt W+P E2 so far against the Opt W+P work (seconds summed over the cells), to its last point'
    : "Best E2 so far against run time (seconds), up to the job's end";
  holder.setAttribute('aria-label', `Best E2 against run time, ${mode} axes`);
  // The curve's last point is the job's end (no marker there) when it runs past the last
  // improvement.
  const endPoint = curve.xs.length > curve.points;
  marked = axes.xs.length - (endPoint ? 1 : 0);
  const data = [axes.xs, axes.ys];
  const key = `${j.id}:${mode}:${zoom ? zoom.x.join() + zoom.y.join() : ''}`;
  if (!axes.xs.length) {
    if (chart) chart.destroy();
    chart = null;
    return;
  }
  if (chart && chartKey === key) {
    chart.setData(data);
    chart.setLegend({ idx: null });
    return;
  }
  if (chart) chart.destroy();
  chartKey = key;
  // uPlot's own log splits loop until they pass the range: ranges and ticks come from
  // traceAxes, which are finite, non-empty and positive on log axes.
  const scale = (which) => ({ time: false, distr: mode === 'log' ? 3 : 1, range: () => axes[which].range });
  const ticks = (which) => () => axes[which].ticks;
  const labels = (which) => (u, splits) => {
    const l = tickLabels(axes[which].ticks);
    return splits.map((v) => l[axes[which].ticks.indexOf(v)] ?? '');
  };
  const lastOf = (arr) => arr[arr.length - 1];
  chart = new uPlot(
    {
      ...chartSize(),
      scales: { x: scale('x'), y: scale('y') },
      // Dragging a rectangle zooms to it (the chart is rebuilt with those ranges); the toolbar's
      // Reset zoom goes back.
      cursor: { drag: { x: true, y: true, uni: 20, setScale: false } },
      hooks: {
        setSelect: [
          (u) => {
            const s = u.select;
            if (s.width < 6 && s.height < 6) return;
            const x = [u.posToVal(s.left, 'x'), u.posToVal(s.left + Math.max(s.width, 1), 'x')];
            const y = [u.posToVal(s.top + Math.max(s.height, 1), 'y'), u.posToVal(s.top, 'y')];
            zoom = { x: s.width < 6 ? axes.x.range : x, y: s.height < 6 ? axes.y.range : y };
            setTimeout(() => lastJob && drawTrace(lastJob));
          },
        ],
      },
      axes: [
        // uPlot labels only some ticks of a log axis by default: label every one of ours.
        { label: traceXLabel(j.kind), splits: ticks('x'), filter: (u, splits) => splits, values: labels('x') },
        { label: 'best E2', size: 70, splits: ticks('y'), filter: (u, splits) => splits, values: labels('y') },
      ],
      // Without the cursor over the plot, the legend shows the job's end and its best E2.
      series: [
        { label: 'seconds', value: (u, v, s, i) => `${+(i == null ? lastOf(axes.xs) : v).toPrecision(4)}` },
        {
          label: 'best E2',
          stroke: '#1f5fbf',
          width: 2,
          // Best-so-far is constant between improvements: a step after each point.
          paths: uPlot.paths.stepped({ align: 1 }),
          points: { show: true, size: 5, filter: () => Array.from({ length: marked }, (_, i) => i) },
          value: (u, v, s, i) => (i == null ? lastOf(axes.ys) : v).toFixed(6),
        },
      ],
    },
    data,
    holder,
  );
}

async function exportPattern(id, format) {
  try {
    const { text, type } = await apiGetText(`/v1/patterns/${encodeURIComponent(id)}/export?format=${format}`);
    if (String(id) !== String(selected)) return; // another job is shown now
    let out = text;
    try {
      out = JSON.stringify(JSON.parse(text), null, 1);
    } catch {
      /* not JSON (a UTK, x y w or CSV point set): show as it is */
    }
    $('jd-export-text').textContent = out;
    const a = $('jd-download');
    if (a.href) URL.revokeObjectURL(a.href);
    a.href = URL.createObjectURL(new Blob([text], { type }));
    // Point sets keep their usual extensions, so that `aalab eval FILE` reads them back.
    const ext = { json: 'json', utk: 'dat', xyw: 'xyw', csv: 'csv' }[format] || `${format}.txt`;
    a.download = `aalab-job-${id}.${ext}`;
    a.textContent = `Download ${a.download}`;
    a.hidden = false;
  } catch (e) {
    if (String(id) === String(selected)) $('jd-export-text').textContent = `export failed: ${e.message}`;
  }
}

function esc(s) {
  return String(s ?? '').replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}
