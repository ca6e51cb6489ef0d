// Minimal test bookkeeping: named checks, a failure stops the suite it belongs to (later checks
// depend on earlier state), and a closing "N passed, N failed" line.

export class Report {
  constructor() {
    this.passed = 0;
    this.failed = 0;
  }
  pass(name) {
    this.passed++;
    console.log(`ok - ${name}`);
  }
  fail(name, err) {
    this.failed++;
    console.log(`not ok - ${name}`);
    for (const line of String(err && err.stack ? err.stack : err).split('\n')) console.log(`#   ${line}`);
  }
}

export function assert(cond, message) {
  if (!cond) throw new Error(message);
}

export async function eventually(fn, { timeout = 15000, interval = 100, message = 'condition' } = {}) {
  const deadline = Date.now() + timeout;
  let last;
  for (;;) {
    try {
      const v = await fn();
      if (v) return v;
      last = v;
    } catch (e) {
      last = e.message;
    }
    if (Date.now() > deadline) throw new Error(`timed out after ${timeout} ms waiting for ${message} (last: ${JSON.stringify(last)})`);
    await new Promise((r) => setTimeout(r, interval));
  }
}
