// Temporal view (issue 30): a temporal preset's numbers equal POST /v1/evaluate's (E2 of the
// worst phase, mean, F2, frames to 5 %, per-phase E2, the after-cut curve); the sequence is drawn
// with its frame numbers; the α slider re-evaluates (debounced, and a newer move aborts the
// request in flight); bad JSON and a refused pattern show an error in place and clear the old
// result; at 1400x1000 and 1000x800 the page fits the window, plot labels do not overlap and are
// at least 11 px.

import { assert, eventually } from '../lib/check.mjs';
import { overlappingLabels } from '../lib/labels.mjs';

const SIZES = [
  { width: 1400, height: 1000 },
  { width: 1000, height: 800 },
];

async function waitIdle(page) {
  await page.waitForFunction(() => document.getElementById('tp-e2').getAttribute('aria-busy') !== 'true');
}

/* What the page shows, as the numbers it holds (data attributes) and the text. */
function shown(page) {
  return page.evaluate(() => {
    const $ = (id) => document.getElementById(id);
    return {
      e2: $('tp-e2').dataset.e2,
      e2Text: $('tp-e2').textContent,
      alpha: $('tp-e2').dataset.alpha,
      mean: $('tp-mean').dataset.value,
      f2: $('tp-f2').dataset.value,
      frames: $('tp-frames').dataset.value,
      bars: [...document.querySelectorAll('#tp-phase-e2 rect.tp-bar')].map((b) => [Number(b.dataset.phase), Number(b.dataset.e2)]),
      worstBars: document.querySelectorAll('#tp-phase-e2 rect.tp-bar.tp-worst').length,
      curve: [...document.querySelectorAll('#tp-after-cut circle.tp-point')].map((c) => [Number(c.dataset.k), Number(c.dataset.e2)]),
      frameLabels: [...document.querySelectorAll('#tp-sequence g.tp-frame text')].map((t) => t.textContent),
      frames_drawn: document.querySelectorAll('#tp-sequence g.tp-frame').length,
      e1Curves: document.querySelectorAll('#tp-polar-e1 path.polar-curve').length,
      f1Curves: document.querySelectorAll('#tp-polar-f1 path.polar-curve').length,
      status: $('tp-status').textContent,
      statusError: $('tp-status').classList.contains('error-text'),
    };
  });
}

function sameAsApi(s, ref, what) {
  assert(Number(s.e2) === ref.e2, `${what}: page holds E2 ${s.e2}, API ${ref.e2}`);
  assert(s.e2Text === ref.e2.toFixed(6), `${what}: page shows "${s.e2Text}", API E2 to 6 places ${ref.e2.toFixed(6)}`);
  assert(Number(s.mean) === ref.mean_phase_e2, `${what}: mean ${s.mean}, API ${ref.mean_phase_e2}`);
  assert(Number(s.f2) === ref.f2, `${what}: F2 ${s.f2}, API ${ref.f2}`);
  assert(s.frames === String(ref.frames_to_5pct), `${what}: frames to 5 % ${s.frames}, API ${ref.frames_to_5pct}`);
  const phases = ref.phases.map((p) => [p.phase, p.e2]);
  assert(JSON.stringify(s.bars) === JSON.stringify(phases), `${what}: bars ${JSON.stringify(s.bars)}, API ${JSON.stringify(phases)}`);
  const curve = ref.after_cut.map((v, i) => [i + 1, v]);
  assert(JSON.stringify(s.curve) === JSON.stringify(curve), `${what}: after-cut points differ from the API's (${s.curve.length} against ${curve.length})`);
}

/* Plot text under 11 px on screen, and any text of the view under 11 px. */
function smallText(page) {
  return page.evaluate(() => {
    const out = [];
    for (const svg of document.querySelectorAll('#view-temporal svg')) {
      const vb = svg.viewBox && svg.viewBox.baseVal;
      const r = svg.getBoundingClientRect();
      if (!r.width) continue;
      const scale = vb && vb.width ? Math.min(r.width / vb.width, r.height / vb.height) : 1;
      for (const t of svg.querySelectorAll('text')) {
        if (!t.textContent.trim() || !t.getClientRects().length) continue;
        const px = parseFloat(getComputedStyle(t).fontSize) * scale;
        if (px < 10.5) out.push(`${svg.parentElement.id}: "${t.textContent.trim()}" ${px.toFixed(1)} px`);
      }
    }
    for (const e of document.querySelectorAll('#view-temporal label, #view-temporal figcaption, #view-temporal .hint, #view-temporal dt, #view-temporal dd'))
      if (e.getClientRects().length && parseFloat(getComputedStyle(e).fontSize) < 10.5) out.push(`${e.id || e.tagName}: ${getComputedStyle(e).fontSize}`);
    return out;
  });
}

/* Moves the slider to v the way a user's drag does: value set, an input event. */
async function slide(page, v) {
  await page.$eval('#tp-alpha', (s, value) => {
    s.value = String(value);
    s.dispatchEvent(new Event('input', { bubbles: true }));
  }, v);
}

export default async function temporalSuite({ page, base, api, step, shot, consoleProblems, artifacts }) {
  await step('halton23-8: every number shown equals POST /v1/evaluate', async () => {
    await page.goto(`${base}/#/temporal?preset=halton23-8`);
    await page.waitForFunction(() => document.getElementById('tp-e2') && document.getElementById('tp-e2').dataset.e2);
    await waitIdle(page);
    const ref = await api('POST', '/v1/evaluate', { pattern: { temporal: { preset: 'halton23-8' } } });
    const s = await shown(page);
    sameAsApi(s, ref, 'halton23-8');
    assert(Math.abs(ref.e2 - 0.482) < 5e-4, `halton23-8 E2 ${ref.e2}, the issue's independent value is 0.482`);
    assert(s.worstBars === 1, `one bar marked worst, found ${s.worstBars}`);
    assert(s.alpha === '0.1', `the slider shows the preset's alpha: ${s.alpha}`);
    assert(Number(await page.inputValue('#tp-alpha')) === 0.1, 'slider at the preset\'s 0.1');
    assert(/FSR2/.test(await page.textContent('#tp-source')), 'the preset\'s provenance is shown');
  });

  await step('the sequence drawn with its frame numbers; E1 and F1 polars side by side', async () => {
    const s = await shown(page);
    assert(s.frames_drawn === 8, `8 frames drawn, found ${s.frames_drawn}`);
    assert(JSON.stringify(s.frameLabels.slice().sort()) === JSON.stringify(['0', '1', '2', '3', '4', '5', '6', '7']), `frame numbers ${JSON.stringify(s.frameLabels)}`);
    assert(s.e1Curves === 2 && s.f1Curves === 1, `polar curves: E1 ${s.e1Curves}, F1 ${s.f1Curves}`);
    assert(await page.$('#tp-polar-e1 circle.polar-argmax'), 'no E2 ring on the E1 polar');
    assert(await page.$('#tp-polar-f1 circle.polar-argmax'), 'no F2 ring on the F1 polar');
    const label = await page.textContent('#tp-polar-e1 .polar-argmax-label');
    assert(/^max 0\.482 @ \d+°, phase \d+$/.test(label), `E1 argmax label "${label}"`);
    const [a, b] = await page.$$eval('.tp-polars figure', (f) => f.map((x) => x.getBoundingClientRect().toJSON()));
    assert(Math.abs(a.top - b.top) < 2 && b.left > a.right - 1, `F1 polar not beside the E1 polar: ${JSON.stringify([a, b])}`);
    await shot('temporal');
  });

  await step('the α slider re-evaluates once per pause (debounced) and shows the API\'s numbers', async () => {
    const posts = [];
    const onRequest = (req) => req.url().endsWith('/v1/evaluate') && req.method() === 'POST' && posts.push(JSON.parse(req.postData()));
    page.on('request', onRequest);
    for (const v of [0.12, 0.15, 0.18, 0.2]) await slide(page, v); // faster than the debounce
    await eventually(async () => (await shown(page)).alpha === '0.2', { message: 'alpha 0.2 evaluated' });
    await waitIdle(page);
    await page.waitForTimeout(300);
    page.off('request', onRequest);
    assert(posts.length === 1, `one request for four quick moves, got ${posts.length}: ${JSON.stringify(posts)}`);
    assert(JSON.stringify(posts[0].pattern.temporal) === JSON.stringify({ preset: 'halton23-8', blend: { kind: 'exponential', alpha: 0.2 } }), `request ${JSON.stringify(posts[0])}`);
    const ref = await api('POST', '/v1/evaluate', posts[0]);
    sameAsApi(await shown(page), ref, 'alpha 0.2');
    assert((await page.textContent('#tp-alpha-out')) === '0.20', 'the slider\'s value is shown');
  });

  await step('a newer move aborts the request in flight; the last one wins', async () => {
    const aborted = [];
    const onFailed = (req) => req.url().endsWith('/v1/evaluate') && /ERR_ABORTED/.test((req.failure() || {}).errorText || '') && aborted.push(JSON.parse(req.postData()).pattern.temporal.blend.alpha);
    page.on('requestfailed', onFailed);
    // Answers held back 700 ms, so the first is still in flight when the second move is sent.
    const handler = async (route) => {
      await new Promise((r) => setTimeout(r, 700));
      await route.continue().catch(() => {}); // the page may have aborted it meanwhile
    };
    await page.route('**/v1/evaluate', handler);
    await slide(page, 0.3);
    await page.waitForTimeout(350); // past the debounce: the 0.3 request is in flight
    await slide(page, 0.05);
    await eventually(async () => (await shown(page)).alpha === '0.05', { message: 'alpha 0.05 evaluated' });
    await waitIdle(page);
    await page.unroute('**/v1/evaluate', handler);
    page.off('requestfailed', onFailed);
    assert(aborted.includes(0.3), `the 0.3 request should have been aborted; aborted: ${JSON.stringify(aborted)}`);
    const ref = await api('POST', '/v1/evaluate', { pattern: { temporal: { preset: 'halton23-8', blend: { kind: 'exponential', alpha: 0.05 } } } });
    sameAsApi(await shown(page), ref, 'alpha 0.05 after an aborted 0.3');
  });

  await step('box blend: the slider is disabled and the D3D 4x positions give the spatial E2', async () => {
    await page.click('#tp-paste summary');
    await page.fill('#tp-json', '{"jitter":{"generator":"preset","preset":"d3d-4x"}}');
    await page.click('#tp-apply');
    await waitIdle(page);
    await page.selectOption('#tp-blend', 'box');
    await eventually(async () => (await shown(page)).alpha === 'box', { message: 'box blend evaluated' });
    await waitIdle(page);
    assert(await page.$eval('#tp-alpha', (s) => s.disabled), 'slider enabled under the box blend');
    const spatial = await api('POST', '/v1/evaluate', { pattern: { preset: 'd3d-4x' } });
    const s = await shown(page);
    assert(Number(s.e2) === spatial.e2, `box over D3D 4x shows ${s.e2}, spatial D3D 4x ${spatial.e2}`);
    assert(Number(s.f2) === 0, `F2 ${s.f2} for a box blend (every phase the same kernel)`);
  });

  await step('bad JSON: the error is shown in place and the old result cleared', async () => {
    await page.fill('#tp-json', '{"jitter": [[0, 0], ');
    await page.click('#tp-apply');
    const s = await shown(page);
    assert(s.statusError && /not valid JSON/.test(s.status), `status "${s.status}"`);
    assert(s.e2 === '' && s.e2Text === '—' && s.mean === '' && s.f2 === '' && s.frames === '', `old numbers left: ${JSON.stringify(s)}`);
    assert(!s.bars.length && !s.curve.length && !s.frames_drawn && !s.e1Curves && !s.f1Curves, 'old plots left on screen');
    await shot('temporal-bad-json');
  });

  await step('a pattern the daemon refuses (400): its message names the field, nothing stale shown', async () => {
    await page.goto(`${base}/#/temporal?preset=halton23-16`);
    await page.waitForFunction(() => document.getElementById('tp-e2').dataset.e2);
    await waitIdle(page);
    const before = consoleProblems.length;
    await page.fill('#tp-json', '{"jitter":[[0,0],[0.7,0]]}');
    await page.click('#tp-apply');
    await eventually(async () => (await shown(page)).statusError, { message: 'an error shown' });
    const s = await shown(page);
    assert(/pattern\.temporal\.jitter\[1\]/.test(s.status), `status "${s.status}" should name pattern.temporal.jitter[1]`);
    assert(s.e2 === '' && !s.bars.length && !s.e1Curves, 'the halton23-16 result is still shown');
    // The browser logs the refused request; that one, and only that one, is expected.
    const provoked = consoleProblems.splice(before);
    const unexpected = provoked.filter((m) => !(/\b400\b/.test(m) && /\/v1\/evaluate/.test(m)));
    consoleProblems.push(...unexpected);
    assert(provoked.length > unexpected.length, 'the bad offset should have been refused with 400');
    // The preset the URL still names, chosen again, evaluates (no hashchange happens then).
    await page.selectOption('#tp-preset', 'halton23-16');
    await page.waitForFunction(() => document.getElementById('tp-e2').dataset.e2);
    await waitIdle(page);
    const again = await api('POST', '/v1/evaluate', { pattern: { temporal: { preset: 'halton23-16' } } });
    sameAsApi(await shown(page), again, 'halton23-16 chosen again');
    // And another preset.
    await page.selectOption('#tp-preset', 'fsr2-2x');
    await page.waitForFunction(() => document.getElementById('tp-e2').dataset.e2);
    await waitIdle(page);
    const ref = await api('POST', '/v1/evaluate', { pattern: { temporal: { preset: 'fsr2-2x' } } });
    sameAsApi(await shown(page), ref, 'fsr2-2x after an error');
  });

  for (const size of SIZES) {
    const tag = `${size.width}x${size.height}`;
    for (const preset of ['halton23-8', 'fsr2-3x']) {
      await step(`${tag}, ${preset}: fits the window, labels apart and at least 11 px`, async () => {
        await page.setViewportSize(size);
        await page.goto(`${base}/#/temporal?preset=${preset}`);
        await page.waitForFunction(() => document.getElementById('tp-e2').dataset.e2);
        await waitIdle(page);
        await page.waitForTimeout(400); // the resize redraw settles
        await page.screenshot({ path: `${artifacts}/temporal-${preset}-${tag}.png`, fullPage: true });
        const w = await page.evaluate(() => ({ scroll: document.documentElement.scrollWidth, inner: window.innerWidth }));
        assert(w.scroll <= w.inner, `page ${w.scroll} px wide in a ${w.inner} px window`);
        const overlaps = await overlappingLabels(page);
        assert(!overlaps.length, `${overlaps.length} overlapping labels, e.g. ${overlaps.slice(0, 4).join('; ')}`);
        const small = await smallText(page);
        assert(!small.length, `${small.length} labels under 11 px, e.g. ${small.slice(0, 4).join('; ')}`);
        const cut = await page.evaluate(() => {
          const c = document.createElement('canvas').getContext('2d');
          return [...document.querySelectorAll('#view-temporal select')]
            .filter((s) => s.getClientRects().length && s.selectedIndex >= 0)
            .filter((s) => {
              c.font = getComputedStyle(s).font;
              return c.measureText(s.options[s.selectedIndex].text).width > s.clientWidth - 24;
            })
            .map((s) => s.id);
        });
        assert(!cut.length, `menus cut off: ${cut.join(', ')}`);
      });
    }
  }
}
