#!/usr/bin/env node
// A Foxglove WebSocket client nobody here wrote (@foxglove/ws-protocol's FoxgloveClient on ws) on a live
// hg-foxglove, while the test runs a job through the pipeline:
//   - receives the advertisement of every channel, subscribes to each as it is advertised, decodes every
//     message (JSON parsed and validated with ajv against the advertised schema, and the foxglove.* ones
//     against @foxglove/schemas), counts raw ones; every advertised schema must be one Foxglove's and
//     Lichtblick's viewers can read (viewer_schema.js);
//   - each /hg/plate/points must give the plate's points back: as many as HG_PLATE_CLOUD's n decimated to
//     --max-points, the same bounding box as the cloud's (u, v) on its plane;
//   - each /hg/grind_path must show its grind_path_t's smoothed edge (scene_check.js);
//   - every process log line received on HG_LOG (log_line_t) must also come as a foxglove.Log on /hg/log
//     with its process, level, time and text; the lines go to RESULT.json for the test to find them in
//     the processes' own log files;
//   - probes: foxglove.sdk.v1 is accepted; no subprotocol is refused; text garbage, binary data and a bad
//     subscribe are each closed with code 1008 and a reason; a client that stops reading (paused socket)
//     must show dropped frames in hg-foxglove's heartbeat.
// usage: live_check.js ws://HOST:PORT RESULT.json STOPFILE [--max-points N]
// Prints "ready" once the first channels are subscribed; writes RESULT.json when STOPFILE appears.
"use strict";
const fs = require("fs");
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");
const Ajv = require("ajv");
const foxgloveSchemas = require("@foxglove/schemas/jsonschema");
const { checkSmoothedEdge, outlineColors } = require("./scene_check");
const { viewerProblems } = require("./viewer_schema");

const [url, resultFile, stopFile] = process.argv.slice(2);
const maxPoints = process.argv.includes("--max-points") ? Number(process.argv[process.argv.indexOf("--max-points") + 1]) : 200000;
const result = { advertised: [], counts: {}, invalid: [], clouds_checked: 0, cloud_failures: [], heartbeat: "",
                 probes: {}, raw: 0, errors: [], paths_checked: 0, edge_points: 0, path_failures: [],
                 log_lines: [], log_unshown: [] };
const logShown = new Set();  // "process|utime|level|text" of each /hg/log line
const logKey = (name, utime, level, text) => `${name}|${utime}|${level}|${text}`;
const ajv = new Ajv({ strict: false });
const official = {};
for (const [name, s] of Object.entries(foxgloveSchemas)) official["foxglove." + name] = ajv.compile(s);

function probe(name, protocols, onOpen) {
  return new Promise((resolve) => {
    const ws = protocols ? new WebSocket(url, protocols) : new WebSocket(url);
    const r = { opened: false };
    ws.on("open", () => { r.opened = true; r.protocol = ws.protocol; onOpen && onOpen(ws); });
    ws.on("message", (d, isBinary) => { if (!isBinary && !r.first) r.first = JSON.parse(d.toString()).op; });
    ws.on("unexpected-response", (req, res) => { r.status = res.statusCode; resolve((result.probes[name] = r)); });
    ws.on("close", (code, reason) => { r.code = code; r.reason = reason.toString(); resolve((result.probes[name] = r)); });
    ws.on("error", (e) => { r.error = String(e.message); });
    setTimeout(() => { if (name === "sdk" && r.first) ws.close(); }, 1000);
    setTimeout(() => { r.timeout = true; ws.terminate(); resolve((result.probes[name] = r)); }, 8000);
  });
}

async function probes() {
  await probe("sdk", ["foxglove.sdk.v1"]);
  await probe("no_subprotocol", null);
  await probe("text_garbage", [FoxgloveClient.SUPPORTED_SUBPROTOCOL], (ws) => ws.send("hello, server"));
  await probe("binary", [FoxgloveClient.SUPPORTED_SUBPROTOCOL], (ws) => ws.send(Buffer.from([1, 2, 3, 4])));
  await probe("bad_subscribe", [FoxgloveClient.SUPPORTED_SUBPROTOCOL],
              (ws) => ws.send(JSON.stringify({ op: "subscribe", subscriptions: "all" })));
}

// A client that subscribes to everything and then stops reading.
function slowClient() {
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  let next = 1;
  ws.on("message", (d, isBinary) => {
    if (isBinary) return;
    const m = JSON.parse(d.toString());
    if (m.op !== "advertise") return;
    ws.send(JSON.stringify({ op: "subscribe", subscriptions: m.channels.map((c) => ({ id: next++, channelId: c.id })) }));
    setTimeout(() => ws.pause(), 200);
  });
  ws.on("error", () => {});
  return ws;
}

// u and v are float32: their JSON is the shortest text of the float, so Math.fround gives the float back.
function cloudExpectation(msg) {
  const n = msg.n, step = maxPoints === 0 || n <= maxPoints ? 1 : Math.ceil(n / maxPoints);
  const o = msg.plane_origin, ua = msg.plane_u_axis, va = msg.plane_v_axis;
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  let count = 0;
  for (let i = 0; i < n; i += step, ++count)
    for (let k = 0; k < 3; ++k) {
      const x = Math.fround(o[k] + Math.fround(msg.u[i]) * ua[k] + Math.fround(msg.v[i]) * va[k]);
      if (x < min[k]) min[k] = x;
      if (x > max[k]) max[k] = x;
    }
  return { count, min, max, frame: msg.header.frame_id };
}

function checkCloud(pc, want) {
  const raw = Buffer.from(pc.data, "base64");
  const off = Object.fromEntries(pc.fields.map((f) => [f.name, f.offset]));
  const count = raw.length / pc.point_stride;
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < count; ++i)
    ["x", "y", "z"].forEach((f, k) => {
      const x = raw.readFloatLE(i * pc.point_stride + off[f]);
      if (x < min[k]) min[k] = x;
      if (x > max[k]) max[k] = x;
    });
  const same = count === want.count && pc.frame_id === want.frame &&
               [0, 1, 2].every((k) => min[k] === want.min[k] && max[k] === want.max[k]);
  if (!same) result.cloud_failures.push({ got: { count, min, max, frame: pc.frame_id }, want });
  ++result.clouds_checked;
}

function main() {
  const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
  const bySub = new Map(), validators = new Map(), clouds = new Map(), paths = new Map(), outline = new Set();
  let ready = false;
  client.on("serverInfo", (info) => { result.serverInfo = info; });
  client.on("advertise", (channels) => {
    for (const ch of channels) {
      result.advertised.push({ topic: ch.topic, encoding: ch.encoding, schemaName: ch.schemaName });
      if (ch.encoding === "json") {
        const schema = JSON.parse(ch.schema);
        for (const p of viewerProblems(schema)) result.invalid.push(`${ch.topic}: schema unreadable by viewers: ${p}`);
        validators.set(ch.id, ajv.compile(schema));
      }
      bySub.set(client.subscribe(ch.id), ch);
    }
    if (!ready) { ready = true; console.log("ready"); }
  });
  client.on("message", ({ subscriptionId, data }) => {
    const ch = bySub.get(subscriptionId);
    result.counts[ch.topic] = (result.counts[ch.topic] || 0) + 1;
    if (ch.encoding !== "json") { ++result.raw; return; }
    let msg;
    try { msg = JSON.parse(new TextDecoder("utf-8", { fatal: true }).decode(data)); }
    catch (e) { result.invalid.push(`${ch.topic}: ${e.message}`); return; }
    const v = validators.get(ch.id);
    if (!v(msg)) result.invalid.push(`${ch.topic}: ${ajv.errorsText(v.errors)}`);
    if (official[ch.schemaName] && !official[ch.schemaName](msg))
      result.invalid.push(`${ch.topic}: not ${ch.schemaName}: ${ajv.errorsText(official[ch.schemaName].errors)}`);
    if (ch.schemaName === "hullgrind.plate_cloud_t") clouds.set(msg.header.utime, cloudExpectation(msg));
    if (ch.topic === "/hg/plate/points") {
      const key = msg.timestamp.sec * 1e6 + msg.timestamp.nsec / 1e3;
      if (clouds.has(key)) checkCloud(msg, clouds.get(key));
    }
    if (ch.schemaName === "hullgrind.grind_path_t") paths.set(msg.header.utime, msg);
    if (ch.topic === "/hg/outline") for (const c of outlineColors(msg)) outline.add(c);
    if (ch.topic === "/hg/grind_path") {
      const path = paths.get(msg.entities[0].timestamp.sec * 1e6 + msg.entities[0].timestamp.nsec / 1e3);
      if (path) {
        result.path_failures.push(...checkSmoothedEdge(msg, path, [...outline]));
        result.edge_points += path.num_edge_points;
        ++result.paths_checked;
      }
    }
    if (ch.schemaName === "hullgrind.heartbeat_t" && msg.process === "hg-foxglove") result.heartbeat = msg.state_text;
    if (ch.schemaName === "hullgrind.log_line_t")
      result.log_lines.push({ process: msg.process, pid: msg.pid, level: msg.level, text: msg.text, utime: msg.header.utime });
    if (ch.topic === "/hg/log")
      logShown.add(logKey(msg.name, msg.timestamp.sec * 1e6 + msg.timestamp.nsec / 1e3, msg.level, msg.message));
  });
  client.on("error", (e) => result.errors.push(String(e && e.message)));
  return client;
}

(async () => {
  const client = main();
  const slow = slowClient();
  await probes();
  const timer = setInterval(() => {
    if (!fs.existsSync(stopFile)) return;
    clearInterval(timer);
    for (const l of result.log_lines)
      if (!logShown.has(logKey(l.process, l.utime, l.level + 1, l.text))) result.log_unshown.push(l);
    fs.writeFileSync(resultFile, JSON.stringify(result, null, 1));
    client.close();
    slow.terminate();
    process.exit(0);
  }, 200);
})();
