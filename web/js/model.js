// Reads the daemon's answers into what the views draw. Every field name is the one the schemas
// in proto/schemas/ give (the per-kind results in proto/schemas/kinds/<kind>.result.json); a
// field the schema does not promise is never looked for under another name. Pure functions.

export function num(v) {
  return typeof v === 'number' && Number.isFinite(v) ? v : null;
}

function str(v) {
  return typeof v === 'string' ? v : '';
}

function list(v) {
  return Array.isArray(v) ? v : [];
}

/* A pattern object as the daemon encodes it (pattern.json: family, cost_spp, form and the
 * form's own key, plus kernels_expanded) reduced to what the daemon takes back and the page
 * draws: {mirrored} or {kernels}; a tile pattern is sent back whole and drawn from
 * kernels_expanded, read-only. */
export function wirePattern(p) {
  if (!p || typeof p !== 'object') return null;
  if (p.form === 'mirrored') return { mirrored: p.mirrored };
  if (p.form === 'kernels') return { kernels: p.kernels };
  if (p.form === 'tile') return { tile: p.tile, kernels_expanded: p.kernels_expanded };
  return null;
}

/* GET /v1/presets: {presets: [{name, family, cost_spp, source, note?, published_e2}]};
 * GET /v1/presets/{name} adds the pattern. */
export function normPreset(p) {
  return {
    name: p.name,
    family: str(p.family),
    cost_spp: num(p.cost_spp),
    source: str(p.source),
    note: str(p.note),
    published: num(p.published_e2),
    pattern: p.pattern ? wirePattern(p.pattern) : null,
  };
}

export function presetsFrom(resp) {
  return list(resp && resp.presets).map(normPreset);
}

/* GET /v1/filters: {filters: [{name, radius, B?, C?, sigma?, a?, cdf_error_bound?, default}]}.
 * The parameters the filter decoder takes are B, C, sigma and a; radius is taken by gaussian
 * only (the others have a fixed support). */
const FILTER_PARAMS = { B: true, C: true, sigma: true, a: true };

export function filtersFrom(resp) {
  return list(resp && resp.filters).map((f) => {
    const params = {};
    for (const k of Object.keys(FILTER_PARAMS)) if (num(f[k]) != null) params[k] = f[k];
    if (f.name === 'gaussian' && num(f.radius) != null) params.radius = f.radius;
    return { name: f.name, params, isDefault: f.default === true };
  });
}

/* GET /v1/acuity: {tables: [{name, version, description, folded, knots, ...}], default}. */
export function acuityFrom(resp) {
  const tables = list(resp && resp.tables).map((t) => ({ name: str(t.name), version: num(t.version), description: str(t.description) }));
  return { names: tables.map((t) => t.name), tables, default: str(resp && resp.default) };
}

/* The selector's label of a table: its name and version ("naiman v2"). */
export function acuityLabel(t) {
  return t.version != null ? `${t.name} v${t.version}` : t.name;
}

/* POST /v1/evaluate: {e2, argmax: {kernel, angle_deg}, mean, kernel_count, angle_count, family,
 * cost_spp, detail?: [{kernel, angles: [{angle_deg, weight, e1, weighted}]}]}. Kernels are
 * numbered from 0, as on the wire. */
export function normEvaluation(resp) {
  const detail = list(resp.detail)
    .slice()
    .sort((a, b) => a.kernel - b.kernel)
    .map((k) => list(k.angles).map((r) => ({ angle: r.angle_deg, weight: num(r.weight), e1: num(r.e1), weighted: num(r.weighted) })));
  return {
    e2: num(resp.e2),
    argmaxKernel: resp.argmax ? resp.argmax.kernel : null,
    argmaxAngle: resp.argmax ? num(resp.argmax.angle_deg) : null,
    family: str(resp.family),
    cost: num(resp.cost_spp),
    kernels: detail,
  };
}

/* A job's trace: [{seconds, iterations, evaluations, best_e2}], in the order recorded. */
export function normTrace(trace) {
  return list(trace).map((p) => ({ seconds: p.seconds, iterations: p.iterations, evaluations: p.evaluations, best_e2: p.best_e2 }));
}

export const ACTIVE_STATES = new Set(['queued', 'running']);

/* One summary of GET /v1/jobs (job.json without spec, best, trace and result). */
export function jobSummary(j) {
  return {
    id: j.id,
    kind: j.kind,
    state: j.state,
    progress: Math.max(0, Math.min(1, j.progress)),
    label: str(j.label),
    family: str(j.family),
    bestE2: num(j.best_e2),
    created: num(j.created),
    started: num(j.started),
    finished: num(j.finished),
    error: j.error ? j.error.message : str(j.reason),
  };
}

export function jobsFrom(resp) {
  return list(resp && resp.jobs).map(jobSummary);
}

/* GET /v1/jobs/{id}: the summary plus spec, best ({pattern, e2}; {elapsed, pattern?} for sleep;
 * animation's best pattern is only {family, samples_per_pixel}), trace and result. The result,
 * once there, is authoritative for the best pattern: its own "best" (optimize, family-sweep,
 * random-stats). */
export function normJob(j) {
  const s = jobSummary(j);
  const best = j.best && typeof j.best === 'object' ? j.best : null;
  const r = j.result && typeof j.result === 'object' ? j.result : null;
  let bestPattern = null;
  // A temporal-optimize job's best is a sequence, not a kernel set: its kind's detail shows it
  // and opens it in Temporal (the pattern exports and Evaluate take kernels).
  if (r && r.best && !r.best.temporal) bestPattern = r.best;
  else if (best && best.pattern && best.pattern.form) bestPattern = best.pattern;
  const e2 = r && num(r.e2) != null ? r.e2 : best ? num(best.e2) : null;
  return {
    ...s,
    bestE2: s.bestE2 ?? e2,
    best: bestPattern ? { pattern: wirePattern(bestPattern), family: str(bestPattern.family), cost: num(bestPattern.cost_spp), e2 } : null,
    trace: normTrace(j.trace),
    spec: j.spec || {},
    pausedSeconds: num(j.paused_seconds),
    executor: str(j.executor),
    result: r,
    execution: executionText(j.spec, r),
  };
}

/* Where and how a job ran: "slurm, 8 shards, reproducible" from an optimizer kind's result, the
 * spec's executor while it runs, or null (kinds that always run locally). */
export function executionText(spec, result) {
  if (result && typeof result.executor === 'string') {
    const n = num(result.shards);
    const shards = n == null ? '' : `, ${n} shard${n === 1 ? '' : 's'}`;
    return `${result.executor}${shards}, ${result.reproducible ? 'reproducible' : 'best effort (time budget)'}`;
  }
  return spec && typeof spec.executor === 'string' ? spec.executor : null;
}

/* Kinds whose trace seconds are not the job's clock: table3's are the Opt W+P work summed over
 * its cells (which may run side by side), so its curve ends at its last point, not at the job's
 * wall time. */
const TRACE_WORK_SECONDS = { table3: 'Opt W+P seconds (summed over cells)' };

/* The trace chart's x-axis label for a job's kind. */
export function traceXLabel(kind) {
  return TRACE_WORK_SECONDS[kind] || 'seconds';
}

/* Trace points to draw, sorted by time, and the curve's end: best-so-far stays constant after
 * the last improvement, so the curve runs on to the job's end (finished - started; now for a
 * running job), except for kinds whose trace seconds are work, not the clock. The job's best E2
 * (posted apart from the trace, so a running job's may be newer) ends the curve when it is
 * lower, so the legend's last value and the header's agree. Points at t = 0 are kept for linear
 * axes; log axes drop them. `best`: the E2 both show. */
export function traceCurve(job, now = Date.now() / 1000) {
  const pts = job.trace.filter((p) => num(p.seconds) != null && num(p.best_e2) != null).sort((a, b) => a.seconds - b.seconds);
  const clock = !TRACE_WORK_SECONDS[job.kind];
  const end = clock && job.started != null ? (job.finished ?? (ACTIVE_STATES.has(job.state) ? now : null)) : null;
  const endSeconds = end != null ? end - job.started : null;
  const xs = pts.map((p) => p.seconds);
  const ys = pts.map((p) => p.best_e2);
  const lastY = ys.length ? ys[ys.length - 1] : null;
  const jobBest = num(job.bestE2);
  const best = lastY == null ? jobBest : jobBest != null && jobBest < lastY ? jobBest : lastY;
  if (pts.length && endSeconds != null && endSeconds > xs[xs.length - 1]) {
    xs.push(endSeconds);
    ys.push(best);
  } else if (pts.length && best < lastY) ys[ys.length - 1] = best;
  return { xs, ys, points: pts.length, endSeconds, best };
}

/* family-sweep result: {cost, configurations, seeds_per_config, ranked: [{rank, config:
 * {corners[4], edges[4], interior}, cost, e2, best}], best, e2}. */
export function sweepRows(result) {
  return list(result && result.ranked).map((r) => ({
    rank: r.rank,
    config: configLabel(r.config),
    corners: r.config.corners.reduce((a, b) => a + b, 0),
    edges: r.config.edges.reduce((a, b) => a + b, 0),
    interior: r.config.interior,
    e2: num(r.e2),
    family: r.best ? str(r.best.family) : '',
    pattern: r.best ? wirePattern(r.best) : null,
  }));
}

/* Corners then edges (counts per corner / edge site) and interior samples, e.g.
 * "corners 0001 · edges 1100 · interior 0". */
export function configLabel(c) {
  return `corners ${c.corners.join('')} · edges ${c.edges.join('')} · interior ${c.interior}`;
}

/* random-stats result, as L&A Table 3: {family, distribution, count, random: {min, avg, max},
 * best_random, opt_w: {e2, pattern, method}, opt_wp: {e2, pattern, method}, best, e2}. */
export function randomStatsRow(result) {
  const r = result || {};
  const rnd = r.random || {};
  return {
    family: str(r.family),
    distribution: str(r.distribution),
    count: r.count,
    min: num(rnd.min),
    avg: num(rnd.avg),
    max: num(rnd.max),
    optW: r.opt_w ? num(r.opt_w.e2) : null,
    optWMethod: r.opt_w ? str(r.opt_w.method) : '',
    optWP: r.opt_wp ? num(r.opt_wp.e2) : null,
    optWPMethod: r.opt_wp ? str(r.opt_wp.method) : '',
    optWPattern: r.opt_w ? wirePattern(r.opt_w.pattern) : null,
    optWPPattern: r.opt_wp ? wirePattern(r.opt_wp.pattern) : null,
  };
}

/* table3 result, as L&A Table 3 over seeds: {family, count, seeds, rows: [{distribution,
 * generator: {name, radius?}, columns: {min|avg|max|opt_w|opt_wp: {mean, sd, paper}},
 * per_seed}], best, e2, acuity}. Columns in the paper's order. */
export const TABLE3_COLUMNS = [['min', 'Min'], ['avg', 'Avg'], ['max', 'Max'], ['opt_w', 'Opt W'], ['opt_wp', 'Opt W+P']];
export function table3Rows(result) {
  const r = result || {};
  return {
    family: str(r.family),
    count: r.count,
    seeds: list(r.seeds),
    acuity: r.acuity ? (r.acuity.version != null ? `${r.acuity.name} v${r.acuity.version}` : str(r.acuity.name)) : '',
    rows: list(r.rows).map((row) => ({
      distribution: str(row.distribution),
      generator: row.generator ? str(row.generator.name) : '',
      radius: row.generator ? num(row.generator.radius) : null,
      cols: TABLE3_COLUMNS.map(([k]) => {
        const c = (row.columns || {})[k] || {};
        return { mean: num(c.mean), sd: num(c.sd), paper: num(c.paper) };
      }),
    })),
  };
}

/* compare result rows: [{name, family, samples_per_pixel, e2, rmse, max_dev, render_seconds,
 * pixels_sampled, coverage_samples, stats, tiles, predicted_rmse?}]. */
export function comparisonRows(result) {
  return list(result && result.rows).map((r) => ({
    label: r.name,
    family: str(r.family),
    spp: num(r.samples_per_pixel),
    e2: num(r.e2),
    rmse: num(r.rmse),
    maxDev: num(r.max_dev),
    seconds: num(r.render_seconds),
    predicted: num(r.predicted_rmse),
  }));
}

/* compare result's prediction: {spearman (null: undefined), subpixel_area_share}; null when the
 * result has none (older results). */
export function comparisonPrediction(result) {
  const p = result && result.prediction;
  return p ? { spearman: num(p.spearman), subpixelAreaShare: num(p.subpixel_area_share) } : null;
}

/* animation result: {scene, pattern: {family, samples_per_pixel}, e2, frames: [{frame, rmse,
 * max_dev, pixels_recomputed, pattern_sampled, reference_supersampled, pattern_seconds,
 * reference_seconds, tiles}], total: {rmse, max_dev, pixels, histogram, penalised_histogram},
 * times: {pattern_seconds, reference_seconds}, pixels: {recomputed, all_frames}}. */
export function animationTable(result) {
  const r = result || {};
  return {
    family: r.pattern ? str(r.pattern.family) : '',
    spp: r.pattern ? num(r.pattern.samples_per_pixel) : null,
    e2: num(r.e2),
    frames: list(r.frames).map((f) => ({
      frame: f.frame,
      rmse: num(f.rmse),
      maxDev: num(f.max_dev),
      recomputed: f.pixels_recomputed,
      patternSeconds: num(f.pattern_seconds),
      referenceSeconds: num(f.reference_seconds),
    })),
    total: r.total ? { rmse: num(r.total.rmse), maxDev: num(r.total.max_dev), pixels: r.total.pixels } : null,
    recomputed: r.pixels ? r.pixels.recomputed : null,
    allPixels: r.pixels ? r.pixels.all_frames : null,
  };
}

/* reference-convergence result: {scene, output_offset, baseline: {spp, seconds, supersampled,
 * samples}, rows: [{spp, rmse, max_dev, seconds, supersampled, samples}]}. */
export function convergenceTable(result) {
  const r = result || {};
  return {
    baselineSpp: r.baseline ? r.baseline.spp : null,
    baselineSeconds: r.baseline ? num(r.baseline.seconds) : null,
    rows: list(r.rows).map((x) => ({ spp: x.spp, rmse: num(x.rmse), maxDev: num(x.max_dev), seconds: num(x.seconds), samples: x.samples })),
  };
}

/* POST /v1/render: tiles {pattern, reference, difference, crop?} each {id, url, width, height}. */
export function renderImages(r) {
  const out = {};
  for (const k of ['pattern', 'reference', 'difference', 'crop']) if (r.tiles && r.tiles[k]) out[k] = r.tiles[k].url;
  return out;
}

/* POST /v1/render: e2, stats {rmse, max_dev, pixels, histogram, penalised_histogram}, times
 * {pattern_seconds, reference_seconds}, pixels {total, supersampled, ...}. */
export function renderStats(r) {
  const s = r.stats || {};
  return {
    rmse: num(s.rmse),
    maxDev: num(s.max_dev),
    e2: num(r.e2),
    patternSeconds: r.times ? num(r.times.pattern_seconds) : null,
    referenceSeconds: r.times ? num(r.times.reference_seconds) : null,
    supersampled: r.pixels ? num(r.pixels.supersampled) : null,
    totalPixels: r.pixels ? num(r.pixels.total) : null,
    histogram: Array.isArray(s.penalised_histogram) ? s.penalised_histogram : null,
  };
}

export function fmt(v, digits = 4) {
  return v == null || !Number.isFinite(v) ? '—' : v.toFixed(digits);
}

export function fmtSeconds(s) {
  if (s == null) return '—';
  return s < 1 ? `${(s * 1000).toFixed(1)} ms` : `${s.toFixed(2)} s`;
}

/* "P(4,1+,2)" -> "P(4,1+,n)": the family series a result belongs to. */
export function familySeries(label) {
  const m = /^P\(([^,]+),([^,]+),[^)]*\)$/.exec((label || '').replace(/\s+/g, ''));
  return m ? `P(${m[1]},${m[2]},n)` : label || 'other';
}

/* The pattern a link into Evaluate names: a sweep row (rank), random-stats' opt_w or opt_wp
 * (pick), else the job's best. Null when the job has none. */
export function jobPattern(job, { rank, pick } = {}) {
  const r = job.result;
  if (rank != null && r && Array.isArray(r.ranked)) {
    const row = r.ranked.find((x) => String(x.rank) === String(rank));
    return row && row.best ? wirePattern(row.best) : null;
  }
  if ((pick === 'opt_w' || pick === 'opt_wp') && r && r[pick]) return wirePattern(r[pick].pattern);
  return job.best ? job.best.pattern : null;
}

/* POST /v1/predict (predict_response.json): {scene, reference: {filter}, edges: {length[180],
 * total_length, locked_length, locked_edges, subpixel_area_share, ...}, predictions: [{pattern,
 * predicted_rmse, locked_share, subpixel_area_share, angles: [{angle, length, e1_rms, share}]
 * (costliest first), e1_by_angle?[180]}]}. One pattern's prediction with the scene's histogram;
 * null when the answer holds no prediction. */
export function predictionFrom(resp, index = 0) {
  const p = list(resp && resp.predictions)[index];
  if (!p) return null;
  const e = (resp && resp.edges) || {};
  const bins = (v) => (Array.isArray(v) && v.length === 180 ? v.map((x) => num(x) ?? 0) : null);
  return {
    rmse: num(p.predicted_rmse),
    lockedShare: num(p.locked_share),
    subpixelAreaShare: num(p.subpixel_area_share),
    subpixelEstimated: p.subpixel_error_estimated === true,
    angles: list(p.angles).map((a) => ({ angle: a.angle, length: num(a.length), e1: num(a.e1_rms), share: num(a.share) })),
    e1ByAngle: bins(p.e1_by_angle),
    edgeLength: bins(e.length),
    totalLength: num(e.total_length),
    lockedLength: num(e.locked_length),
    filter: resp.reference ? str(resp.reference.filter) : '',
  };
}

/* Measured over predicted RMSE; null unless both are there and the prediction is above 0. */
export function predictionRatio(measured, predicted) {
  return measured != null && predicted != null && predicted > 0 ? measured / predicted : null;
}

/* The costliest angles of a prediction (already sorted by the daemon), the first `count`, and
 * the share of all the others together. */
export function costliestAngles(angles, count = 6) {
  const top = angles.slice(0, count);
  const rest = angles.slice(count).reduce((s, a) => s + (a.share ?? 0), 0);
  return { top, rest, restCount: Math.max(0, angles.length - count) };
}

/* "12.3 %" of a 0..1 share; "—" when absent. */
export function fmtShare(v, digits = 1) {
  return v == null || !Number.isFinite(v) ? '—' : `${(v * 100).toFixed(digits)} %`;
}

/* The submitted settings of a job (its spec less the kind) as [name, text] pairs in the spec's
 * order: numbers and strings as they are, a pattern or other object shortened to what names it
 * ({"preset": "rgss"} -> rgss; a pattern -> "pattern, N kernels"), long lists by their length.
 * Settings left out of the spec took the daemon's defaults. */
export function jobSettings(spec) {
  const out = [];
  for (const [k, v] of Object.entries(spec || {})) {
    if (k === 'kind') continue;
    out.push([k, settingText(v)]);
  }
  return out;
}

function settingText(v) {
  if (v == null) return '—';
  if (typeof v === 'number' || typeof v === 'boolean' || typeof v === 'string') return String(v);
  if (Array.isArray(v)) {
    const inner = v.map(settingText).join(', ');
    return inner.length <= 60 ? `[${inner}]` : `${v.length} items`;
  }
  if (typeof v.preset === 'string' && Object.keys(v).length === 1) return v.preset;
  if (typeof v.job !== 'undefined' && Object.keys(v).length <= 2) return `job ${v.job}`;
  const kernels = Array.isArray(v.kernels) ? v.kernels : Array.isArray(v.kernels_expanded) ? v.kernels_expanded : null;
  if (kernels) return `pattern${v.family ? ` ${v.family}` : ''}, ${kernels.length} kernel${kernels.length === 1 ? '' : 's'}`;
  if (Array.isArray(v.mirrored)) return `mirrored pattern, ${v.mirrored.length} samples`;
  const inner = Object.entries(v).map(([k, x]) => `${k} ${settingText(x)}`).join(', ');
  return inner.length <= 80 ? inner : `${Object.keys(v).length} settings`;
}

/* How long a job waited, ran and was paused (seconds; null where not known yet): queued is
 * started - created (now - created while it waits), ran is finished - started (now - started
 * while it runs), paused the running job's time with its worker lent to others (fair share). */
export function jobTimings(job, now = Date.now() / 1000) {
  const created = num(job.created);
  const started = num(job.started);
  const finished = num(job.finished);
  const queued = created == null ? null : (started ?? (job.state === 'queued' ? now : null)) == null ? null : (started ?? now) - created;
  const ran = started == null ? null : (finished ?? (ACTIVE_STATES.has(job.state) ? now : null)) == null ? null : (finished ?? now) - started;
  return { created, started, finished, queued, ran, paused: num(job.pausedSeconds) };
}

/* "queued 0.2 s · ran 2.05 s · paused 0.0 s" (parts not known are left out). */
export function timingsText(t) {
  const part = (name, v) => (v == null ? null : `${name} ${fmtDuration(v)}`);
  return [part('queued', t.queued), part('ran', t.ran), part('paused', t.paused)].filter(Boolean).join(' · ') || '—';
}

export function fmtDuration(s) {
  if (s == null || !Number.isFinite(s)) return '—';
  if (s < 60) return `${s.toFixed(s < 10 ? 2 : 1)} s`;
  const m = Math.floor(s / 60);
  return m < 60 ? `${m} min ${Math.round(s - 60 * m)} s` : `${Math.floor(m / 60)} h ${m % 60} min`;
}

/* optimize result's per_seed: [{seed, distribution, initial_e2, e2, iterations}] (sorted by
 * seed), and the best seed's index. */
export function optimizeSeeds(result) {
  const rows = list(result && result.per_seed).map((x) => ({ seed: x.seed, distribution: str(x.distribution), initial: num(x.initial_e2), e2: num(x.e2), iterations: x.iterations }));
  let best = -1;
  rows.forEach((r, i) => {
    if (r.e2 != null && (best < 0 || r.e2 < rows[best].e2)) best = i;
  });
  return { rows, best };
}

/* The images of a compare result: the reference's and, per row, the pattern's render and its
 * difference ({url, width, height} or null). */
export function comparisonImages(result) {
  const r = result || {};
  const ref = list(r.reference && r.reference.renders)[0];
  const img = (t) => (t && typeof t.url === 'string' ? { url: t.url, width: t.width, height: t.height } : null);
  return {
    reference: img(ref && ref.tile),
    rows: list(r.rows).map((x) => ({ label: str(x.name), pattern: img(x.tiles && x.tiles.pattern), difference: img(x.tiles && x.tiles.difference) })),
  };
}

/* The images of an animation result per frame: pattern, reference and difference. */
export function animationImages(result) {
  const img = (t) => (t && typeof t.url === 'string' ? { url: t.url, width: t.width, height: t.height } : null);
  return list(result && result.frames).map((f) => ({ frame: f.frame, pattern: img(f.tiles && f.tiles.pattern), reference: img(f.tiles && f.tiles.reference), difference: img(f.tiles && f.tiles.difference) }));
}
