// Normalises API answers into the shapes the views draw. The wire format of issue 4 fixes the
// request side; for answers we accept the documented field names and a few natural variants so
// the page keeps working while the service grows (every accessor below is small and pure).

export function listFrom(resp, ...keys) {
  if (Array.isArray(resp)) return resp;
  if (resp && typeof resp === 'object') {
    for (const k of keys) if (Array.isArray(resp[k])) return resp[k];
    for (const v of Object.values(resp)) if (Array.isArray(v)) return v;
  }
  return [];
}

export function num(v) {
  return typeof v === 'number' && Number.isFinite(v) ? v : null;
}

/* The pattern part of an object holding one ({kernels}, {mirrored}, {tile...}, {preset}). */
export function patternOf(obj) {
  if (!obj || typeof obj !== 'object') return null;
  if (obj.pattern && typeof obj.pattern === 'object') return patternOf(obj.pattern) || obj.pattern;
  if (Array.isArray(obj.kernels) && Array.isArray(obj.kernels[0])) return { kernels: obj.kernels };
  if (Array.isArray(obj.mirrored)) return { mirrored: obj.mirrored };
  if (obj.tile && typeof obj.tile === 'object')
    return Array.isArray(obj.kernels_expanded) ? { tile: obj.tile, kernels_expanded: obj.kernels_expanded } : { tile: obj.tile };
  if (typeof obj.preset === 'string') return { preset: obj.preset };
  return null;
}

export function normPreset(p) {
  if (typeof p === 'string') return { name: p, family: '', cost_spp: null, pattern: { preset: p } };
  return {
    name: p.name,
    family: p.family || '',
    cost_spp: num(p.cost_spp) ?? num(p.cost),
    source: p.source || '',
    note: p.note || '',
    // A number, or {source: value} in data/presets.json.
    published: typeof p.published_e2 === 'number' ? p.published_e2 : p.published_e2 && typeof p.published_e2 === 'object' ? num(Object.values(p.published_e2)[0]) : null,
    pattern: patternOf(p) || { preset: p.name },
  };
}

function isAngleRow(o) {
  return o && typeof o === 'object' && !Array.isArray(o) && 'angle_deg' in o && ('e1' in o || 'weighted' in o);
}

/* Per-kernel per-angle rows, found wherever the detail lives in the answer. */
export function perKernelRows(resp) {
  const found = [];
  const visit = (v, depth) => {
    if (depth > 5 || v == null || typeof v !== 'object') return;
    if (Array.isArray(v)) {
      if (v.length && v.every(isAngleRow)) {
        found.push(v);
        return;
      }
      v.forEach((x) => visit(x, depth + 1));
      return;
    }
    for (const [k, x] of Object.entries(v)) if (k !== 'pattern') visit(x, depth + 1);
  };
  visit(resp, 0);
  if (found.length === 1 && found[0].some((r) => 'kernel' in r)) {
    const byKernel = [];
    for (const r of found[0]) (byKernel[r.kernel] ||= []).push(r);
    return byKernel.filter(Boolean).map(rowsNormalised);
  }
  return found.map(rowsNormalised);
}

function rowsNormalised(rows) {
  return rows
    .map((r) => {
      const e1 = num(r.e1);
      const w = num(r.weight) ?? num(r.w) ?? (e1 && num(r.weighted) != null ? r.weighted / e1 : null);
      return { angle: r.angle_deg, weight: w, e1, weighted: num(r.weighted) ?? (w != null && e1 != null ? w * e1 : null) };
    })
    .sort((a, b) => a.angle - b.angle);
}

export function normEvaluation(resp) {
  const argmax = resp.argmax || {};
  return {
    e2: num(resp.e2),
    argmaxKernel: num(argmax.kernel) ?? 0,
    argmaxAngle: num(argmax.angle_deg) ?? num(argmax.angle),
    family: resp.family || '',
    cost: num(resp.cost_spp) ?? num(resp.cost),
    kernels: perKernelRows(resp),
    raw: resp,
  };
}

const TRACE_ORDER = ['seconds', 'iterations', 'evaluations', 'best_e2'];

export function normTrace(trace) {
  if (!Array.isArray(trace)) return [];
  return trace
    .map((p) => {
      if (Array.isArray(p)) return Object.fromEntries(TRACE_ORDER.map((k, i) => [k, p[i]]));
      return {
        seconds: num(p.seconds) ?? num(p.t) ?? num(p.time),
        iterations: num(p.iterations),
        evaluations: num(p.evaluations),
        best_e2: num(p.best_e2) ?? num(p.e2),
      };
    })
    .filter((p) => p.seconds != null && p.best_e2 != null);
}

/* The best pattern a job has found: {e2, pattern, family, cost} or null. A finished job's result
 * is authoritative ({best: pattern, e2, ...}); "best" is the best-so-far posted while running. */
export function jobBest(j) {
  const specFamily = (j.spec && j.spec.family) || j.family || '';
  const r = j.result;
  if (r && typeof r === 'object' && r.best && typeof r.best === 'object') {
    const pattern = patternOf(r.best);
    if (pattern)
      return {
        e2: num(r.e2) ?? num(r.best.e2) ?? num(r.best_e2),
        pattern,
        family: r.family || r.best.family || (r.best.pattern && r.best.pattern.family) || specFamily,
        cost: num(r.best.cost_spp) ?? num(r.cost_spp) ?? num(r.best.pattern && r.best.pattern.cost_spp),
      };
  }
  for (const c of [j.best, j.best_so_far, r]) {
    if (!c || typeof c !== 'object') continue;
    const pattern = patternOf(c);
    if (pattern || num(c.e2) != null)
      return {
        e2: num(c.e2) ?? num(c.best_e2),
        pattern,
        family: c.family || (c.pattern && c.pattern.family) || specFamily,
        cost: num(c.cost_spp) ?? num(c.cost) ?? num(c.pattern && c.pattern.cost_spp),
      };
  }
  return null;
}

export const ACTIVE_STATES = new Set(['queued', 'running']);

export function normJob(j) {
  const spec = j.spec || {};
  const trace = normTrace(j.trace || (j.result && j.result.trace) || []);
  const best = jobBest(j);
  let progress = num(j.progress);
  if (progress == null) progress = j.state === 'done' ? 1 : 0;
  return {
    id: j.id,
    kind: j.kind || spec.kind || '',
    state: j.state || 'unknown',
    progress: Math.max(0, Math.min(1, progress)),
    best,
    bestE2: best && best.e2 != null ? best.e2 : trace.length ? trace[trace.length - 1].best_e2 : null,
    trace,
    family: spec.family || j.family || (best && best.family) || '',
    error: (j.error && (j.error.message || j.error)) || j.reason || '',
    created: j.created || j.created_at || j.submitted || null,
    result: j.result || null,
    spec,
    raw: j,
  };
}

/* Tile image URLs of a render answer: pattern, reference, difference (and crop if any). */
export function renderImages(r) {
  const out = {};
  const classify = (key) => {
    const k = key.toLowerCase();
    if (k.includes('ref')) return 'reference';
    if (k.includes('diff')) return 'difference';
    if (k.includes('crop') || k.includes('zoom') || k.includes('magn')) return 'crop';
    if (k.includes('pattern') || k === 'image' || k === 'tile') return 'pattern';
    return null;
  };
  const toUrl = (v) => {
    if (typeof v === 'string') return v.includes('/') ? v : `/v1/tiles/${v.replace(/\.png$/, '')}.png`;
    if (typeof v === 'number') return `/v1/tiles/${v}.png`;
    if (v && typeof v === 'object') return toUrl(v.url || v.href || v.id || v.path);
    return null;
  };
  // Inside a container named like "tiles"/"images"/"urls", a bare id or URL under "pattern",
  // "reference", ... is an image; elsewhere the key must say so ("reference_url", "diff_id").
  const scan = (obj, depth, container) => {
    if (!obj || typeof obj !== 'object' || depth > 2) return;
    for (const [k, v] of Object.entries(obj)) {
      const cls = classify(k);
      const lk = k.toLowerCase();
      const scalar = typeof v === 'string' || typeof v === 'number';
      const looksLikeImage =
        (typeof v === 'string' && (/\.png$/.test(v) || /^\/v1\/tiles\//.test(v))) ||
        (cls && scalar && (container || /(_url|_id|_tile|_png)$/.test(lk))) ||
        (cls && v && typeof v === 'object' && !Array.isArray(v) && (v.url || v.id != null));
      if (cls && looksLikeImage && !out[cls]) out[cls] = toUrl(v);
      else if (v && typeof v === 'object' && !Array.isArray(v)) scan(v, depth + 1, /tile|image|png|url/.test(lk));
    }
  };
  scan(r, 0, false);
  return out;
}

export function renderStats(r) {
  const s = r.stats && typeof r.stats === 'object' ? { ...r, ...r.stats } : r;
  const hist = s.penalised_histogram || s.penalized_histogram || s.histogram || null;
  let histogram = null;
  if (Array.isArray(hist)) histogram = hist.map((v) => (Array.isArray(v) ? v[1] : num(v) ?? num(v && v.value) ?? 0));
  else if (hist && Array.isArray(hist.values)) histogram = hist.values;
  else if (hist && Array.isArray(hist.bins)) histogram = hist.bins;
  const t = s.times || s.timing || s;
  return {
    rmse: num(s.rmse),
    maxDev: num(s.max_deviation) ?? num(s.max_dev) ?? num(s.maxdev),
    e2: num(s.e2),
    patternSeconds: num(t.pattern_seconds) ?? num(t.pattern_s) ?? num(t.pattern_time) ?? num(t.pattern),
    referenceSeconds: num(t.reference_seconds) ?? num(t.reference_s) ?? num(t.reference_time) ?? num(t.reference),
    supersampled: num(r.pixels && r.pixels.supersampled) ?? num(s.supersampled_pixels) ?? num(s.supersampled),
    totalPixels: num(r.pixels && r.pixels.total),
    histogram,
  };
}

/* Rows of a comparison job's result: {label, spp, e2, rmse, maxDev, seconds}. */
export function comparisonRows(result) {
  return listFrom(result, 'rows', 'table', 'patterns').map((r, i) => ({
    label: r.name || r.label || (r.pattern && r.pattern.preset) || (r.job != null ? `job ${r.job}` : `#${i + 1}`),
    spp: num(r.samples_per_pixel) ?? num(r.spp) ?? num(r.cost_spp),
    e2: num(r.e2),
    rmse: num(r.rmse),
    maxDev: num(r.max_deviation) ?? num(r.max_dev),
    seconds: num(r.render_seconds) ?? num(r.seconds) ?? num(r.time) ?? num(r.render_time),
  }));
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
