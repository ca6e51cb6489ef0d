// Errors that recover (issue 34, defects 1, 2 and 9): a wrong token says so (not "unreachable")
// and fixing it in place loads every menu; an evaluate error clears the previous result and
// offers normalize for a weight sum off 1; a stopped daemon gets an offline banner, greyed
// stale data and a retry.

import { assert, eventually } from '../lib/check.mjs';

async function waitIdle(page) {
  await page.waitForFunction(() => document.getElementById('ev-e2').getAttribute('aria-busy') !== 'true');
}

export default async function recoverySuite({ page, base, api, step, shot, daemon, consoleProblems }) {
  await step('a wrong token: the header says "wrong or revoked token", not unreachable', async () => {
    await page.evaluate(() => localStorage.setItem('aalab.token', 'wrong-token-0000'));
    await page.goto(`${base}/#/evaluate`);
    await page.reload();
    await eventually(async () => /wrong or revoked token/.test(await page.textContent('#health')), { message: 'health line to name the token' });
    const health = await page.textContent('#health');
    assert(!/unreachable/.test(health), `health line "${health}"`);
    const presets = await page.$$eval('#ev-preset option', (o) => o.length);
    assert(presets <= 1, `preset menu filled (${presets}) although every request was refused`);
  });

  await step('the right token entered in the Token form loads menus, E2 and clears the 401 notice', async () => {
    if (await page.isHidden('#token-form')) await page.click('#token-button');
    await page.fill('#token-input', daemon.token);
    await page.click('#token-form button[type=submit]');
    await page.waitForFunction(() => document.querySelectorAll('#ev-preset option').length > 3);
    await page.waitForFunction(() => document.querySelectorAll('#ev-filter option').length > 0 && document.querySelectorAll('#ev-acuity option').length > 0);
    await page.waitForFunction(() => document.getElementById('ev-e2').dataset.e2);
    assert(await page.isHidden('#toast'), `401 notice still shown: ${await page.textContent('#toast')}`);
    await eventually(async () => /^aalabd /.test(await page.textContent('#health')), { message: 'health line to show the daemon' });
    // "Evaluate this JSON" works too (its listener was never attached before).
    await page.click('#ev-paste summary');
    await page.fill('#ev-json', '{"kernels":[[[-0.25,-0.25,0.5],[0.25,0.25,0.5]]]}');
    await page.click('#ev-apply');
    const ref = await api('POST', '/v1/evaluate', { pattern: { kernels: [[[-0.25, -0.25, 0.5], [0.25, 0.25, 0.5]]] } });
    await eventually(async () => Number(await page.$eval('#ev-e2', (o) => o.dataset.e2)) === ref.e2, { message: `E2 ${ref.e2} of the pasted pattern` });
  });

  await step('an evaluate error clears the previous result and offers normalize', async () => {
    await page.goto(`${base}/#/evaluate?preset=quincunx`);
    const q = await api('POST', '/v1/evaluate', { pattern: { preset: 'quincunx' } });
    await eventually(async () => Number(await page.$eval('#ev-e2', (o) => o.dataset.e2)) === q.e2, { message: 'Quincunx E2' });
    await waitIdle(page);
    const bad = { kernels: [[[-0.25, -0.25, 0.45], [0.25, 0.25, 0.45]]] };
    await page.fill('#ev-json', JSON.stringify(bad));
    await page.click('#ev-apply');
    await page.waitForFunction(() => document.getElementById('ev-status').classList.contains('error-text'));
    const shown = await page.evaluate(() => ({
      e2: document.getElementById('ev-e2').textContent,
      raw: document.getElementById('ev-e2').dataset.e2,
      argmax: document.getElementById('ev-argmax').textContent,
      family: document.getElementById('ev-family').textContent,
      curves: document.querySelectorAll('#ev-polar-weighted path.polar-curve, #ev-polar-e1 path.polar-curve').length,
    }));
    assert(shown.raw === '' && shown.e2 === '—', `E2 of the previous pattern still shown: ${JSON.stringify(shown)}`);
    assert(shown.argmax === '—' && shown.family === '—', `argmax/family still shown: ${JSON.stringify(shown)}`);
    assert(shown.curves === 0, `${shown.curves} polar curves of the previous pattern still drawn`);
    assert(await page.isVisible('#ev-normalize'), 'no normalize control beside a weight-sum error');
    await shot('recovery-evaluate-error');
    await page.click('#ev-normalize');
    const ref = await api('POST', '/v1/evaluate', { pattern: { ...bad, normalize: true } });
    await eventually(async () => Number(await page.$eval('#ev-e2', (o) => o.dataset.e2)) === ref.e2, { message: `normalised E2 ${ref.e2}` });
    assert(await page.isHidden('#ev-normalize'), 'normalize control still shown after a good answer');
    assert(JSON.parse(await page.inputValue('#ev-json')).normalize === true, 'the JSON box does not say normalize');
  });

  await step('a stopped daemon: offline banner, stale data greyed, a retry', async () => {
    await daemon.stop();
    await page.waitForSelector('#offline:not([hidden])', { timeout: 12000 });
    const text = await page.textContent('#offline-text');
    assert(/not answering/.test(text) && !/Failed to fetch/.test(text), `banner "${text}"`);
    assert(await page.evaluate(() => document.body.classList.contains('stale')), 'stale data not marked');
    const filter = await page.$eval('main', (m) => getComputedStyle(m).filter);
    assert(/grayscale/.test(filter), `main not greyed (filter ${filter})`);
    // Any request may be the first to find the daemon gone (the analysis panel's, asked after the
    // last evaluation): the health line says so at its next poll, within 5 s.
    await eventually(async () => /unreachable/.test(await page.textContent('#health')), { timeout: 8000, message: 'the health line to say unreachable' });
    await shot('recovery-offline');
    await page.click('#offline-retry');
    await eventually(async () => /not answering/.test(await page.textContent('#offline-text')), { message: 'retry to report again' });
    // The refused token, the 400 of the bad weights and the refused connections were intended.
    consoleProblems.splice(0, consoleProblems.length, ...consoleProblems.filter((p) => !/HTTP 401|HTTP 400 for POST .*evaluate|ERR_CONNECTION_REFUSED|status of 40[01]/.test(p)));
  });
}
