// The station's page: views Cell, Job (live 3-D, top view, timeline, approval), New job, History.
import * as api from "./api.js";
import { Live } from "./live.js";
import { Scene3D } from "./scene.js";
import { drawTop } from "./top.js";

const $ = (id) => document.getElementById(id);
const STATES = ["REQUESTED", "ACCEPTED", "PLANNING", "PLANNED", "RUNNING", "DONE", "FAILED", "ABORTED", "REFUSED",
  "AWAITING_APPROVAL", "APPROVED", "INCOMPLETE", "REJECTED", "NEEDS_RESCAN", "interrupted"];
const TERMINAL = new Set(["DONE", "FAILED", "ABORTED", "REFUSED", "INCOMPLETE", "REJECTED", "NEEDS_RESCAN"]);

const state = { user: null, role: null, live: null, scene: null, job: null, cloud: null, cloudJob: null, tcp: null, cell: null };

function el(tag, text, cls) {
  const e = document.createElement(tag);
  if (text !== undefined && text !== null) e.textContent = String(text);
  if (cls) e.className = cls;
  return e;
}

function row(tbody, cells) {
  const tr = el("tr");
  for (const c of cells) {
    const td = el("td");
    if (c instanceof Node) td.appendChild(c); else td.textContent = c === undefined || c === null ? "" : String(c);
    tr.appendChild(td);
  }
  tbody.appendChild(tr);
  return tr;
}

function dl(target, pairs) {
  target.replaceChildren();
  for (const [k, v] of pairs) { target.appendChild(el("dt", k)); target.appendChild(el("dd", v)); }
}

function banner(text) {
  $("banner").textContent = text;
  $("banner").hidden = !text;
}

function fmtTime(utime) { return utime ? new Date(utime / 1000).toISOString().replace("T", " ").slice(0, 19) : ""; }

// ---- views and navigation ----
function show(view) {
  for (const v of document.querySelectorAll(".view")) v.hidden = v.id !== "view-" + view;
  for (const a of document.querySelectorAll("nav a")) a.classList.toggle("active", a.id === "nav-" + view);
}

async function route() {
  if (!state.user) return show("login");
  const [view, ...rest] = location.hash.replace(/^#/, "").split("/");
  const arg = rest.length ? decodeURIComponent(rest.join("/")) : "";
  try {
    if (view === "job") { show("job"); await openJob(arg || (state.job && state.job.job_id) || ""); }
    else if (view === "history") { show("history"); await loadHistory(); if (arg) await openRecord(arg); else $("history-job").hidden = true; }
    else if (view === "new") show("new");
    else { show("cell"); await loadCell(); }
  } catch (e) {
    banner(`${e.message}`);
  }
}

// ---- login ----
async function loggedIn(who) {
  state.user = who.user;
  state.role = who.role;
  document.body.classList.toggle("viewer", who.role !== "operator");
  $("who-name").textContent = `${who.user} (${who.role})`;
  $("nav").hidden = false;
  $("who").hidden = false;
  state.live = new Live(onEvent, onCloud);
  state.live.open();
  await route();
}

async function onLogin(ev) {
  ev.preventDefault();
  $("login-error").textContent = "";
  try {
    await loggedIn(await api.login($("login-user").value, $("login-password").value));
  } catch (e) {
    $("login-error").textContent = e.status === 401 ? "Wrong user or password." : e.message;
  }
}

async function onLogout() {
  try { await api.logout(); } catch (e) { /* the session may have ended already */ }
  location.hash = "";
  location.reload();
}

// ---- cell ----
async function loadCell() {
  const c = await api.get("/api/cell");
  state.cell = c;
  const tbody = $("cell-processes").querySelector("tbody");
  tbody.replaceChildren();
  const sup = {};
  for (const p of (c.supervisor && c.supervisor.processes) || []) sup[p.name] = p;
  const hbName = ["STARTING", "OK", "DEGRADED", "ERROR", "STOPPING"];
  for (const p of c.processes) {
    const s = Object.values(sup).find((x) => x.pid === p.pid);
    row(tbody, [p.process, hbName[p.state] || p.state, s ? s.restarts : "", `${p.age.toFixed(1)} s`, p.state_text]);
  }
  for (const s of Object.values(sup))
    if (!c.processes.some((p) => p.pid === s.pid)) row(tbody, [s.name, s.state, s.restarts, "no heartbeat", s.reason || ""]);
  const r = c.robot;
  const modes = ["DISCONNECTED", "IDLE", "RUNNING", "FAULT"];
  dl($("cell-robot"), r ? [["mode", modes[r.mode] || r.mode], ["job", r.job_id || "-"], ["TCP", r.tcp.map((v) => v.toFixed(3)).join(", ") + " m"],
    ["fault", r.fault_code ? `${r.fault_code}: ${r.fault_text}` : "none"], ["age", `${r.age.toFixed(1)} s`]] : [["robot", "no status heard"]]);
  dl($("cell-camera"), [["plate clouds", c.camera_fps > 0 ? `${c.camera_fps.toFixed(2)} per s` : "none recently (job-triggered)"]]);
  const cal = c.cell.calibration;
  // The file's name: the whole path (in the API's cell.file) is the machine's, not what a reader knows it by.
  dl($("cell-calibration"), [["file", c.cell.file.split("/").pop()], ["mounting", cal.eye_in_hand ? "eye-in-hand" : "eye-to-hand"],
    ["method", cal.method], ["date", cal.date],
    // A hand-entered transform has no residuals: its zeros are not a perfect calibration.
    ["residuals", cal.features > 0 ? `RMS ${cal.rms_mm} mm, worst ${cal.worst_mm} mm (${cal.features} features)`
      : "none measured (no calibration features)"],
    ["tool", `radius ${c.cell.tool.radius * 1000} mm`], ["max speed", `${c.cell.max_speed} m/s`]]);
  const faults = $("cell-faults");
  faults.replaceChildren();
  for (const f of c.faults) faults.appendChild(el("li", `${f.source}: ${f.reason}`, "error"));
  if (!c.faults.length) faults.appendChild(el("li", "none"));
}

async function onReset() {
  try {
    const r = await api.post("/api/robot/reset");
    $("reset-result").textContent = `RESET sent (${r.job_id})`;
    setTimeout(loadCell, 800);
  } catch (e) { $("reset-result").textContent = e.message; }
}

// ---- new job ----
function options(prefix) {
  const o = {};
  const speed = $(prefix + "-grind-speed").value, step = $(prefix + "-step").value, dir = $(prefix + "-direction").value;
  if (speed !== "") o.grind_speed = Number(speed);
  if (step !== "") o.step = Number(step);
  if (dir) o.direction = dir;
  return o;
}

async function onNewJob(ev) {
  ev.preventDefault();
  try {
    const r = await api.post("/api/jobs", { part_id: $("new-part").value, options: options("new") });
    $("new-result").textContent = `Job ${r.job_id} started.`;
    location.hash = "#job/" + encodeURIComponent(r.job_id);
  } catch (e) { $("new-result").textContent = e.message; }
}

// ---- job, live ----
// The station's time of the newest status heard per job, live, before or while its snapshot is fetched: a
// snapshot older than that is fetched again, so that a last status (AWAITING_APPROVAL, with nothing after
// it) is never lost between the POST that started a job and the page's first look at it.
const heard = new Map();
function hear(ev) {
  if (heard.size > 1000) heard.clear();
  heard.set(ev.job_id, Math.max(heard.get(ev.job_id) || 0, ev.utime || 0));
}

async function openJob(id) {
  if (!state.scene) state.scene = new Scene3D($("job-3d"));
  if (!id) { $("job-id").textContent = "(none: start one under New job)"; return; }
  // The cloud, the larger part of the first render, is asked for at once, while the job's JSON is fetched.
  const changed = !state.job || state.job.job_id !== id;
  if (changed) askCloud(id);
  let j;
  try {
    j = await api.get("/api/jobs/" + encodeURIComponent(id));
  } catch (e) {
    if (changed) askCloud(null);  // no such job: draw no cloud for it
    throw e;
  }
  if ((heard.get(id) || 0) > ((j.live && j.live.updated_utime) || 0)) refreshJobSoon();
  state.job = { job_id: id, live: j.live, record: j.record };
  askOutlineCloud(state.job);
  renderJob();
}

// The job whose cloud the 3-D and top views wait for (null: none; a frame that comes then is not drawn).
function askCloud(id) {
  state.cloud = null;
  state.cloudJob = id;
  if (id) state.live.requestCloud(id);
}

// A job opened before its capture got the newest cloud there was (another job's); once the job's outline
// names its cloud, that one is asked for, once per cloud.
function askOutlineCloud(j) {
  const seq = j.live && j.live.outline ? j.live.outline.cloud_seq : undefined;
  if (seq === undefined || !state.cloud || Number($("job-3d").dataset.cloudSeq) === seq || state.cloudAsked === seq) return;
  state.cloudAsked = seq;
  askCloud(j.job_id);
}

function jobState() {
  const j = state.job;
  if (j.live) return j.live.state;
  return j.record ? j.record.job.state : "";
}

function renderJob() {
  const j = state.job, live = j.live;
  $("job-id").textContent = j.job_id;
  const st = jobState();
  $("job-state").textContent = st;
  $("job-state").className = "state " + st;
  const last = live && live.statuses.length ? live.statuses[live.statuses.length - 1] : null;
  $("job-message").textContent = last ? last.message
    : st === "REQUESTED" ? "started by this station; no process has answered yet"
    : (j.record ? j.record.job.message || "" : "");
  const running = last && last.state === "RUNNING" ? last.progress : null;
  $("job-progress-bar").style.width = `${100 * (st === "DONE" ? 1 : running !== null ? running : 0)}%`;
  $("job-abort").hidden = TERMINAL.has(st);
  renderTimeline(live ? live.statuses : []);
  renderScan(live && live.outline);
  renderApproval(st, live);
  if (live) {
    state.scene.setOutline(live.outline);
    state.scene.setEdge(live.plan && live.plan.edge);
    state.scene.setPlan(live.plan);
    if (live.outline && live.outline.placement_error) banner(`outline ${live.outline.seq}: ${live.outline.placement_error}`);
  }
  drawTopView();
}

// At most once per animation frame (see Scene3D.render): poses come faster than a frame.
let topPending = false;
function drawTopView() {
  if (topPending) return;
  topPending = true;
  requestAnimationFrame(() => {
    topPending = false;
    const live = state.job && state.job.live;
    drawTop($("job-top"), { cloud: state.cloud, outline: live && live.outline, plan: live && live.plan, tcp: state.tcp });
  });
}

// outline_t's QUALITY_*: what the outline service judged of the scan's edge against the cell's limits.
const VERDICT = { 0: "not assessed", 1: "OK", 2: "POOR: rescan" };
const mm = (m) => `${(m * 1000).toFixed(1)} mm`;
const mm2 = (m2) => `${(m2 * 1e6).toFixed(0)} mm²`;

// The outline's scan-quality figures, so that an operator sees why a job ended NEEDS_RESCAN (or what was
// filled and dropped on the way to a plan).
function renderScan(o) {
  const dl = $("job-scan"), verdict = $("job-scan-verdict");
  dl.replaceChildren();
  verdict.textContent = o ? VERDICT[o.quality] || `quality ${o.quality}` : "no outline yet";
  verdict.className = "verdict q" + (o ? o.quality : "");
  if (!o) return;
  const entries = [
    ["edge in dropout or shadow", `${(100 * o.edge_dropout_fraction).toFixed(1)} %`],
    ["largest gap along the edge", mm(o.largest_edge_gap)],
    ["why", o.quality_text || "-"],
    ["gaps filled or dropped", `${o.holes_dropped} (${mm2(o.holes_dropped_area)})`],
    ["fragments dropped", `${o.fragments_dropped} (${mm2(o.fragments_dropped_area)})`],
    ["dropped", o.dropped_text || "-"],
    ["points", o.points_read],
    ["point spacing h", mm(o.point_spacing)],
    ["alpha radius R", `${mm(o.alpha_radius)} (${o.alpha_automatic ? "automatic" : "given"}, ${o.alpha_mode || "-"})`],
  ];
  for (const [k, v] of entries) {
    const dt = el("dt", k);
    dt.dataset.key = k;
    dl.append(dt, el("dd", v));
  }
}

function renderTimeline(statuses) {
  const tbody = $("job-timeline").querySelector("tbody");
  tbody.replaceChildren();
  // In the order of the times shown: two processes' statuses of the same instant may arrive swapped.
  const rows = [...statuses].sort((a, b) => a.utime - b.utime);
  const t0 = rows.length ? rows[0].utime : 0;
  for (const s of rows)
    row(tbody, [fmtTime(s.utime), ((s.utime - t0) / 1e6).toFixed(2), s.source, s.state,
      s.message + (s.actor ? ` [${s.actor}]` : "")]);
}

// The loops the operator ticked for exclusion, per job and plan revision: the approval table is drawn again
// whenever the job's snapshot is fetched, and must not forget them.
function excluded(plan) {
  const key = `${plan.job_id} ${plan.revision}`;
  if (!state.exclude || state.exclude.key !== key) state.exclude = { key, loops: new Set() };
  return state.exclude.loops;
}

function renderApproval(st, live) {
  const box = $("approval");
  box.hidden = st !== "AWAITING_APPROVAL" || !live || !live.plan || !live.plan.coverage;
  if (box.hidden) return;
  const plan = live.plan;
  $("approval-revision").textContent = plan.revision;
  const tbody = $("approval-loops").querySelector("tbody");
  tbody.replaceChildren();
  for (const c of plan.coverage) {
    const box = el("input");
    box.type = "checkbox";
    box.className = "exclude";
    box.dataset.loop = c.loop_index;
    box.id = "exclude-" + c.loop_index;
    if (state.role !== "operator") box.disabled = true;
    box.checked = excluded(plan).has(c.loop_index);
    box.addEventListener("change", () => { if (box.checked) excluded(plan).add(c.loop_index); else excluded(plan).delete(c.loop_index); });
    row(tbody, [c.loop_index, c.hole ? "hole" : "outer", c.planned ? "yes" : "no", `${(c.edge_length * 1000).toFixed(1)} mm`,
      `${(100 * c.reached_length / (c.edge_length || 1)).toFixed(1)} %`, c.reason, box]);
  }
  const warn = $("approval-warnings");
  warn.replaceChildren();
  for (const u of plan.unreached) warn.appendChild(el("li", `loop ${u.loop_index} (${u.hole ? "hole" : "outer"}): ${u.cause}, ${(u.length * 1000).toFixed(1)} mm: ${u.reason}`));
  const last = live.statuses[live.statuses.length - 1];
  for (const u of (last && last.unground) || [])
    if (!plan.unreached.some((p) => p.loop_index === u.loop_index && p.start === u.start))
      warn.appendChild(el("li", `loop ${u.loop_index}: ${u.cause}: ${u.reason}`));
  if (!warn.children.length) warn.appendChild(el("li", "none"));
}

async function jobAction(action, body) {
  const j = state.job;
  try {
    await api.post(`/api/jobs/${encodeURIComponent(j.job_id)}/${action}`, body);
    $("approval-result").textContent = `${action} sent`;
  } catch (e) {
    $("approval-result").textContent = e.message;
    banner(e.message);
  }
}

function onApprove() {
  const exclude = [...excluded(state.job.live.plan)].sort((a, b) => a - b);
  jobAction("approve", { exclude_loops: exclude, plan_revision: state.job.live.plan.revision });
}

// ---- live events ----
let refreshTimer = null;
function refreshJobSoon() {
  if (refreshTimer) return;
  refreshTimer = setTimeout(async () => {
    refreshTimer = null;
    if (state.job && !$("view-job").hidden) {
      try { await openJob(state.job.job_id); } catch (e) { banner(e.message); }
    }
  }, 150);
}

function onEvent(ev) {
  const j = state.job;
  if (ev.type === "status") hear(ev);
  if (ev.type === "lost") {  // the station dropped events this page was too slow for: read the state again
    if (j) refreshJobSoon();
    if (!$("view-cell").hidden) cellSoon();
    return;
  }
  if (ev.type === "status" && j && ev.job_id === j.job_id) {
    if (j.live) {  // update in place: the progress bar follows every status
      const rows = j.live.statuses, last = rows[rows.length - 1];
      // A new source or state: a row of its own at once (the label, message and timeline agree), then the
      // snapshot for what else changed with it (a plan, an outline).
      if (last && last.source === ev.source && last.state === ev.state) rows[rows.length - 1] = ev;
      else { rows.push(ev); refreshJobSoon(); }
      if (!ev.answer) j.live.state = ev.state;
      renderJobLight();
    } else refreshJobSoon();
  } else if ((ev.type === "path" && j && ev.job_id === j.job_id) || (ev.type === "outline" && j && j.live && !j.live.outline)) {
    refreshJobSoon();
  } else if (ev.type === "cloud" && ev.placement_error) {
    if (j) banner(`plate cloud ${ev.seq}: ${ev.placement_error}`);
  } else if (ev.type === "cloud" && state.cloudJob && !state.cloud) {
    askCloud(state.cloudJob);  // the job asked before the station had a cloud (its JSON may still be coming)
  } else if (ev.type === "robot") {
    if (ev.job_id && j && ev.job_id === j.job_id) {
      state.tcp = ev.tcp;
      if (state.scene) state.scene.setTcp(ev.tcp);
      drawTopView();
    }
    if (ev.mode === 3 && !$("view-cell").hidden) loadCell().catch(() => {});
  } else if (ev.type === "heartbeat" && !$("view-cell").hidden) {
    cellSoon();
  }
}

let cellTimer = null;
function cellSoon() {
  if (cellTimer) return;
  cellTimer = setTimeout(() => { cellTimer = null; loadCell().catch((e) => banner(e.message)); }, 1000);
}

function renderJobLight() {
  const j = state.job, rows = j.live.statuses, last = rows[rows.length - 1];
  const st = j.live.state;
  $("job-state").textContent = st;
  $("job-state").className = "state " + st;
  $("job-message").textContent = last ? last.message : "";
  const p = st === "DONE" ? 1 : last && last.state === "RUNNING" ? last.progress : 0;
  $("job-progress-bar").style.width = `${100 * p}%`;
  $("job-abort").hidden = TERMINAL.has(st);
  renderTimeline(rows);
  if (st !== "AWAITING_APPROVAL") $("approval").hidden = true;
}

function onCloud(cloud) {
  performance.mark("hg-cloud-received");  // tools/bench/station_bench.py: transfer vs. drawing
  if (!state.cloudJob) return;
  state.cloud = cloud.xyz;
  $("job-3d").dataset.cloudSeq = cloud.seq;  // the browser tests compare it with the job's outline
  if (state.scene) state.scene.setCloud(cloud.xyz);
  drawTopView();
}

// ---- history ----
async function loadHistory() {
  const q = new URLSearchParams();
  for (const [k, id] of [["state", "history-state"], ["part", "history-part"], ["from", "history-from"], ["to", "history-to"]])
    if ($(id).value) q.set(k, $(id).value);
  const r = await api.get("/api/jobs?" + q.toString());
  const tbody = $("history-table").querySelector("tbody");
  tbody.replaceChildren();
  for (const j of r.jobs) {
    const a = el("a", j.job_id);
    a.href = "#history/" + encodeURIComponent(j.job_id);
    row(tbody, [j.requested, a, j.part_id, j.interrupted && !j.final ? "interrupted" : j.state, j.ended, j.reason]);
  }
  for (const j of r.live_only) {
    const a = el("a", j.job_id);
    a.href = "#job/" + encodeURIComponent(j.job_id);
    row(tbody, [fmtTime(j.first_utime), a, j.part_id, j.state + " (not recorded yet)", "", ""]);
  }
}

async function openRecord(id) {
  const r = await api.get("/api/jobs/" + encodeURIComponent(id));
  $("history-job").hidden = false;
  $("hj-id").textContent = id;
  const rec = r.record ? r.record.job : {};
  const req = rec.request || {};
  // The decisions and who made them: requests (START, APPROVE, REJECT, ABORT ...) and the statuses that
  // carry a decision; progress statuses repeat the approver's name and would bury them.
  const decided = new Set(["APPROVED", "REJECTED", "ABORTED"]);
  const approval = [...new Set((r.record ? r.record.events : [])
    .filter((e) => (e.action && e.action !== "QUERY") || decided.has(e.state))
    .map((e) => `${e.state || e.action || ""} by ${e.actor || "?"}${e.excluded_loops && e.excluded_loops.length ? ", excluded loops " + e.excluded_loops.join(", ") : ""}`))];
  dl($("hj-summary"), [["part", rec.part_id], ["state", rec.state], ["requested", rec.requested], ["ended", rec.ended || ""],
    ["reason", rec.reason || rec.message || ""], ["request", JSON.stringify(req)],
    ["outline", rec.outline ? JSON.stringify(rec.outline) : "-"], ["path", rec.path ? JSON.stringify(rec.path) : "-"],
    ["approval", approval.join("; ") || "-"]]);
  const files = $("hj-files");
  files.replaceChildren();
  for (const f of r.record ? r.record.files : []) {
    const a = el("a", `${f.name} (${f.size} bytes)`);
    a.href = `/api/jobs/${encodeURIComponent(id)}/files/${encodeURIComponent(f.name)}`;
    a.setAttribute("download", f.name);
    a.className = "download";
    const li = el("li");
    li.appendChild(a);
    files.appendChild(li);
  }
  await drawRecordOverview(id, r.record);
  const tbody = $("hj-events").querySelector("tbody");
  tbody.replaceChildren();
  for (const e of r.record ? r.record.events : [])
    row(tbody, [e.time, e.event || e.type || "", e.source || "", e.state || e.action || "", e.message || e.why || ""]);
  const open = el("a", "open the live view");
  open.href = "#job/" + encodeURIComponent(id);
  files.appendChild(el("li")).appendChild(open);
}

// The overview from the record alone (a job heard before the station started has no live data): the path
// (path.json, its own frame) and the outline (outline.json, in its plate plane: the record holds no
// calibration to put it in the base frame) with the stretches job.json says were left unground.
const KIND_NAMES = ["approach", "lead_in", "grind", "lead_out", "retract", "travel"];
// Causes whose stretch is the whole loop (its length the smoothed edge's, shorter than the outline's ragged one).
const WHOLE_LOOP = new Set(["EXCLUDED", "TOO_SMALL"]);
async function drawRecordOverview(id, record) {
  const names = new Set(((record && record.files) || []).map((f) => f.name));
  const file = async (name) => {
    if (!names.has(name)) return null;
    const d = await api.get(`/api/jobs/${encodeURIComponent(id)}/files/${name}`);
    return typeof d === "string" ? JSON.parse(d) : d;
  };
  const [path, outline] = await Promise.all([file("path.json"), file("outline.json")]);
  const none = $("hj-overview-none");
  none.hidden = !!(path && outline);
  none.textContent = `The record holds no ${[path ? "" : "path.json", outline ? "" : "outline.json"].filter(Boolean).join(" and ")}: not drawn.`;
  const pathCanvas = $("hj-overview"), outlineCanvas = $("hj-outline");
  pathCanvas.dataset.drawn = outlineCanvas.dataset.drawn = "";
  const plan = path && { position: path.waypoints.flatMap((w) => w.position), kind: path.waypoints.map((w) => KIND_NAMES.indexOf(w.kind)) };
  drawTop(pathCanvas, { plan });
  $("hj-path-frame").textContent = (path && path.frame) || "?";
  if (path) pathCanvas.dataset.drawn = `path ${path.waypoints.length} waypoints, frame ${path.frame || "?"}`;
  const loops = outline ? outline.loops.map((l) => ({ hole: l.hole, xyz: l.points.flatMap((p) => [p[0], p[1], 0]) })) : [];
  const unreached = ((record && record.job.unground) || []).filter((u) => loops[u.loop])
    .map((u) => ({ xyz: alongLoop(loops[u.loop].xyz, u.start, WHOLE_LOOP.has(u.cause) ? Infinity : u.length) }));
  drawTop(outlineCanvas, { outline: outline && { loops }, plan: { position: [], kind: [], unreached } });
  if (outline) outlineCanvas.dataset.drawn = `outline ${loops.length} loops, ${unreached.length} unground stretches`;
}

// The points of a closed loop (xyz flat) from arc length `start` over `length` (wrapping past the first vertex).
function alongLoop(xyz, start, length) {
  const n = xyz.length / 3, out = [];
  const d = (i, j) => Math.hypot(xyz[3 * j] - xyz[3 * i], xyz[3 * j + 1] - xyz[3 * i + 1]);
  let perimeter = 0;
  for (let i = 0; i < n; i++) perimeter += d(i, (i + 1) % n);
  if (!(perimeter > 0)) return out;
  let s = 0, end = start + Math.min(length, perimeter);
  for (let k = 0; k < 2 * n && s < end; k++) {
    const i = k % n, j = (k + 1) % n, seg = d(i, j);
    const at = (t) => [xyz[3 * i] + t * (xyz[3 * j] - xyz[3 * i]), xyz[3 * i + 1] + t * (xyz[3 * j + 1] - xyz[3 * i + 1]), 0];
    if (s + seg >= start && seg > 0) {
      if (!out.length) out.push(...at((start - s) / seg));
      out.push(...at(Math.min(1, (end - s) / seg)));
    }
    s += seg;
  }
  return out;
}

// ---- start ----
function wire() {
  for (const s of STATES) $("history-state").appendChild(el("option", s));
  $("login-form").addEventListener("submit", onLogin);
  $("logout").addEventListener("click", onLogout);
  $("reset").addEventListener("click", onReset);
  $("new-form").addEventListener("submit", onNewJob);
  $("job-abort").addEventListener("click", () => jobAction("abort"));
  $("approve").addEventListener("click", onApprove);
  $("reject").addEventListener("click", () => jobAction("reject"));
  $("replan").addEventListener("click", () => jobAction("replan", { options: options("replan") }));
  $("history-filter").addEventListener("submit", (ev) => { ev.preventDefault(); loadHistory().catch((e) => banner(e.message)); });
  window.addEventListener("hashchange", () => { banner(""); route(); });
}

async function start() {
  wire();
  try {
    const who = await api.session();
    if (who.user) await loggedIn(who); else show("login");
  } catch (e) {
    show("login");
  }
}

start();
