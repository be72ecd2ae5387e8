// The REST API's client (libs/dashboard/openapi.yaml): JSON in and out, the session cookie sent
// with every request, the CSRF token of the session in the header X-CSRF-Token of every request
// that changes something (POST, DELETE), and every error as an ApiError carrying the server's
// {"error": "...", "status": N} text, so the pages can show what went wrong.

export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
  }
}

let csrfToken = '';
let session = null;

// The logged-in user {user, role, csrf}, or null.
export function currentSession() {
  return session;
}

function remember(value) {
  session = value;
  csrfToken = value ? value.csrf || '' : '';
  return value;
}

async function errorOf(response) {
  let text = response.statusText || `HTTP ${response.status}`;
  try {
    const body = await response.json();
    if (body && typeof body.error === 'string') text = body.error;
  } catch {
    // not JSON (a proxy's page, an empty body): the status line says enough
  }
  if (response.status === 429) {
    const after = response.headers.get('Retry-After');
    if (after) text += ` (try again in ${after} s)`;
  }
  return new ApiError(response.status, text);
}

// One request; the parsed JSON answer (null for an empty one), or throws ApiError.
export async function request(method, path, body) {
  const headers = {Accept: 'application/json'};
  const init = {method, credentials: 'same-origin', headers, cache: 'no-store'};
  if (body !== undefined) {
    headers['Content-Type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  if (method !== 'GET' && method !== 'HEAD') headers['X-CSRF-Token'] = csrfToken;
  let response;
  try {
    response = await fetch(path, init);
  } catch (e) {
    throw new ApiError(0, `the server is not reachable (${e.message})`);
  }
  if (!response.ok) throw await errorOf(response);
  const text = await response.text();
  return text ? JSON.parse(text) : null;
}

// A query string of the defined parameters.
export function query(params) {
  const q = new URLSearchParams();
  for (const [key, value] of Object.entries(params || {})) {
    if (value !== undefined && value !== null && value !== '') q.set(key, String(value));
  }
  const text = q.toString();
  return text ? `?${text}` : '';
}

const enc = encodeURIComponent;

// The session: null when nobody is logged in (401).
export async function loadSession() {
  try {
    return remember(await request('GET', '/api/session'));
  } catch (e) {
    if (e.status === 401) return remember(null);
    throw e;
  }
}

export async function login(user, password) {
  return remember(await request('POST', '/api/session', {user, password}));
}

export async function logout() {
  try {
    await request('DELETE', '/api/session');
  } finally {
    remember(null);
  }
}

// Operator, engineer and admin may command machines, acknowledge alarms and cancel any order.
export function mayOperate(role) {
  return role === 'operator' || role === 'engineer' || role === 'admin';
}

export const catalog = () => request('GET', '/api/catalog');
export const layout = () => request('GET', '/api/layout');
export const orders = (params) => request('GET', `/api/orders${query(params)}`);
export const order = (id) => request('GET', `/api/orders/${enc(id)}`);
export const placeOrder = (box, candy) => request('POST', '/api/orders', {box, candy});
export const cancelOrder = (id) => request('DELETE', `/api/orders/${enc(id)}`);
export const negotiation = (id) => request('GET', `/api/orders/${enc(id)}/negotiation`);
export const machines = () => request('GET', '/api/machines');
export const machine = (name) => request('GET', `/api/machines/${enc(name)}`);
export const command = (name, cmd) => request('POST', `/api/machines/${enc(name)}/commands/${enc(cmd)}`);
export const series = (params) => request('GET', `/api/series${query(params)}`);
export const aggregate = (id, params) => request('GET', `/api/series/${enc(id)}/aggregate${query(params)}`);
export const alarms = (params) => request('GET', `/api/alarms${query(params)}`);
export const acknowledge = (id, comment) => request('POST', `/api/alarms/${enc(id)}/ack`, {comment});
export const oee = (params) => request('GET', `/api/oee${query(params)}`);
