#!/usr/bin/env node
// Browser tests of the aalab dashboard: a real aalabd on a temporary socket, state directory and
// TCP port serves web/, Debian's Chromium (headless, via playwright-core) drives the page.
//
//   node run-browser-tests.mjs --aalabd build/server/aalabd --web-dir web \
//        --artifacts build/artifacts/web [--suite evaluate,jobs,...] [--daemon-arg ARG ...]
//
// Missing Chromium, a missing node_modules or a missing daemon binary is a loud FAILURE, never a
// skip. Screenshots of each view go to the artefact directory. Exit status 0 only if every check
// passed and the page logged no console errors.

import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { Report } from './lib/check.mjs';
import { CHROMIUM } from './lib/browser.mjs';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const SUITES = ['evaluate', 'families', 'jobs', 'optimize', 'tiles', 'kinds', 'recovery', 'layout', 'temporal', 'analysis', 'plots'];

function parseArgs(argv) {
  const o = { suites: SUITES, daemonArgs: [], widths: [1400, 1000], schemas: path.resolve(HERE, '../../proto/schemas') };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const next = () => argv[++i];
    if (a === '--aalabd') o.aalabd = next();
    else if (a === '--web-dir') o.webDir = next();
    else if (a === '--artifacts') o.artifacts = next();
    else if (a === '--suite') o.suites = next().split(',');
    else if (a === '--daemon-arg') o.daemonArgs.push(next());
    else if (a === '--schemas') o.schemas = next();
    else throw new Error(`unknown argument ${a}`);
  }
  return o;
}

function die(lines) {
  const bar = '!'.repeat(78);
  console.log(`${bar}\nFAIL: the dashboard browser tests cannot run (this is a failure, not a skip)`);
  for (const l of lines) console.log(`  ${l}`);
  console.log(`${bar}\n0 passed, 1 failed`);
  process.exit(1);
}

// A reader that goes away (| head) must not kill the run before it has stopped its daemons.
process.stdout.on('error', () => {});

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  const problems = [];
  if (!opts.aalabd || !fs.existsSync(opts.aalabd)) problems.push(`daemon binary not found: --aalabd ${opts.aalabd} (build the aalabd target)`);
  if (!opts.webDir || !fs.existsSync(path.join(opts.webDir, 'index.html'))) problems.push(`no index.html in --web-dir ${opts.webDir}`);
  try {
    fs.accessSync(CHROMIUM, fs.constants.X_OK);
  } catch {
    problems.push(`Chromium not found at ${CHROMIUM}: install it with "apt-get install chromium" (Debian package; no browser is ever downloaded)`);
  }
  for (const dep of ['playwright-core', 'ajv'])
    if (!fs.existsSync(path.join(HERE, 'node_modules', dep, 'package.json'))) problems.push(`${dep} missing: run "npm ci" in ${HERE}`);
  if (!fs.existsSync(opts.schemas)) problems.push(`no JSON Schemas in --schemas ${opts.schemas}`);
  for (const s of opts.suites) if (!SUITES.includes(s)) problems.push(`unknown suite ${s} (have ${SUITES.join(', ')})`);
  if (problems.length) die(problems);
  if (!opts.artifacts) opts.artifacts = path.join(process.cwd(), 'artifacts', 'web');
  fs.mkdirSync(opts.artifacts, { recursive: true });

  const { launchBrowser, watchConsole } = await import('./lib/browser.mjs');
  const { startDaemon, apiClient } = await import('./lib/daemon.mjs');
  const { ResponseValidator } = await import('./lib/schemas.mjs');
  const report = new Report();

  for (const suiteName of opts.suites) {
    const { default: suite } = await import(`./suites/${suiteName}.mjs`);
    let daemon = null;
    let browser = null;
    let validator = null;
    try {
      daemon = await startDaemon({
        binary: path.resolve(opts.aalabd),
        webDir: path.resolve(opts.webDir),
        logFile: path.join(opts.artifacts, `aalabd-${suiteName}.log`),
        extraArgs: opts.daemonArgs,
      });
      browser = await launchBrowser();
      const page = await browser.context.newPage();
      const consoleProblems = watchConsole(page);
      validator = new ResponseValidator(opts.schemas);
      validator.watch(page);
      page.setDefaultTimeout(20000);
      // The token arrives in the fragment the way a user would paste the dashboard URL.
      await page.goto(`${daemon.base}/#token=${encodeURIComponent(daemon.token)}`);
      await page.waitForFunction(() => localStorage.getItem('aalab.token'));
      const shot = async (name) => {
        for (const w of opts.widths) {
          await page.setViewportSize({ width: w, height: w >= 1400 ? 1000 : 800 }); // the sizes issue 34 checks
          await page.waitForTimeout(150);
          await page.screenshot({ path: path.join(opts.artifacts, `${name}-${w}.png`), fullPage: true });
        }
        await page.setViewportSize({ width: 1366, height: 900 });
      };
      let stopped = false;
      const step = async (name, fn) => {
        const full = `${suiteName}: ${name}`;
        if (stopped) {
          report.fail(full, 'not run: an earlier check of this suite failed');
          return;
        }
        try {
          await fn();
          report.pass(full);
        } catch (e) {
          report.fail(full, e);
          stopped = true;
          await page.screenshot({ path: path.join(opts.artifacts, `FAILED-${suiteName}.png`), fullPage: true }).catch(() => {});
        }
      };
      const api = apiClient(daemon.base, daemon.token, (...a) => validator.check(...a));
      await suite({ page, base: daemon.base, api, step, shot, daemon, consoleProblems, artifacts: opts.artifacts });
      await page.waitForTimeout(300); // let late console messages and answers arrive
      if (consoleProblems.length) report.fail(`${suiteName}: no console errors`, consoleProblems.join('\n'));
      else report.pass(`${suiteName}: no console errors`);
      console.log(`#   ${validator.validated} answers validated against proto/schemas; without a schema: ${[...validator.unschemed].sort().join(', ') || 'none'}`);
      if (validator.problems.length) report.fail(`${suiteName}: every API answer matches its JSON Schema`, validator.problems.join('\n'));
      else if (!validator.validated) report.fail(`${suiteName}: every API answer matches its JSON Schema`, 'no answer was validated');
      else report.pass(`${suiteName}: every API answer matches its JSON Schema`);
    } catch (e) {
      report.fail(`${suiteName}: set-up`, e);
    } finally {
      if (browser) await browser.close();
      if (daemon) {
        const how = await daemon.stop();
        if (how && how.signal === 'SIGKILL') report.fail(`${suiteName}: aalabd stops on SIGTERM`, 'needed SIGKILL');
      }
    }
  }
  console.log(`# screenshots and daemon logs in ${opts.artifacts}`);
  console.log(`${report.passed} passed, ${report.failed} failed`);
  process.exit(report.failed ? 1 : 0);
}

main().catch((e) => {
  console.log(`not ok - runner: ${e.stack || e}`);
  console.log('0 passed, 1 failed');
  process.exit(1);
});
