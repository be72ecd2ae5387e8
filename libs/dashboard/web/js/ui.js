// What both pages share: building elements without innerHTML (texts from the server are never
// parsed as markup), the message area where errors are shown, the login form and the header with
// the user, times and numbers as people read them.
import * as api from './api.js';

// An element with attributes ({class, text, on: {event: fn}, dataset, ...}) and children.
export function el(tag, attrs = {}, ...children) {
  const svg = ['svg', 'g', 'path', 'line', 'polyline', 'rect', 'circle', 'text', 'title'].includes(tag);
  const node = svg ? document.createElementNS('http://www.w3.org/2000/svg', tag) : document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (value === undefined || value === null || value === false) continue;
    if (key === 'text') node.textContent = String(value);
    else if (key === 'on') for (const [event, fn] of Object.entries(value)) node.addEventListener(event, fn);
    else if (key === 'dataset') Object.assign(node.dataset, value);
    else if (key === 'class' && !svg) node.className = value;
    else if (key in node && !svg && typeof value !== 'string') node[key] = value;
    else node.setAttribute(key, value === true ? '' : String(value));
  }
  for (const child of children.flat()) {
    if (child === null || child === undefined || child === false) continue;
    node.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return node;
}

export const $ = (selector, root = document) => root.querySelector(selector);

export function clear(node, ...children) {
  node.replaceChildren(...children.flat().filter((c) => c !== null && c !== undefined && c !== false));
  return node;
}

// Shows a message in the page's message area (#messages): kind 'error' or 'info'.
export function notify(text, kind = 'info') {
  const box = $('#messages');
  if (!box) return;
  const item = el('div', {class: `message ${kind}`, role: kind === 'error' ? 'alert' : 'status'},
    el('span', {text}),
    el('button', {type: 'button', class: 'dismiss', 'aria-label': 'dismiss', text: '×',
      on: {click: () => item.remove()}}));
  box.append(item);
  if (kind !== 'error') setTimeout(() => item.remove(), 6000);
}

export function showError(error) {
  const status = error && error.status ? ` (${error.status})` : '';
  notify(`${error && error.message ? error.message : String(error)}${status}`, 'error');
}

// Runs an async handler and shows its error instead of losing it.
export function guard(fn) {
  return async (...args) => {
    try {
      return await fn(...args);
    } catch (e) {
      showError(e);
      return undefined;
    }
  };
}

export function time(t) {
  if (t === undefined || t === null || t === '') return '';
  const d = new Date(typeof t === 'number' ? t : String(t));
  return Number.isNaN(d.getTime()) ? String(t) : d.toLocaleTimeString();
}

export function millis(t) {
  return new Date(typeof t === 'number' ? t : String(t)).getTime();
}

export function percent(x) {
  return x === null || x === undefined ? '–' : `${(100 * x).toFixed(1)} %`;
}

export function value(v) {
  if (v === null || v === undefined) return '–';
  if (typeof v === 'number') return Number.isInteger(v) ? String(v) : v.toFixed(3);
  if (typeof v === 'object') return JSON.stringify(v);
  return String(v);
}

// What every page has around its content, made here once: the header's live badge (#live), user
// (#who) and log-out button (#logout), and the login form (#login) first in <main>.
function addSessionChrome() {
  if ($('#login')) return;
  $('header.bar').append(
      el('span', {id: 'live', class: 'live down'}, 'offline'),
      el('span', {id: 'who'}),
      el('button', {id: 'logout', type: 'button', hidden: true}, 'Log out'));
  $('main').prepend(el('form', {id: 'login', class: 'card', hidden: true},
      el('h2', {}, 'Log in'),
      el('label', {}, 'User ', el('input', {name: 'user', autocomplete: 'username', required: true})),
      el('label', {}, 'Password ',
          el('input', {name: 'password', type: 'password', autocomplete: 'current-password', required: true})),
      el('button', {type: 'submit'}, 'Log in')));
}

// The session of the page: shows the login form (#login) until someone is logged in, then calls
// onSession(session); the header's #who and #logout follow the session.
export async function startSession(onSession) {
  addSessionChrome();
  const form = $('#login');
  const who = $('#who');
  const out = $('#logout');
  const show = (session) => {
    document.body.dataset.role = session ? session.role : '';
    form.hidden = !!session;
    out.hidden = !session;
    who.textContent = session ? `${session.user} (${session.role})` : '';
    if (session) onSession(session);
  };
  form.addEventListener('submit', guard(async (event) => {
    event.preventDefault();
    const data = new FormData(form);
    const session = await api.login(String(data.get('user')), String(data.get('password')));
    form.reset();
    show(session);
  }));
  out.addEventListener('click', guard(async () => {
    await api.logout();
    location.reload();
  }));
  show(await api.loadSession());
}

// The live connection's state in the header (#live).
export function showLiveState(live) {
  addSessionChrome();
  const badge = $('#live');
  const set = (up) => {
    badge.textContent = up ? 'live' : 'offline';
    badge.className = up ? 'live up' : 'live down';
    badge.dataset.connected = up ? 'true' : 'false';
  };
  set(false);
  // How often the stream was opened: a page that refetches on every open is still "live".
  badge.dataset.opens = '0';
  live.on('open', () => {
    badge.dataset.opens = String(Number(badge.dataset.opens) + 1);
    set(true);
  });
  live.on('close', () => set(false));
  live.on('error', (message) => notify(`live: ${message.error}${message.topics ? ` ${message.topics.join(', ')}` : ''}`,
    'error'));
}
