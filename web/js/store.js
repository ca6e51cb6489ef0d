// Data several views share, fetched once and cached: presets (with their patterns), filters,
// acuity tables, finished jobs with a best pattern.

import { apiGet } from './api.js';
import { listFrom, normPreset, normJob, patternOf } from './model.js';

let presetsPromise = null;

export function loadPresets() {
  if (!presetsPromise)
    presetsPromise = (async () => {
      const list = listFrom(await apiGet('/v1/presets'), 'presets').map(normPreset);
      // The list may carry names only; fetch a preset's coordinates when they are missing.
      await Promise.all(
        list.map(async (p) => {
          if (p.pattern && !p.pattern.preset) return;
          try {
            const full = normPreset(await apiGet(`/v1/presets/${encodeURIComponent(p.name)}`));
            Object.assign(p, { ...full, pattern: patternOf(full.pattern) || full.pattern });
          } catch {
            /* keep {preset: name}: the server still evaluates it, the drawing needs kernels */
          }
        }),
      );
      return list;
    })().catch((e) => {
      presetsPromise = null;
      throw e;
    });
  return presetsPromise;
}

export async function findPreset(name) {
  return (await loadPresets()).find((p) => p.name === name) || null;
}

/* Filters: [{name, params:{B:0.333,...}}]. The answer may list names or objects. */
const FILTER_PARAMS = ['B', 'C', 'radius', 'sigma', 'a'];

export async function loadFilters() {
  const raw = listFrom(await apiGet('/v1/filters'), 'filters');
  return raw.map((f) => {
    if (typeof f === 'string') return { name: f, params: {} };
    const params = {};
    const src = f.params || f.parameters || f.defaults || f;
    // Only the parameters the filter decoder takes; other numbers (error bounds, piece counts)
    // are information and would be rejected as unknown fields.
    for (const [k, v] of Object.entries(src)) if (typeof v === 'number' && FILTER_PARAMS.includes(k)) params[k] = v;
    return { name: f.name, params, description: f.description || '' };
  });
}

export async function loadAcuity() {
  const raw = await apiGet('/v1/acuity');
  const list = listFrom(raw, 'tables', 'acuity');
  const names = list.map((a) => (typeof a === 'string' ? a : a.name)).filter(Boolean);
  if (!names.length && raw && raw.name) names.push(raw.name);
  for (const n of ['naiman', 'uniform']) if (!names.includes(n)) names.push(n);
  return names;
}

export async function loadJobs() {
  return listFrom(await apiGet('/v1/jobs'), 'jobs').map(normJob);
}

export async function loadJob(id) {
  const j = await apiGet(`/v1/jobs/${encodeURIComponent(id)}`);
  return normJob(j.job && typeof j.job === 'object' ? j.job : j);
}

/* The last health answer, and a promise of the first, for the job kinds this daemon runs. */
let health = null;
let healthResolve;
const firstHealth = new Promise((r) => (healthResolve = r));
export function setHealth(h) {
  health = h;
  healthResolve(h);
}
export async function jobKinds() {
  const h = health || (await Promise.race([firstHealth, apiGet('/v1/health')]));
  return Array.isArray(h && h.job_kinds) ? h.job_kinds : null; // null: not reported, try anyway
}

/* Finished jobs that have a best pattern, newest first. The list answer is a summary, so the
 * details are fetched (once: a finished job does not change). */
const finishedDetails = new Map();
export async function loadFinishedWithBest({ exclude = new Set(), limit = 30 } = {}) {
  const done = (await loadJobs())
    .filter((j) => j.state === 'done' && !exclude.has(j.kind))
    .sort((a, b) => (b.created ?? 0) - (a.created ?? 0))
    .slice(0, limit);
  const out = await Promise.all(
    done.map(async (j) => {
      const key = String(j.id);
      if (!finishedDetails.has(key)) finishedDetails.set(key, await loadJob(j.id).catch(() => null));
      return finishedDetails.get(key);
    }),
  );
  return out.filter((j) => j && j.best && j.best.pattern);
}
