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

// A 422's field said next to its control: `controls` maps the field's last name (e.g.
// "fence_friction" of "body.options.fence_friction") to the id of its input; the note is
// cleared by clearFieldErrors (called before each request of the form).
export function markFieldError(err, controls) {
  const name = err && err.field ? String(err.field).split(".").pop() : null;
  const id = name && controls[name];
  const input = id && document.getElementById(id);
  if (!input) return;
  input.setAttribute("aria-invalid", "true");
  const note = Object.assign(document.createElement("span"), { className: "field-error", role: "alert" });
  note.dataset.field = name;
  note.textContent = err.message;
  (input.closest("label") || input).after(note);
}

export function clearFieldErrors(form) {
  form.querySelectorAll(".field-error").forEach((n) => n.remove());
  form.querySelectorAll("[aria-invalid]").forEach((n) => n.removeAttribute("aria-invalid"));
}
