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
    const msg = r.status === 401 ? "this service needs an API key: enter it above" : e.message || r.statusText;
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
