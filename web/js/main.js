// Dashboard shell: token, tabs with hash routing (#/view?key=value), health line, error toast.

import { apiGet, getToken, setComputeShares, setToken, takeTokenFromFragment } from './api.js';
import { setHealth } from './store.js';
import * as evaluate from './views/evaluate.js';
import * as families from './views/families.js';
import * as jobs from './views/jobs.js';
import * as tiles from './views/tiles.js';
import * as temporal from './views/temporal.js';

const views = { evaluate, families, jobs, tiles, temporal };
const inited = new Set();
let current = null;

export function toast(message) {
  const t = document.getElementById('toast');
  t.textContent = message;
  t.hidden = false;
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => (t.hidden = true), 8000);
}

export function parseRoute(hash = location.hash) {
  const frag = hash.replace(/^#\/?/, '');
  const [name, query = ''] = frag.split('?');
  const params = Object.fromEntries(new URLSearchParams(query));
  return { name: views[name] ? name : 'evaluate', params };
}

export function navigate(name, params = {}) {
  const q = new URLSearchParams(params).toString();
  location.hash = `#/${name}${q ? '?' + q : ''}`;
}

async function route() {
  const { name, params } = parseRoute();
  for (const [n] of Object.entries(views)) {
    const tab = document.getElementById(`tab-${n}`);
    const panel = document.getElementById(`view-${n}`);
    const active = n === name;
    tab.setAttribute('aria-selected', String(active));
    tab.tabIndex = active ? 0 : -1;
    panel.hidden = !active;
  }
  if (current && current !== name && views[current].hide) views[current].hide();
  current = name;
  const view = views[name];
  try {
    if (!inited.has(name)) {
      inited.add(name);
      try {
        await view.init({ toast, navigate });
      } catch (e) {
        inited.delete(name); // e.g. a 401 or a stopped daemon: init again on the next route
        throw e;
      }
    }
    await view.show(params);
  } catch (e) {
    toast(`${name}: ${e.message}`);
  }
}

function setupTabs() {
  const tabs = [...document.querySelectorAll('[role=tab]')];
  tabs.forEach((tab, i) => {
    tab.addEventListener('click', () => navigate(tab.dataset.view));
    tab.addEventListener('keydown', (e) => {
      const d = { ArrowRight: 1, ArrowLeft: -1 }[e.key];
      if (d == null) return;
      const next = tabs[(i + d + tabs.length) % tabs.length];
      next.focus();
      navigate(next.dataset.view);
    });
  });
}

function setupToken() {
  const btn = document.getElementById('token-button');
  const form = document.getElementById('token-form');
  const input = document.getElementById('token-input');
  const refresh = () => {
    btn.textContent = getToken() ? 'Token ✓' : 'Token (none)';
  };
  const hideForm = () => {
    form.hidden = true;
    btn.setAttribute('aria-expanded', 'false');
    refresh();
  };
  btn.addEventListener('click', () => {
    form.hidden = !form.hidden;
    btn.setAttribute('aria-expanded', String(!form.hidden));
    if (!form.hidden) {
      input.value = getToken();
      input.focus();
    }
  });
  form.addEventListener('submit', (e) => {
    e.preventDefault();
    setToken(input.value.trim());
    hideForm();
    btn.focus();
    tokenChanged();
  });
  document.getElementById('token-clear').addEventListener('click', () => {
    setToken('');
    input.value = '';
    refresh();
  });
  refresh();
  const ask = () => {
    if (!form.hidden) return;
    form.hidden = false;
    btn.setAttribute('aria-expanded', 'true');
    input.value = getToken();
    input.focus();
  };
  // Every API request on the TCP listener needs a token: without one the page sends none (each
  // would be a 401) and asks for it; again whenever the daemon refuses one (revoked, or from
  // another daemon).
  if (!getToken()) {
    ask();
    document.getElementById('health').textContent = 'no API token yet: open the dashboard URL with #token=… that scripts/run.sh (or aalab token) prints, or paste the token';
  }
  window.addEventListener('aalab:token-given', hideForm);
  window.addEventListener('aalab:need-token', () => {
    refresh();
    ask();
  });
}

async function pollHealth() {
  const el = document.getElementById('health');
  try {
    const h = await apiGet('/v1/health');
    setHealth(h);
    setComputeShares(h.sharing);
    const byState = Object.entries(h.jobs).filter(([, n]) => n).map(([s, n]) => `${n} ${s}`).join(', ');
    el.textContent = `aalabd ${h.version} · workers busy ${h.workers.busy}/${h.workers.count} · queue ${h.queue.length}${byState ? ' · jobs ' + byState : ''}`;
    el.classList.remove('down');
  } catch (e) {
    // A 401 is an answer: the daemon runs and refuses the token.
    el.textContent = e.status === 401 ? 'wrong or revoked token: set it with the Token button' : e.status === 0 ? 'server unreachable' : `server error: ${e.message}`;
    el.classList.add('down');
  }
}

/* A new token: the 401 notices go, and every view loads again with it (views whose first load
 * failed run init again; the others reload when shown, the current one now). */
function tokenChanged() {
  document.getElementById('toast').hidden = true;
  start();
}

/* Offline banner: shown when a request cannot reach the daemon, with the time of the last
 * answer; the views' content is greyed until the daemon answers again. */
let lastAnswer = null;
function setupOffline() {
  const banner = document.getElementById('offline');
  const text = document.getElementById('offline-text');
  window.addEventListener('aalab:offline', () => {
    const since = lastAnswer ? ` What is shown is from ${lastAnswer.toLocaleTimeString()} and may be stale.` : '';
    text.textContent = `aalabd is not answering (stopped, or the network is down); retrying every 5 s.${since}`;
    banner.hidden = false;
    document.body.classList.add('stale');
  });
  window.addEventListener('aalab:online', () => {
    lastAnswer = new Date();
    if (banner.hidden) return;
    banner.hidden = true;
    document.body.classList.remove('stale');
    route(); // refresh what was stale
  });
  document.getElementById('offline-retry').addEventListener('click', () => {
    text.textContent = 'retrying…';
    pollHealth();
  });
}

let healthTimer = null;

/* Health polling and the current view, once there is a token to send. */
function start() {
  if (!getToken()) return;
  if (!healthTimer) healthTimer = setInterval(pollHealth, 5000);
  pollHealth();
  route();
}

takeTokenFromFragment();
setupTabs();
setupToken();
setupOffline();
window.addEventListener('hashchange', () => {
  // A dashboard URL with #token=… pasted into an open page changes the fragment only.
  if (/(?:^#|&)token=/.test(location.hash)) {
    takeTokenFromFragment();
    window.dispatchEvent(new CustomEvent('aalab:token-given'));
    tokenChanged();
  } else if (getToken()) route();
});
start();
