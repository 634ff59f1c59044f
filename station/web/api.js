// The station's API (docs/station.md): JSON in and out, the CSRF token on every POST.
let csrf = "";

export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function call(method, path, body) {
  const headers = {};
  if (method === "POST") headers["X-CSRF-Token"] = csrf;
  if (body !== undefined) headers["Content-Type"] = "application/json";
  const res = await fetch(path, {
    method, headers, credentials: "same-origin",
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const type = res.headers.get("Content-Type") || "";
  const data = type.startsWith("application/json") ? await res.json() : await res.text();
  if (!res.ok) throw new ApiError(res.status, (data && data.error) || res.statusText);
  return data;
}

export async function login(user, password) {
  const r = await call("POST", "/api/login", { user, password });
  csrf = r.csrf;
  return r;
}

export async function session() {
  const r = await call("GET", "/api/session");
  csrf = r.csrf;
  return r;
}

export async function logout() {
  await call("POST", "/api/logout", {});
  csrf = "";
}

export const get = (path) => call("GET", path);
export const post = (path, body) => call("POST", path, body === undefined ? {} : body);
