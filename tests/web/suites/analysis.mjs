// Evaluate's point-set analysis panel (issue 31): every figure shown equals POST /v1/analyze's for
// the evaluated pattern; the periodogram image has one cell per frequency, each drawn in the
// colour of the API's P(k) (a regular 8x8 grid: dark everywhere but at multiples of 8); radius and
// PCF bins re-query; bad values show the error beside their field and clear the old result; the
// analysis waits for the evaluation, a new evaluation aborts it, a collapsed panel asks nothing;
// at 1400x1000 and 1000x800 the page fits the window and no plot labels overlap.

import { assert, eventually } from '../lib/check.mjs';
import { overlappingLabels } from '../lib/labels.mjs';

const SIZES = [
  { width: 1400, height: 1000, preset: 'd3d-8x' },
  { width: 1000, height: 800, preset: 'd3d-16x' },
];

/* The panel's answer for the next action: the state is reset first so an old "done" does not
 * count. */
async function resetState(page) {
  await page.evaluate(() => (document.getElementById('ev-analysis').dataset.state = 'test-reset'));
}
async function waitState(page, state, timeout = 20000) {
  await page
    .waitForFunction((s) => document.getElementById('ev-analysis').dataset.state === s, state, { timeout })
    .catch(async () => {
      const now = await page.evaluate(() => [document.getElementById('ev-analysis').dataset.state, document.getElementById('an-status').textContent]);
      throw new Error(`panel state ${JSON.stringify(now)}, waited for "${state}"`);
    });
}

/* Every td[data-key] of the figures table: key -> {value (exact, as a string), text}. */
function shownFigures(page) {
  return page.$$eval('#an-figures td[data-key]', (tds) => Object.fromEntries(tds.map((td) => [td.dataset.key, { value: td.dataset.value, text: td.textContent }])));
}

/* The table against the API answer: the exact number kept and six significant digits shown,
 * and every scalar figure of the answer has a cell. */
async function checkFigures(page, ref) {
  const shown = await shownFigures(page);
  const problems = [];
  for (const group of ['discrepancy', 'spacing', 'spectrum']) {
    assert(ref[group], `API answer has no ${group}`);
    for (const [name, v] of Object.entries(ref[group])) {
      if (Array.isArray(v) || name === 'radius') continue;
      const key = `${group}.${name}`;
      const cell = shown[key];
      if (!cell) {
        problems.push(`${key}: no cell in the table`);
        continue;
      }
      if (v == null) {
        if (cell.value !== '' || cell.text !== '—') problems.push(`${key}: API null, shown ${JSON.stringify(cell)}`);
        continue;
      }
      if (cell.value !== String(v)) problems.push(`${key}: holds ${cell.value}, API ${v}`);
      const t = Number(cell.text);
      const rel = v === 0 ? Math.abs(t) : Math.abs(t - v) / Math.abs(v);
      if (!(rel <= 5e-6)) problems.push(`${key}: shows "${cell.text}", API ${v}`);
    }
  }
  assert(!problems.length, problems.join('\n'));
  // The roots are the squares' roots: the table does not mix them up.
  for (const n of ['centered', 'wrap_around', 'mixture', 'l2_star']) {
    const root = Number(shown[`discrepancy.${n}`].value);
    const sq = Number(shown[`discrepancy.${n}_squared`].value);
    assert(Math.abs(root * root - sq) <= 1e-12 * Math.max(1, sq), `${n}: root ${root} squared is not ${sq}`);
  }
}

/* Canvas size, and per frequency the drawn colour and the colour the API's P(k) maps to. */
function imageAgainst(page, spectrum) {
  return page.evaluate(async (s) => {
    const mod = await import('/js/periodogram-image.js');
    const canvas = document.querySelector('#an-periodogram canvas');
    if (!canvas) return { error: 'no canvas' };
    const r = s.radius;
    const cell = Number(canvas.dataset.cell);
    const scale = mod.colourScale(s.power);
    const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    const wrong = [];
    const colours = new Set();
    const cells = {};
    for (let ky = -r; ky <= r; ky++)
      for (let kx = -r; kx <= r; kx++) {
        const x = (kx + r) * cell + Math.floor(cell / 2);
        const y = (r - ky) * cell + Math.floor(cell / 2);
        const o = (y * canvas.width + x) * 4;
        const got = [data[o], data[o + 1], data[o + 2]];
        const want = mod.colourOf(s.power[ky + r][kx + r], scale, { dc: kx === 0 && ky === 0 });
        colours.add(got.join(','));
        cells[`${kx},${ky}`] = got.join(',');
        if (got.join(',') !== want.join(',') || data[o + 3] !== 255) wrong.push(`(${kx},${ky}) drawn ${got} want ${want} for P=${s.power[ky + r][kx + r]}`);
      }
    const box = canvas.getBoundingClientRect();
    const labels = [...document.querySelectorAll('#an-periodogram svg text')].map((t) => t.textContent);
    return {
      width: canvas.width,
      height: canvas.height,
      cell,
      cssWidth: box.width,
      cssHeight: box.height,
      wrong: wrong.slice(0, 5),
      wrongCount: wrong.length,
      distinct: colours.size,
      cells,
      floor: mod.LUT[0].join(','),
      top: mod.LUT[255].join(','),
      dc: mod.DC_COLOUR.join(','),
      hiLabel: mod.powerOfTen(scale.hiExp),
      loLabel: '≤' + mod.powerOfTen(scale.loExp),
      labels,
    };
  }, spectrum);
}

/* Vertices of a line plot's series path. */
function pathVertices(page, id) {
  return page.$eval(`#${id} path.series-line`, (p) => (p.getAttribute('d').match(/[ML]/g) || []).length).catch(() => 0);
}

/* The panel's own geometry: its SVG text at least 11 px on screen, its figures side by side
 * without overlapping, every one inside the window, the image inside its frame. */
function panelGeometry(page) {
  return page.evaluate(() => {
    const out = [];
    for (const svg of document.querySelectorAll('#ev-analysis svg')) {
      const vb = svg.viewBox.baseVal;
      const r = svg.getBoundingClientRect();
      const scale = Math.min(r.width / vb.width, r.height / vb.height);
      for (const t of svg.querySelectorAll('text'))
        if (parseFloat(getComputedStyle(t).fontSize) * scale < 10.5) out.push(`"${t.textContent}" ${(parseFloat(getComputedStyle(t).fontSize) * scale).toFixed(1)} px`);
    }
    const items = [...document.querySelectorAll('#ev-analysis .analysis-grid figure, #ev-analysis .analysis-grid table')].map((e) => ({ id: e.id || e.firstElementChild.id, r: e.getBoundingClientRect() }));
    if (items.length !== 4 || items.some((i) => !(i.r.width > 0 && i.r.height > 0))) out.push(`figures: ${JSON.stringify(items)}`);
    for (let i = 0; i < items.length; i++) {
      const a = items[i].r;
      if (a.right > window.innerWidth + 0.5) out.push(`${items[i].id} ends at ${a.right} px in a ${window.innerWidth} px window`);
      for (let j = i + 1; j < items.length; j++) {
        const b = items[j].r;
        if (Math.min(a.right, b.right) - Math.max(a.left, b.left) > 1 && Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top) > 1) out.push(`${items[i].id} overlaps ${items[j].id}`);
      }
    }
    for (const t of document.querySelectorAll('#ev-analysis figcaption, #ev-analysis table, #ev-analysis .analysis-controls'))
      if (t.getBoundingClientRect().right > window.innerWidth + 0.5) out.push(`${t.id || t.className} past the window's right edge`);
    const canvas = document.querySelector('#an-periodogram canvas');
    const frame = document.querySelector('#an-periodogram svg rect.frame').getBoundingClientRect();
    const c = canvas.getBoundingClientRect();
    if (Math.abs(c.left - frame.left) > 1.5 || Math.abs(c.right - frame.right) > 1.5 || Math.abs(c.top - frame.top) > 1.5 || Math.abs(c.bottom - frame.bottom) > 1.5)
      out.push(`image ${JSON.stringify(c)} not on its frame ${JSON.stringify(frame)}`);
    for (const el of document.querySelectorAll('#ev-analysis figcaption, #ev-analysis td, #ev-analysis th, #ev-analysis label, #ev-analysis summary'))
      if (el.textContent.trim() && parseFloat(getComputedStyle(el).fontSize) < 11) out.push(`${el.tagName} "${el.textContent.slice(0, 30)}" ${getComputedStyle(el).fontSize}`);
    return out;
  });
}

/* A regular k x k grid on the unit square as a points pattern (tile 1, equal weights). */
function gridPattern(k) {
  let text = '';
  for (let j = 0; j < k; j++) for (let i = 0; i < k; i++) text += `${(i + 0.5) / k} ${(j + 0.5) / k}\n`;
  return { points: { format: 'utk', text, weights: 'equal' } };
}

export default async function analysisSuite({ page, base, api, step, shot, consoleProblems, artifacts }) {
  // Every analyze request the page sends, with its time and body, and when evaluations answer.
  const log = [];
  page.on('request', (req) => {
    const u = new URL(req.url());
    if (req.method() === 'POST' && (u.pathname === '/v1/analyze' || u.pathname === '/v1/evaluate')) log.push({ what: `${u.pathname} sent`, t: Date.now(), body: req.postDataJSON() });
  });
  page.on('requestfinished', (req) => {
    const u = new URL(req.url());
    if (req.method() === 'POST' && u.pathname === '/v1/evaluate') log.push({ what: '/v1/evaluate answered', t: Date.now() });
  });
  page.on('requestfailed', (req) => {
    const u = new URL(req.url());
    if (u.pathname === '/v1/analyze') log.push({ what: '/v1/analyze failed', t: Date.now(), error: req.failure() && req.failure().errorText });
  });
  const analyzeSent = () => log.filter((e) => e.what === '/v1/analyze sent');
  const options = { spectrum: { radius: 32 }, pcf: { bins: 64 } };

  let ref;
  await step('D3D 16x: the figures shown equal POST /v1/analyze, asked after the evaluation', async () => {
    await page.setViewportSize({ width: SIZES[0].width, height: SIZES[0].height });
    // The page opens on its default preset: let that settle first, so its answer cannot pass for
    // D3D 16x's.
    await waitState(page, 'done');
    const start = log.length;
    await resetState(page);
    await page.goto(`${base}/#/evaluate?preset=d3d-16x`);
    await waitState(page, 'done');
    ref = await api('POST', '/v1/analyze', { pattern: { preset: 'd3d-16x' }, ...options });
    assert(ref.points === 16 && ref.spectrum.radius === 32, `API answer: ${ref.points} points, radius ${ref.spectrum.radius}`);
    await checkFigures(page, ref);
    const sent = log.slice(start).filter((e) => e.what === '/v1/analyze sent');
    assert(sent.length === 1, `${sent.length} analyze requests for one evaluation`);
    assert(JSON.stringify(sent[0].body) === JSON.stringify({ pattern: { preset: 'd3d-16x' }, ...options }), `request ${JSON.stringify(sent[0].body)}`);
    const answered = log.slice(start).filter((e) => e.what === '/v1/evaluate answered');
    assert(answered.length && answered[answered.length - 1].t <= sent[0].t, 'the analysis was asked before the evaluation answered');
    const points = await page.textContent('#an-points');
    assert(points.includes('16 points') && points.includes(ref.family), `points line "${points}"`);
  });

  await step('periodogram: (2r+1)·cell pixels, every frequency drawn in the colour of the API\'s P(k), DC white', async () => {
    const img = await imageAgainst(page, ref.spectrum);
    assert(!img.error, img.error);
    assert(img.cell === Math.max(1, Math.floor(320 / 65)) && img.width === 65 * img.cell && img.height === img.width, `canvas ${img.width}x${img.height}, cell ${img.cell} at radius 32`);
    assert(img.cssWidth > 200 && Math.abs(img.cssWidth - img.cssHeight) < 1, `image shown ${img.cssWidth}x${img.cssHeight} px`);
    assert(img.wrongCount === 0, `${img.wrongCount} cells off the API's colour: ${img.wrong.join('; ')}`);
    assert(img.distinct >= 20, `only ${img.distinct} distinct colours: a trivial image`);
    assert(img.cells['0,0'] === img.dc, `DC drawn ${img.cells['0,0']}`);
    assert(await page.$('#an-periodogram circle.pgram-dc'), 'DC not ringed');
    for (const l of [img.hiLabel, img.loLabel, 'kx (cycles per tile)', 'ky']) assert(img.labels.includes(l), `no label "${l}" in ${JSON.stringify(img.labels)}`);
    const legend = await page.textContent('#an-periodogram-legend');
    assert(/log₁₀ P\(k\)/.test(legend) && /DC/.test(legend), `legend "${legend}"`);
  });

  await step('radial spectrum, anisotropy and PCF drawn from the API\'s arrays', async () => {
    const radial = await pathVertices(page, 'an-radial');
    const defined = ref.spectrum.anisotropy_db.slice(1).filter((v) => v != null).length;
    const aniso = await page.$$eval('#an-anisotropy path.series-line, #an-anisotropy circle', (e) => e.length);
    const pcf = await pathVertices(page, 'an-pcf');
    assert(radial === 32, `radial curve has ${radial} vertices, want 32 (annuli 1..32)`);
    assert(defined > 0 && aniso > 0, `anisotropy: ${defined} defined values, ${aniso} drawn elements`);
    assert(pcf === ref.pcf.g.filter((v) => v != null).length && pcf === 64, `PCF curve has ${pcf} vertices, API ${ref.pcf.g.length} bins`);
    for (const id of ['an-radial', 'an-anisotropy', 'an-pcf']) assert(await page.$(`#${id} line.ref-line`), `${id}: no reference line`);
    await shot('analysis');
  });

  await step('radius 16 and 32 PCF bins re-query and redraw, equal to the API', async () => {
    const before = analyzeSent().length;
    await resetState(page);
    await page.fill('#an-radius', '16');
    await page.$eval('#an-radius', (e) => e.blur()); // the native change, once (a dispatched one plus a later blur made two)
    await waitState(page, 'done');
    await resetState(page);
    await page.fill('#an-bins', '32');
    await page.$eval('#an-bins', (e) => e.blur());
    await waitState(page, 'done');
    const sent = analyzeSent().slice(before);
    assert(sent.length === 2 && sent[0].body.spectrum.radius === 16 && sent[1].body.pcf.bins === 32, `requests ${JSON.stringify(sent.map((s) => [s.body.spectrum, s.body.pcf]))}`);
    ref = await api('POST', '/v1/analyze', { pattern: { preset: 'd3d-16x' }, spectrum: { radius: 16 }, pcf: { bins: 32 } });
    await checkFigures(page, ref);
    const img = await imageAgainst(page, ref.spectrum);
    assert(img.width === 33 * Math.floor(320 / 33) && img.wrongCount === 0, `radius 16: canvas ${img.width} px, ${img.wrongCount} cells off (${img.wrong.join('; ')})`);
    assert((await pathVertices(page, 'an-radial')) === 16, 'radial curve not 16 annuli');
    assert((await pathVertices(page, 'an-pcf')) === 32, 'PCF curve not 32 bins');
  });

  await step('radius 200: the daemon\'s 400 shown beside the field, naming spectrum.radius; old result cleared', async () => {
    const before = consoleProblems.length;
    await resetState(page);
    await page.fill('#an-radius', '200');
    await page.$eval('#an-radius', (e) => e.blur()); // the native change, once (a dispatched one plus a later blur made two)
    await waitState(page, 'error');
    const msg = await page.textContent('#an-radius-error');
    assert(/spectrum\.radius/.test(msg) && /1 to 128/.test(msg), `radius error "${msg}"`);
    assert((await page.getAttribute('#an-radius', 'aria-invalid')) === 'true', 'radius not marked invalid');
    assert(!(await page.$('#an-periodogram canvas')) && !(await page.$('#an-radial svg')) && !(await page.$('#an-pcf svg')), 'old plots still shown');
    const figs = Object.values(await shownFigures(page));
    assert(figs.every((f) => f.text === '—' && f.value === ''), `old figures still shown: ${JSON.stringify(figs.slice(0, 3))}`);
    const provoked = consoleProblems.splice(before);
    const unexpected = provoked.filter((m) => !(/\b400\b/.test(m) && /\/v1\/analyze\b/.test(m)));
    consoleProblems.push(...unexpected);
    assert(provoked.length > unexpected.length, 'no 400 answer seen');
    await shot('analysis-error');
  });

  await step('radius 1.5: refused on the page (no request), naming spectrum.radius; 32 brings the result back', async () => {
    const before = analyzeSent().length;
    await resetState(page);
    await page.fill('#an-radius', '1.5');
    await page.$eval('#an-radius', (e) => e.blur()); // the native change, once (a dispatched one plus a later blur made two)
    await waitState(page, 'error');
    const msg = await page.textContent('#an-radius-error');
    assert(/spectrum\.radius/.test(msg) && /whole number/.test(msg), `radius error "${msg}"`);
    assert(analyzeSent().length === before, 'a request was sent for 1.5');
    await resetState(page);
    await page.fill('#an-radius', '32');
    await page.fill('#an-bins', '64');
    await page.click('#an-run');
    await waitState(page, 'done');
    assert((await page.textContent('#an-radius-error')) === '', 'the error stays after a good radius');
    assert((await page.getAttribute('#an-radius', 'aria-invalid')) === 'false', 'radius still marked invalid');
    ref = await api('POST', '/v1/analyze', { pattern: { preset: 'd3d-16x' }, ...options });
    await checkFigures(page, ref);
  });

  await step('regular 8x8 grid (points form): P(k) is zero except at multiples of 8, and so is the image', async () => {
    const pattern = gridPattern(8);
    // The new radius first, answered, so that its change event (on blur) cannot come later.
    await resetState(page);
    await page.fill('#an-radius', '20');
    await page.$eval('#an-radius', (e) => e.blur()); // the native change, once (a dispatched one plus a later blur made two)
    await waitState(page, 'done');
    await resetState(page);
    await page.click('#ev-paste summary');
    await page.fill('#ev-json', JSON.stringify(pattern));
    await page.click('#ev-apply');
    await waitState(page, 'done');
    await page.click('#ev-paste summary');
    const grid = await api('POST', '/v1/analyze', { pattern, spectrum: { radius: 20 }, pcf: { bins: 64 } });
    await checkFigures(page, grid);
    const r = 20;
    const bad = [];
    for (let ky = -r; ky <= r; ky++)
      for (let kx = -r; kx <= r; kx++) {
        const p = grid.spectrum.power[ky + r][kx + r];
        const onLattice = kx % 8 === 0 && ky % 8 === 0;
        if (onLattice ? Math.abs(p - 64) > 1e-9 : !(Math.abs(p) < 1e-20)) bad.push(`P(${kx},${ky}) = ${p}`);
      }
    assert(!bad.length, `API periodogram of the grid: ${bad.slice(0, 5).join('; ')}`);
    const img = await imageAgainst(page, grid.spectrum);
    assert(img.wrongCount === 0, `${img.wrongCount} cells off the API's colour: ${img.wrong.join('; ')}`);
    const off = [];
    for (const [k, c] of Object.entries(img.cells)) {
      const [kx, ky] = k.split(',').map(Number);
      const onLattice = kx % 8 === 0 && ky % 8 === 0;
      if (kx === 0 && ky === 0) continue;
      if (onLattice ? c === img.floor : c !== img.floor) off.push(`(${k}) ${c}`);
    }
    assert(!off.length, `image not dark exactly off the multiples of 8: ${off.slice(0, 6).join('; ')}`);
    // 64 on a scale to 10^2: bright, in the top fifth of the colours.
    const peak = img.cells['8,0'].split(',').map(Number);
    const top = img.top.split(',').map(Number);
    assert(peak[0] > 150 && peak[1] > 180 && Math.abs(peak[1] - top[1]) < 60, `peak colour ${peak}, top ${top}`);
    await shot('analysis-grid');
  });

  await step('a one-sample preset (centroid): the 400 names the pattern, in place, nothing old left', async () => {
    const before = consoleProblems.length;
    await resetState(page);
    await page.fill('#an-radius', '32');
    await page.$eval('#an-radius', (e) => e.blur()); // the native change, once (a dispatched one plus a later blur made two)
    await waitState(page, 'done');
    await resetState(page);
    await page.goto(`${base}/#/evaluate?preset=centroid`);
    await waitState(page, 'error');
    const status = await page.textContent('#an-status');
    assert(/field pattern/.test(status) && /2 to 4096/.test(status), `status "${status}"`);
    assert(!(await page.$('#an-periodogram canvas')), 'old image still shown');
    const provoked = consoleProblems.splice(before);
    consoleProblems.push(...provoked.filter((m) => !(/\b400\b/.test(m) && /\/v1\/analyze\b/.test(m))));
  });

  await step('a new evaluation aborts the analysis in flight; only the new pattern\'s figures show', async () => {
    // Hold analyze answers until released, so one is surely in flight when the next preset comes.
    let release;
    const held = new Promise((r) => (release = r));
    let heldCount = 0;
    await page.route('**/v1/analyze', async (route) => {
      if (heldCount++ === 0) await held;
      await route.continue().catch(() => {});
    });
    const before = log.length;
    await page.goto(`${base}/#/evaluate?preset=rgss`);
    await eventually(() => analyzeSent().length && log.slice(before).some((e) => e.what === '/v1/analyze sent'), { message: 'the RGSS analysis to be sent' });
    await waitState(page, 'running');
    await resetState(page);
    await page.goto(`${base}/#/evaluate?preset=flipquad`);
    await eventually(() => log.slice(before).some((e) => e.what === '/v1/analyze failed' && /ABORTED/.test(e.error)), { message: 'the RGSS analysis to be aborted' });
    release();
    await waitState(page, 'done');
    await page.unroute('**/v1/analyze');
    const flip = await api('POST', '/v1/analyze', { pattern: { preset: 'flipquad' }, ...options });
    await checkFigures(page, flip);
    const sent = log.slice(before).filter((e) => e.what === '/v1/analyze sent').map((e) => e.body.pattern.preset);
    assert(JSON.stringify(sent) === JSON.stringify(['rgss', 'flipquad']), `analyses sent for ${sent}`);
  });

  await step('a drag evaluates without the panel: no analysis is asked while an evaluation is in flight, one at the end', async () => {
    await resetState(page);
    await page.goto(`${base}/#/evaluate?preset=quincunx`);
    await waitState(page, 'done');
    const before = log.length;
    const dot = page.locator('#ev-pattern g.dot-primary[aria-label*="weight 0.5"]');
    const box = await dot.boundingBox();
    assert(box, 'centre sample not found');
    const x = box.x + box.width / 2;
    const y = box.y + box.height / 2;
    await resetState(page);
    await page.mouse.move(x, y);
    await page.mouse.down();
    for (let i = 1; i <= 20; i++) {
      await page.mouse.move(x + i * 2, y - i);
      await page.waitForTimeout(20);
    }
    await page.mouse.up();
    await waitState(page, 'done');
    const events = log.slice(before);
    let inFlight = 0;
    const overlapping = [];
    for (const e of events) {
      if (e.what === '/v1/evaluate sent') inFlight++;
      else if (e.what === '/v1/evaluate answered') inFlight--;
      else if (e.what === '/v1/analyze sent' && inFlight > 0) overlapping.push(e.t);
    }
    const evaluations = events.filter((e) => e.what === '/v1/evaluate sent').length;
    const analyses = events.filter((e) => e.what === '/v1/analyze sent').length;
    assert(evaluations >= 3, `only ${evaluations} evaluations during the drag`);
    assert(!overlapping.length, `${overlapping.length} analyses sent while an evaluation was in flight`);
    assert(analyses >= 1 && analyses < evaluations, `${analyses} analyses for ${evaluations} evaluations`);
    console.log(`#   drag: ${evaluations} evaluations, ${analyses} analyses asked (after the last evaluation answered)`);
    const pattern = JSON.parse(await page.inputValue('#ev-json'));
    const moved = await api('POST', '/v1/analyze', { pattern, ...options });
    await checkFigures(page, moved);
  });

  await step('collapsed: no analysis is asked; opening asks for the pattern evaluated meanwhile', async () => {
    await page.click('#ev-analysis > summary');
    await waitState(page, 'collapsed');
    const before = analyzeSent().length;
    const evRef = await api('POST', '/v1/evaluate', { pattern: { preset: 'grid-2x2' } });
    await page.goto(`${base}/#/evaluate?preset=grid-2x2`);
    await page.waitForFunction((e2) => document.getElementById('ev-e2').dataset.e2 === String(e2), evRef.e2);
    await page.waitForTimeout(600);
    assert(analyzeSent().length === before, `${analyzeSent().length - before} analyses asked while collapsed`);
    assert((await page.evaluate(() => localStorage.getItem('aalab.analysis.open'))) === 'false', 'collapsed state not kept');
    await resetState(page);
    await page.click('#ev-analysis > summary');
    await waitState(page, 'done');
    const q = await api('POST', '/v1/analyze', { pattern: { preset: 'grid-2x2' }, ...options });
    await checkFigures(page, q);
  });

  for (const size of SIZES) {
    const tag = `${size.width}x${size.height}`;
    await step(`${tag}: the page fits the window, labels at least 11 px and apart, figures side by side without overlap`, async () => {
      const problems = [];
      const check = async (when) => {
        const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, inner: window.innerWidth }));
        if (w.scroll > w.inner) problems.push(`${when}: page ${w.scroll} px wide in a ${w.inner} px window`);
        const overlaps = await overlappingLabels(page);
        if (overlaps.length) problems.push(`${when}: ${overlaps.length} overlapping labels: ${overlaps.slice(0, 5).join('; ')}`);
        problems.push(...(await panelGeometry(page)).map((p) => `${when}: ${p}`));
      };
      // The window resized under a drawn panel: it redraws for the new scale.
      await page.setViewportSize({ width: size.width, height: size.height });
      await page.waitForTimeout(500);
      await check('resized under the last result');
      await resetState(page);
      await page.goto(`${base}/#/evaluate?preset=${size.preset}`);
      await waitState(page, 'done');
      await page.waitForTimeout(200);
      await check(size.preset);
      await page.screenshot({ path: `${artifacts}/analysis-${tag}.png`, fullPage: true });
      const panel = await page.$('#ev-analysis');
      await panel.screenshot({ path: `${artifacts}/analysis-panel-${tag}.png` });
      assert(!problems.length, problems.join('\n'));
    });
  }
}
