// Families: E2 against samples per pixel for every preset and every finished job's best
// pattern, one series per family (Laine & Aila Fig. 10). Points link to the pattern.

import { apiPost } from '../api.js';
import { normEvaluation, familySeries, fmt } from '../model.js';
import { loadPresets, loadFinishedWithBest } from '../store.js';
import { drawScatter, scatterLegend } from '../scatter-plot.js';
import { PUBLISHED_BESTS } from '../published-bests.js';

const $ = (id) => document.getElementById(id);
// Job kinds whose results are optimized patterns.
const OPTIMIZER_KINDS = new Set(['optimize', 'family-sweep', 'random-stats', 'table3']);
const cache = new Map(); // key -> evaluation, so revisits are instant
let loading = null;

export async function init() {
  $('fam-refresh').addEventListener('click', () => {
    cache.clear();
    load();
  });
}

export async function show() {
  await load();
}

async function evaluateOnce(key, pattern) {
  if (!cache.has(key)) cache.set(key, apiPost('/v1/evaluate', { pattern }).then(normEvaluation));
  try {
    return await cache.get(key);
  } catch (e) {
    cache.delete(key);
    throw e;
  }
}

/* Runs fn over items with at most `limit` requests at once (the daemon has few workers). */
async function mapLimited(items, limit, fn) {
  const out = new Array(items.length);
  let next = 0;
  await Promise.all(
    Array.from({ length: Math.min(limit, items.length) }, async () => {
      while (next < items.length) {
        const i = next++;
        out[i] = await fn(items[i]).catch((e) => ({ error: e }));
      }
    }),
  );
  return out;
}

function load() {
  if (!loading) loading = doLoad().finally(() => (loading = null));
  return loading;
}

async function doLoad() {
  $('fam-status').textContent = 'evaluating presets…';
  const presets = await loadPresets();
  const jobs = await loadFinishedWithBest({ kinds: OPTIMIZER_KINDS }).catch(() => []);
  const items = [
    ...presets.map((p) => ({ key: `preset:${p.name}`, label: p.name, pattern: { preset: p.name }, href: `#/evaluate?preset=${encodeURIComponent(p.name)}`, preset: p, hollow: false })),
    ...jobs.map((j) => ({ key: `job:${j.id}`, label: `job #${j.id}`, pattern: { job: j.id }, href: `#/evaluate?job=${encodeURIComponent(j.id)}`, hollow: true })),
  ];
  const evals = await mapLimited(items, 3, (it) => evaluateOnce(it.key, it.pattern));
  const failed = evals.filter((e) => e && e.error).length;
  const bySeries = new Map();
  const rows = [];
  items.forEach((it, i) => {
    const ev = evals[i];
    if (!ev || ev.error || ev.e2 == null) return;
    const family = ev.family || (it.preset && it.preset.family) || '';
    const cost = ev.cost ?? (it.preset && it.preset.cost_spp);
    const series = familySeries(family);
    if (!bySeries.has(series)) bySeries.set(series, []);
    const published = it.preset ? it.preset.published : null;
    bySeries.get(series).push({ x: cost, y: ev.e2, href: it.href, hollow: it.hollow, title: `${it.label}: ${family}, ${cost} spp, E2 ${fmt(ev.e2, 4)}` });
    rows.push({ series, family, label: it.label, href: it.href, cost, e2: ev.e2, published });
  });
  const names = [...bySeries.keys()].sort();
  // The published bests as reference marks (published-bests.js: values with their sources).
  const reference = {
    label: 'published best',
    reference: true,
    points: PUBLISHED_BESTS.map((b) => ({ x: b.cost, y: b.e2, title: `published best of ${b.family}: E2 ${b.e2} (${b.source})` })),
  };
  drawScatter($('fam-plot'), {
    series: [...names.map((n) => ({ label: n, points: bySeries.get(n), envelope: true })), reference],
    xLog: true,
    xLabel: 'samples per pixel',
    yLabel: 'E2',
    width: 720,
    height: 420,
  });
  scatterLegend($('fam-legend'), names);
  $('fam-published').tBodies[0].replaceChildren(
    ...PUBLISHED_BESTS.map((b) => {
      const tr = document.createElement('tr');
      for (const [i, c] of [b.family, String(b.cost), b.e2.toFixed(3), b.source].entries()) {
        const td = document.createElement('td');
        td.textContent = c;
        if (i === 1 || i === 2) td.className = 'num';
        tr.append(td);
      }
      return tr;
    }),
  );
  rows.sort((a, b) => a.series.localeCompare(b.series) || a.cost - b.cost || a.e2 - b.e2);
  $('fam-table').tBodies[0].replaceChildren(
    ...rows.map((r) => {
      const tr = document.createElement('tr');
      const cells = [r.family, null, r.cost == null ? '—' : String(r.cost), fmt(r.e2, 4), r.published == null ? '' : String(r.published)];
      cells.forEach((c, i) => {
        const td = document.createElement('td');
        if (i === 1) {
          const a = document.createElement('a');
          a.href = r.href;
          a.textContent = r.label;
          td.appendChild(a);
        } else td.textContent = c;
        if (i >= 2) td.className = 'num';
        tr.appendChild(td);
      });
      return tr;
    }),
  );
  $('fam-status').textContent = `${rows.length} points${failed ? `, ${failed} could not be evaluated` : ''}`;
}
