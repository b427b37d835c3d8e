// The public REST API, as any controller calls it: the page has no other access.

const KEY = "algrasp-api-key";

export class ApiError extends Error {
  constructor(status, message, field) {
    super(field ? `${message} (field: ${field})` : message);
    this.status = status;
    this.field = field;
  }
}

export function setKey(key) {
  if (key) sessionStorage.setItem(KEY, key);
  else sessionStorage.removeItem(KEY);
}

export function hasKey() {
  return Boolean(sessionStorage.getItem(KEY));
}

function headers(extra = {}) {
  const key = sessionStorage.getItem(KEY);
  return key ? { ...extra, Authorization: `Bearer ${key}` } : extra;
}

// fetch → JSON (or the Response with raw: true); errors become ApiError with the
// service's message and field ({"error": {...}}).
export async function api(path, { json, form, method, raw } = {}) {
  const init = { method: method || (json || form ? "POST" : "GET"), headers: headers() };
  if (json !== undefined) {
    init.headers["Content-Type"] = "application/json";
    init.body = JSON.stringify(json);
  } else if (form) {
    init.body = form;
  }
  const r = await fetch(path, init);
  if (!r.ok) {
    const body = await r.json().catch(() => null);
    const e = body && body.error ? body.error : {};
    const sent = Boolean(init.headers.Authorization);
    const msg = r.status === 401 || r.status === 403
      ? (sent ? "key rejected: the service did not accept this API key; enter another above" : "this service needs an API key: enter it above")
      : e.message || r.statusText;
    throw new ApiError(r.status, msg, e.field);
  }
  return raw ? r : r.json();
}

// A file the API serves behind the key, saved through a blob URL (a link cannot send a header).
export async function download(path, filename) {
  const r = await api(path, { raw: true });
  const url = URL.createObjectURL(await r.blob());
  const a = Object.assign(document.createElement("a"), { href: url, download: filename });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

// Each panel's current request: begin(panel) makes a new request the current one and
// returns a check; a response is applied only while its request is still current, so a
// later click wins whatever order the answers arrive in.
const serial = {};

export class Superseded extends Error {
  constructor(panel) {
    super(`superseded by a later ${panel} request`);
    this.name = "Superseded";
  }
}

export function begin(panel) {
  const n = (serial[panel] = (serial[panel] || 0) + 1);
  // current(): throws Superseded (counted on the panel's host, data-dropped) once a later request began
  return (host = null) => {
    if (serial[panel] === n) return;
    if (host) host.dataset.dropped = String(Number(host.dataset.dropped || 0) + 1);
    throw new Superseded(panel);
  };
}
