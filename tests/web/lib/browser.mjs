// Launches Debian's Chromium through playwright-core (never a downloaded browser) and records
// every console error, page error and failed request of the page.

import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

export const CHROMIUM = process.env.AALAB_CHROMIUM || '/usr/bin/chromium';

export async function launchBrowser() {
  const { chromium } = await import('playwright-core');
  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'aalab-chromium-'));
  // launchPersistentContext is how playwright takes a user data dir; it also gives the
  // viewport in one place.
  const context = await chromium.launchPersistentContext(userDataDir, {
    executablePath: CHROMIUM,
    headless: true,
    args: [
      '--headless',
      '--no-sandbox',
      '--disable-gpu',
      '--disable-quic',
      '--no-first-run',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
    ],
    viewport: { width: 1366, height: 900 },
  });
  return {
    context,
    async close() {
      await context.close().catch(() => {});
      fs.rmSync(userDataDir, { recursive: true, force: true });
    },
  };
}

/* Collects problems a user would see in the developer console. */
export function watchConsole(page) {
  const problems = [];
  page.on('console', (msg) => {
    if (msg.type() === 'error') problems.push(`console.error: ${msg.text()} ${JSON.stringify(msg.location())}`);
  });
  page.on('pageerror', (err) => problems.push(`page error: ${err.message}\n${err.stack || ''}`));
  page.on('requestfailed', (req) => {
    const failure = req.failure();
    // A request the page itself aborted (e.g. an image replaced while loading) is not an error.
    if (failure && !/ERR_ABORTED/.test(failure.errorText)) problems.push(`request failed: ${req.url()} ${failure.errorText}`);
  });
  page.on('response', (resp) => {
    if (resp.status() >= 400) problems.push(`HTTP ${resp.status()} for ${resp.request().method()} ${resp.url()}`);
  });
  return problems;
}
