// Jobs: start an optimization, list jobs with state and progress, cancel, and for one job the
// best-E2-against-seconds trace (log–log, uPlot), the best pattern and its exports.

import uPlot from '../../vendor/uplot/uPlot.esm.js';
import { apiPost, apiDelete, apiGetText } from '../api.js';
import { ACTIVE_STATES, fmt } from '../model.js';
import { loadJobs, loadJob, jobKinds } from '../store.js';
import { PatternView } from '../pattern-view.js';
import { drawableOf } from '../pattern-geometry.js';
import { currentEvaluatePattern } from './evaluate-bridge.js';

const $ = (id) => document.getElementById(id);
const STATE_MARK = { queued: '… ', running: '▶ ', done: '✓ ', failed: '✗ ', cancelled: '⊘ ', interrupted: '! ' };

let ctx = null;
let timer = null;
let visible = false;
let selected = null;
let chart = null;
let chartJob = null;
let bestView = null;
let lastJobs = [];
// The list answer is a summary (no spec, best or trace); details of finished jobs never change,
// so they are fetched once, those of active jobs on every refresh.
const details = new Map();
const DETAIL_LIMIT = 12;

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
      selected = String(r.id);
      await refresh();
    } catch (err) {
      $('job-form-status').textContent = `not started: ${err.message}`;
    } finally {
      $('job-submit').disabled = false;
    }
  });
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
  if (params.job) selected = params.job;
  await refresh();
}

export function hide() {
  visible = false;
  clearTimeout(timer);
}

async function refresh() {
  clearTimeout(timer);
  try {
    lastJobs = await loadJobs();
    await fillDetails(lastJobs);
    renderTable(lastJobs.map((j) => merged(j)));
    if (selected) await renderDetail(selected);
  } catch (e) {
    $('job-form-status').textContent = `jobs: ${e.message}`;
  }
  const active = lastJobs.some((j) => ACTIVE_STATES.has(j.state));
  if (visible) timer = setTimeout(refresh, active ? 700 : 4000);
}

async function fillDetails(jobs) {
  const recent = jobs
    .slice()
    .sort((a, b) => (b.created ?? 0) - (a.created ?? 0))
    .slice(0, DETAIL_LIMIT)
    .filter((j) => ACTIVE_STATES.has(j.state) || !details.has(String(j.id)) || details.get(String(j.id)).state !== j.state);
  await Promise.all(
    recent.map((j) =>
      loadJob(j.id)
        .then((d) => details.set(String(j.id), d))
        .catch(() => {}),
    ),
  );
}

/* The list row with what the detail adds (family, best E2); state and progress from the list. */
function merged(j) {
  const d = details.get(String(j.id));
  if (!d) return j;
  return { ...d, state: j.state, progress: j.progress };
}

function renderTable(jobs) {
  const rows = jobs
    .slice()
    .sort((a, b) => (b.created ?? 0) - (a.created ?? 0) || String(b.id).localeCompare(String(a.id), undefined, { numeric: true }))
    .map((j) => {
      const tr = document.createElement('tr');
      tr.dataset.jobId = j.id;
      tr.dataset.state = j.state;
      if (String(j.id) === String(selected)) tr.classList.add('selected');
      const pct = Math.round(j.progress * 100);
      tr.innerHTML = `
        <td>#${esc(j.id)}</td>
        <td>${esc(j.kind)}${j.family ? ` <span class="hint">${esc(j.family)}</span>` : ''}</td>
        <td class="state state-${esc(j.state)}">${STATE_MARK[j.state] || ''}${esc(j.state)}</td>
        <td><progress max="1" value="${j.progress}" aria-label="job ${esc(j.id)} progress">${pct}%</progress> <span class="pct">${pct}%</span></td>
        <td class="num">${fmt(j.bestE2, 4)}</td>
        <td class="actions"><button type="button" data-action="show">Show</button>
          <button type="button" data-action="cancel" ${ACTIVE_STATES.has(j.state) ? '' : 'disabled'} aria-label="Cancel job ${esc(j.id)}">Cancel</button></td>`;
      return tr;
    });
  $('jobs-table').tBodies[0].replaceChildren(...rows);
  if (!rows.length) $('jobs-table').tBodies[0].innerHTML = '<tr><td colspan="6" class="hint">no jobs yet</td></tr>';
}

async function renderDetail(id) {
  const j = await loadJob(id);
  $('job-detail-hint').hidden = true;
  $('job-detail-body').hidden = false;
  $('job-detail-title').textContent = `Job #${j.id} (${j.kind})`;
  $('jd-state').textContent = `${STATE_MARK[j.state] || ''}${j.state} (${Math.round(j.progress * 100)}%)`;
  $('jd-state').dataset.state = j.state;
  $('jd-e2').textContent = fmt(j.bestE2, 6);
  $('jd-family').textContent = j.family || '—';
  $('jd-points').textContent = String(j.trace.length);
  $('jd-error').textContent = j.error ? `error: ${j.error}` : '';
  drawTrace(j);
  const d = j.best && drawableOf(j.best.pattern);
  if (d) bestView.setPattern(structuredClone(d.pattern), 0);
  const hasBest = !!(j.best && j.best.pattern);
  for (const b of $('jd-export').querySelectorAll('button')) b.disabled = !hasBest;
}

function chartSize() {
  const w = Math.max(280, $('jd-trace').clientWidth || 560);
  return { width: w, height: Math.round(Math.min(320, w * 0.55)) };
}

function drawTrace(j) {
  // Log axes need positive values; the first point may be at t = 0. uPlot needs ascending x
  // (jobs of mirrored families stored before the fix of 2026-11-25 have seconds that restart).
  const points = j.trace.filter((p) => Number.isFinite(p.seconds)).sort((a, b) => a.seconds - b.seconds);
  const xs = points.map((p) => Math.max(p.seconds, 1e-3));
  const ys = points.map((p) => p.best_e2);
  const data = [xs, ys];
  $('jd-trace').dataset.points = String(xs.length);
  if (chart && chartJob === j.id) {
    chart.setData(data);
    return;
  }
  if (chart) chart.destroy();
  chartJob = j.id;
  chart = new uPlot(
    {
      ...chartSize(),
      // Log scales fitted to the data (uPlot's default snaps to whole decades, which squeezes a
      // curve that spans 0.5..0.6 into a corner).
      scales: {
        x: { time: false, distr: 3, range: (u, lo, hi) => logRange(lo, hi, 1.5) },
        y: { distr: 3, range: (u, lo, hi) => logRange(lo, hi, 1.08) },
      },
      axes: [
        { label: 'seconds', values: (u, v) => v.map((x) => (x == null ? '' : String(+x.toPrecision(3)))) },
        { label: 'best E2', size: 60, values: (u, v) => v.map((x) => (x == null ? '' : String(+x.toPrecision(3)))) },
      ],
      series: [
        { label: 's', value: (u, v) => (v == null ? '—' : v.toPrecision(3)) },
        // Best-so-far is constant between improvements: a step after each point.
        { label: 'best E2', stroke: '#1f5fbf', width: 2, paths: uPlot.paths.stepped({ align: 1 }), points: { show: true, size: 5 }, value: (u, v) => (v == null ? '—' : v.toFixed(5)) },
      ],
    },
    data,
    $('jd-trace'),
  );
}

function logRange(lo, hi, pad) {
  if (!(lo > 0) || !(hi > 0)) return [1e-3, 1];
  if (hi / lo < 1.0001) return [lo / pad / 1.05, hi * pad * 1.05];
  return [lo / pad, hi * pad];
}

async function exportPattern(id, format) {
  try {
    const { text, type } = await apiGetText(`/v1/patterns/${encodeURIComponent(id)}/export?format=${format}`);
    let shown = text;
    try {
      shown = JSON.stringify(JSON.parse(text), null, 1);
    } catch {
      /* not JSON (UTK point set): show as it is */
    }
    $('jd-export-text').textContent = shown;
    const a = $('jd-download');
    if (a.href) URL.revokeObjectURL(a.href);
    a.href = URL.createObjectURL(new Blob([text], { type }));
    a.download = `aalab-job-${id}.${format === 'json' ? 'json' : format === 'utk' ? 'dat' : `${format}.txt`}`;
    a.textContent = `Download ${a.download}`;
    a.hidden = false;
  } catch (e) {
    $('jd-export-text').textContent = `export failed: ${e.message}`;
  }
}

function esc(s) {
  return String(s ?? '').replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}
