// Data several views share, fetched once and cached: presets (with their patterns), filters,
// acuity tables, the job list.

import { apiGet } from './api.js';
import { presetsFrom, normPreset, filtersFrom, acuityFrom, jobsFrom, normJob } from './model.js';

let presetsPromise = null;

export function loadPresets() {
  if (!presetsPromise)
    presetsPromise = (async () => {
      const presets = presetsFrom(await apiGet('/v1/presets'));
      // The list carries no coordinates: GET /v1/presets/{name} has the pattern.
      await Promise.all(
        presets.map(async (p) => {
          p.pattern = normPreset(await apiGet(`/v1/presets/${encodeURIComponent(p.name)}`)).pattern;
        }),
      );
      return presets;
    })().catch((e) => {
      presetsPromise = null;
      throw e;
    });
  return presetsPromise;
}

export async function findPreset(name) {
  return (await loadPresets()).find((p) => p.name === name) || null;
}

export async function loadFilters() {
  return filtersFrom(await apiGet('/v1/filters'));
}

export async function loadAcuity() {
  return acuityFrom(await apiGet('/v1/acuity'));
}

export async function loadJobs() {
  return jobsFrom(await apiGet('/v1/jobs'));
}

export async function loadJob(id) {
  return normJob(await apiGet(`/v1/jobs/${encodeURIComponent(id)}`));
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
  return h.job_kinds;
}

/* Kinds whose result is a pattern (sent back to the daemon as {"job": id}); sleep has one when
 * its spec gave one. */
const PATTERN_KINDS = new Set(['optimize', 'family-sweep', 'random-stats', 'table3', 'sleep']);

/* Finished jobs that have a best pattern, newest first, from the list's summaries alone: a
 * summary's family is that of the job's best pattern (or of its spec). */
export async function loadFinishedWithBest({ kinds = PATTERN_KINDS, limit = 30 } = {}) {
  return (await loadJobs()).filter((j) => j.state === 'done' && j.family && kinds.has(j.kind)).slice(0, limit);
}
