// Thin client for the aalabd JSON API. Every request carries the bearer token when one
// is known: on the TCP listener every API request needs one (issued per user on the Unix socket
// with `aalab token`). A 401 raises the event 'aalab:need-token' so the page asks for it.

const TOKEN_KEY = 'aalab.token';

export class ApiError extends Error {
  constructor(status, code, message, field) {
    super(field ? `${message} (field ${field})` : message);
    this.status = status;
    this.code = code;
    this.field = field;
  }
}

export function getToken() {
  try {
    return localStorage.getItem(TOKEN_KEY) || '';
  } catch {
    return '';
  }
}

export function setToken(token) {
  try {
    if (token) localStorage.setItem(TOKEN_KEY, token);
    else localStorage.removeItem(TOKEN_KEY);
  } catch {
    /* storage disabled: the token then lives only as long as the page */
  }
  memoryToken = token;
}

let memoryToken = '';

/* A token in the URL fragment (#token=...) is stored and then removed from the address bar, so
 * it does not end up in bookmarks or screenshots. Returns the rest of the fragment. */
export function takeTokenFromFragment() {
  const frag = location.hash.replace(/^#/, '');
  const m = /(?:^|&)token=([^&]*)/.exec(frag);
  if (!m) return frag;
  setToken(decodeURIComponent(m[1]));
  const rest = frag.replace(m[0], '').replace(/^&/, '');
  history.replaceState(null, '', location.pathname + location.search + (rest ? '#' + rest : '#/evaluate'));
  return rest;
}

/* Tells the page that the daemon wants a (valid) token: main.js opens the token form. */
function needToken() {
  if (typeof window !== 'undefined') window.dispatchEvent(new CustomEvent('aalab:need-token'));
}

/* A fetch that did not reach the daemon (stopped, or the network is down) raises
 * 'aalab:offline' so the page shows its offline banner, and an ApiError saying so instead of the
 * browser's bare "Failed to fetch". Any answer at all raises 'aalab:online'. */
async function reach(path, init) {
  let resp;
  try {
    resp = await fetch(path, init);
  } catch (e) {
    if (e && e.name === 'AbortError') throw e;
    if (typeof window !== 'undefined') window.dispatchEvent(new CustomEvent('aalab:offline'));
    throw new ApiError(0, 'offline', 'aalabd is not answering (stopped, or the network is down)');
  }
  if (typeof window !== 'undefined') window.dispatchEvent(new CustomEvent('aalab:online'));
  return resp;
}

function authHeaders() {
  const token = getToken() || memoryToken;
  return token ? { Authorization: `Bearer ${token}` } : {};
}

async function decode(resp) {
  const type = resp.headers.get('Content-Type') || '';
  let body = null;
  if (type.includes('json')) {
    try {
      body = await resp.json();
    } catch {
      body = null;
    }
  } else {
    body = await resp.text();
  }
  if (!resp.ok) {
    const e = body && body.error ? body.error : {};
    let msg = e.message || `HTTP ${resp.status} ${resp.statusText}`;
    if (resp.status === 401) {
      msg = 'wrong or revoked token: ' + msg + ' — set your API token (button “Token” at the top right; get one with `aalab token`)';
      needToken();
    }
    if (resp.status === 429) msg += ` — server busy, retry after ${resp.headers.get('Retry-After') || '?'} s`;
    throw new ApiError(resp.status, e.code || 'http_error', msg, e.field);
  }
  return body;
}

export async function apiGet(path, { signal } = {}) {
  const resp = await reach(path, { headers: { Accept: 'application/json', ...authHeaders() }, signal });
  return decode(resp);
}

/* The daemon runs at most --user-evaluates evaluates and --user-renders renders per user at once
 * (429 beyond): the page queues its own beyond that, whichever view sends them. The shares are
 * the daemon's (GET /v1/health, "sharing"); its defaults until the first health answer. */
const computeSlots = { '/v1/evaluate': { share: 2, free: 2, waiting: [] }, '/v1/render': { share: 1, free: 1, waiting: [] } };
computeSlots['/v1/predict'] = computeSlots['/v1/evaluate']; // the daemon counts predictions as evaluates
computeSlots['/v1/analyze'] = computeSlots['/v1/evaluate']; // and analyses (issue 31)

export function setComputeShares(sharing) {
  const shares = { '/v1/evaluate': sharing && sharing.user_evaluates, '/v1/render': sharing && sharing.user_renders };
  for (const [path, share] of Object.entries(shares)) {
    const slot = computeSlots[path];
    if (!Number.isInteger(share) || share < 1 || share === slot.share) continue;
    slot.free += share - slot.share; /* may go negative while more than the new share run */
    slot.share = share;
    while (slot.free > 0 && slot.waiting.length) {
      slot.free--;
      slot.waiting.shift()();
    }
  }
}

async function withSlot(path, fn) {
  const slot = computeSlots[path];
  if (!slot) return fn();
  if (slot.free > 0 && slot.waiting.length === 0) slot.free--;
  else await new Promise((resolve) => slot.waiting.push(resolve));
  try {
    return await fn();
  } finally {
    const next = slot.free >= 0 ? slot.waiting.shift() : undefined;
    if (next) next();
    else slot.free++;
  }
}

export async function apiPost(path, body, { signal } = {}) {
  return withSlot(path, async () => {
    const resp = await reach(path, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json', Accept: 'application/json', ...authHeaders() },
      body: JSON.stringify(body),
      signal,
    });
    return decode(resp);
  });
}

export async function apiDelete(path) {
  const resp = await reach(path, { method: 'DELETE', headers: { Accept: 'application/json', ...authHeaders() } });
  return decode(resp);
}

/* Text download (export formats are not all JSON). */
export async function apiGetText(path) {
  const resp = await reach(path, { headers: authHeaders() });
  const text = await resp.text();
  if (!resp.ok) {
    if (resp.status === 401) needToken();
    let msg = resp.status === 401 ? 'wrong or revoked token (HTTP 401)' : `HTTP ${resp.status}`;
    try {
      const j = JSON.parse(text);
      if (j.error) msg = j.error.message || msg;
    } catch {
      /* not JSON: keep the status */
    }
    throw new ApiError(resp.status, 'http_error', msg);
  }
  return { text, type: resp.headers.get('Content-Type') || 'text/plain' };
}

/* Images need the token too when the tile endpoint is protected: fetch as a blob URL. */
export async function apiImageUrl(path) {
  const resp = await reach(path, { headers: authHeaders() });
  if (!resp.ok) {
    if (resp.status === 401) needToken();
    throw new ApiError(resp.status, 'http_error', `image ${path}: HTTP ${resp.status}`);
  }
  return URL.createObjectURL(await resp.blob());
}
