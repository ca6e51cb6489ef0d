// Evaluate view: Quincunx's E2 equals the API's; dragging a sample (mouse) and moving it
// (keyboard) changes E2 to what the API says for the moved pattern; negative weights drawn
// distinctly.

import { assert, eventually } from '../lib/check.mjs';

async function shownE2(page) {
  return page.$eval('#ev-e2', (o) => ({ raw: o.dataset.e2, text: o.textContent }));
}

async function waitIdle(page) {
  await page.waitForFunction(() => document.getElementById('ev-e2').getAttribute('aria-busy') !== 'true');
}

export default async function evaluateSuite({ page, base, api, step, shot }) {
  let initial;
  await step('Quincunx: E2 shown equals POST /v1/evaluate', async () => {
    await page.goto(`${base}/#/evaluate?preset=quincunx`);
    await page.waitForFunction(() => document.getElementById('ev-e2').dataset.e2 !== '' && document.getElementById('ev-e2').dataset.e2 != null);
    await waitIdle(page);
    const ref = await api('POST', '/v1/evaluate', { pattern: { preset: 'quincunx' } });
    initial = await shownE2(page);
    assert(typeof ref.e2 === 'number', `API answer has no numeric e2: ${JSON.stringify(ref)}`);
    assert(Number(initial.raw) === ref.e2, `page holds E2 ${initial.raw}, API says ${ref.e2}`);
    assert(initial.text === ref.e2.toFixed(6), `page shows "${initial.text}", API e2 to 6 places is ${ref.e2.toFixed(6)}`);
    const family = await page.textContent('#ev-family');
    assert(family === ref.family, `family shown "${family}", API "${ref.family}"`);
  });

  await step('polar plots drawn with the argmax marked', async () => {
    const n = await page.$$eval('#ev-polar-weighted path.polar-curve', (p) => p.length);
    const m = await page.$$eval('#ev-polar-e1 path.polar-curve', (p) => p.length);
    assert(n >= 1 && m >= 1, `curves: weighted ${n}, unweighted ${m}`);
    assert(await page.$('#ev-polar-weighted circle.polar-argmax'), 'no argmax ring in the weighted plot');
    const label = await page.textContent('#ev-polar-weighted .polar-argmax-label');
    assert(/max [0-9.]+ @ \d+°/.test(label), `argmax label "${label}"`);
    const dots = await page.$$eval('#ev-pattern g.dot-primary', (g) => g.length);
    assert(dots === 5, `Quincunx should draw 5 samples in the centre pixel, found ${dots}`);
    await shot('evaluate');
  });

  await step('dragging the centre sample changes E2 to the API value of the moved pattern', async () => {
    const dot = page.locator('#ev-pattern g.dot-primary[aria-label*="weight 0.5"]');
    const box = await dot.boundingBox();
    assert(box, 'centre sample not found');
    const x = box.x + box.width / 2;
    const y = box.y + box.height / 2;
    await page.mouse.move(x, y);
    await page.mouse.down();
    for (let i = 1; i <= 8; i++) await page.mouse.move(x + i * 4, y - i * 3);
    await page.mouse.up();
    await eventually(async () => (await shownE2(page)).raw !== initial.raw, { message: 'E2 to change after the drag' });
    await waitIdle(page);
    const pattern = JSON.parse(await page.inputValue('#ev-json'));
    const centre = pattern.kernels[0].find((s) => s[2] === 0.5);
    assert(centre[0] > 0.02 && centre[1] > 0.02, `centre sample did not move right/up: ${JSON.stringify(centre)}`);
    const ref = await api('POST', '/v1/evaluate', { pattern });
    await eventually(async () => Number((await shownE2(page)).raw) === ref.e2, { message: `E2 shown to equal API ${ref.e2}` });
    await shot('evaluate-dragged');
  });

  await step('keyboard: a focused sample moves with the arrow keys and E2 follows', async () => {
    const before = (await shownE2(page)).raw;
    await page.focus('#ev-pattern g.dot-primary[aria-label*="weight 0.5"]');
    await page.keyboard.press('Shift+ArrowRight');
    await eventually(async () => (await shownE2(page)).raw !== before, { message: 'E2 to change after an arrow key' });
  });

  await step('negative weights drawn hollow and labelled with a minus sign', async () => {
    await page.click('#ev-paste summary');
    await page.fill('#ev-json', '{"kernels":[[[-0.25,-0.25,0.6],[0.25,0.25,0.6],[0,0.4,-0.2]]]}');
    await page.click('#ev-apply');
    await page.waitForSelector('#ev-pattern g.dot-primary.dot-negative');
    const sign = await page.textContent('#ev-pattern g.dot-primary.dot-negative .dot-sign');
    assert(sign === '−', `negative dot sign "${sign}"`);
    const dash = await page.$eval('#ev-pattern g.dot-primary.dot-negative .dot-shape', (c) => getComputedStyle(c).strokeDasharray);
    assert(dash && dash !== 'none', `negative dot stroke not dashed (${dash})`);
    const label = await page.textContent('#ev-pattern g.dot-primary.dot-negative .dot-label');
    assert(label.startsWith('−'), `negative weight label "${label}"`);
    await page.waitForFunction(() => document.getElementById('ev-status').textContent === '');
    await shot('evaluate-negative');
  });

  await step('mirrored preset (FLIPQUAD) draws four kernels worth of neighbours', async () => {
    await page.goto(`${base}/#/evaluate?preset=flipquad`);
    await waitIdle(page);
    const ref = await api('POST', '/v1/evaluate', { pattern: { preset: 'flipquad' } });
    await eventually(async () => Number((await shownE2(page)).raw) === ref.e2, { message: `FLIPQUAD E2 ${ref.e2}` });
    const curves = await page.$$eval('#ev-polar-weighted path.polar-curve', (p) => p.length);
    assert(curves === 4, `FLIPQUAD has 4 kernels, polar plot shows ${curves}`);
    await shot('evaluate-flipquad');
  });
}
