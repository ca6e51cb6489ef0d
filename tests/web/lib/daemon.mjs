// Starts a real aalabd on a temporary socket, state directory and TCP port, and stops it.

import { spawn } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';

function freePort() {
  return new Promise((resolve, reject) => {
    const srv = net.createServer();
    srv.on('error', reject);
    srv.listen(0, '127.0.0.1', () => {
      const { port } = srv.address();
      srv.close(() => resolve(port));
    });
  });
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/* One request over the daemon's Unix socket (where tokens are issued): {status, json}. */
export function unixRequest(socketPath, method, p, body) {
  return new Promise((resolve, reject) => {
    const data = body ? JSON.stringify(body) : null;
    const req = http.request(
      { socketPath, method, path: p, headers: data ? { 'Content-Type': 'application/json', 'Content-Length': Buffer.byteLength(data) } : {} },
      (res) => {
        let text = '';
        res.setEncoding('utf8');
        res.on('data', (c) => (text += c));
        res.on('end', () => {
          let json = null;
          try {
            json = JSON.parse(text);
          } catch {
            /* not JSON */
          }
          resolve({ status: res.statusCode, json, text });
        });
      },
    );
    req.on('error', reject);
    if (data) req.write(data);
    req.end();
  });
}

// Daemons still running; killed when this process exits however it exits.
const live = new Set();
process.on('exit', () => {
  for (const c of live) c.kill('SIGKILL');
});
for (const sig of ['SIGINT', 'SIGTERM', 'SIGHUP']) process.on(sig, () => process.exit(1));

export async function startDaemon({ binary, webDir, logFile, extraArgs = [] }) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'aalab-webtest-'));
  const stateDir = path.join(dir, 'state');
  const socket = path.join(dir, 'aalabd.sock');
  fs.mkdirSync(stateDir);
  const port = await freePort();
  const args = ['--socket', socket, '--state-dir', stateDir, '--tcp', `127.0.0.1:${port}`, '--web-dir', webDir, '--workers', '2', '--enable-test-kinds', ...extraArgs];
  const log = fs.openSync(logFile, 'w');
  const child = spawn(binary, args, { stdio: ['ignore', log, log], env: { ...process.env, XDG_RUNTIME_DIR: dir } });
  let exited = null;
  child.on('exit', (code, signal) => (exited = { code, signal }));
  live.add(child);
  // If this runner dies without cleaning up (killed by a ctest timeout, a closed pipe, ...), the
  // watchdog sees its stdin close and kills the daemon, so no aalabd outlives its test.
  const watchdog = spawn('sh', ['-c', 'read _; kill -KILL "$1" 2>/dev/null', 'aalabd-watchdog', String(child.pid)], { stdio: ['pipe', 'ignore', 'ignore'] });
  const base = `http://127.0.0.1:${port}`;
  const deadline = Date.now() + 20000;
  let lastError = '';
  for (;;) {
    if (exited) throw new Error(`aalabd exited during start-up (${JSON.stringify(exited)}); see ${logFile}`);
    if (Date.now() > deadline) {
      child.kill('SIGKILL');
      throw new Error(`aalabd did not answer GET /v1/health on ${base} within 20 s (${lastError}); see ${logFile}`);
    }
    try {
      // Up when the TCP listener answers (401 without a token is an answer).
      const r = await fetch(`${base}/v1/health`);
      if (r.status === 401 && fs.existsSync(socket)) break;
      lastError = `HTTP ${r.status}`;
    } catch (e) {
      lastError = e.cause ? e.cause.code || e.message : e.message;
    }
    await sleep(100);
  }
  // A token issued to this user over the Unix socket, as `aalab token` does.
  const issued = await unixRequest(socket, 'POST', '/v1/tokens', { label: 'web tests' });
  if (issued.status !== 201) throw new Error(`POST /v1/tokens: HTTP ${issued.status} ${issued.text.slice(0, 300)}`);
  const { token } = issued.json;
  let stopped = false;
  return {
    base,
    token,
    socket,
    stateDir,
    async stop() {
      if (stopped) return exited; // a suite may stop its daemon before the runner does
      stopped = true;
      watchdog.kill('SIGKILL');
      if (!exited) {
        child.kill('SIGTERM');
        for (let i = 0; i < 100 && !exited; i++) await sleep(50);
        if (!exited) child.kill('SIGKILL');
      }
      live.delete(child);
      fs.closeSync(log);
      fs.rmSync(dir, { recursive: true, force: true });
      return exited;
    },
  };
}

/* JSON API calls from the test itself, to compare what the page shows with what the API says. */
export function apiClient(base, token, onAnswer = null) {
  return async function api(method, p, body) {
    const r = await fetch(base + p, {
      method,
      headers: { Authorization: `Bearer ${token}`, ...(body ? { 'Content-Type': 'application/json' } : {}) },
      body: body ? JSON.stringify(body) : undefined,
    });
    const text = await r.text();
    let json = null;
    try {
      json = JSON.parse(text);
    } catch {
      /* not JSON */
    }
    if (onAnswer && json !== null) onAnswer(method, new URL(base + p).pathname, r.status, json);
    if (!r.ok) throw new Error(`${method} ${p}: HTTP ${r.status} ${text.slice(0, 300)}`);
    return json;
  };
}
