#!/usr/bin/env node
// Client publishing on hg-foxglove --client-publish, with a client nobody here wrote (@foxglove/ws-protocol's
// FoxgloveClient on ws; credentials as HTTP Basic in the URL, as ws sends them):
//   - anonymous: serverInfo offers clientPublish, but advertising HG_JOB_REQUEST is answered with an error
//     status, and publishing on that channel anyway closes the connection (1008, a reason);
//   - a wrong password: the upgrade is refused with HTTP 401;
//   - a viewer: advertising is answered with an error status; publishing closes the connection;
//   - an operator: HG_ROBOT_MOVE is refused, bad JSON and an unknown field are answered with an error
//     status (the connection stays), then HG_JOB_REQUEST {job_id, action QUERY, actor "someone else"} is
//     published; the test checks on LCM what arrived.
// usage: publish_check.js HOST:PORT OPERATOR:PASSWORD VIEWER:PASSWORD JOB_ID RESULT.json
"use strict";
const fs = require("fs");
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");

const [hostPort, operator, viewer, jobId, resultFile] = process.argv.slice(2);
const result = {};
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const enc = (o) => new TextEncoder().encode(typeof o === "string" ? o : JSON.stringify(o));

// Connects (credentials "user:password" or null) and records serverInfo, statuses and how it closed.
function connect(credentials) {
  const url = `ws://${credentials ? credentials + "@" : ""}${hostPort}`;
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const r = { statuses: [], closed: null, status: null };
  ws.on("unexpected-response", (req, res) => { r.status = res.statusCode; r.closed = { code: -1 }; });
  ws.on("close", (code, reason) => { r.closed = { code, reason: reason.toString() }; });
  ws.on("error", () => {});
  const client = new FoxgloveClient({ ws });
  client.on("serverInfo", (info) => { r.capabilities = info.capabilities; r.encodings = info.supportedEncodings; });
  client.on("status", (s) => r.statuses.push(s));
  client.on("error", () => {});
  return { client, r, opened: new Promise((res) => { ws.on("open", res); ws.on("unexpected-response", res); }) };
}

const request = { job_id: jobId, action: 6, actor: "someone else" };
const channel = { topic: "HG_JOB_REQUEST", encoding: "json", schemaName: "hullgrind.job_request_t" };

async function refused(name, credentials) {
  const c = connect(credentials);
  await c.opened;
  await sleep(500);
  if (c.r.status === null) {
    const id = c.client.advertise(channel);
    await sleep(500);
    c.client.sendMessage(id, enc(request));
    await sleep(1000);
  }
  result[name] = c.r;
}

(async () => {
  await refused("anonymous", null);
  await refused("wrong_password", operator.split(":")[0] + ":not-the-password");
  await refused("viewer", viewer);
  const op = connect(operator);
  await op.opened;
  await sleep(500);
  const move = op.client.advertise({ topic: "HG_ROBOT_MOVE", encoding: "json", schemaName: "hullgrind.robot_move_t" });
  const id = op.client.advertise(channel);
  await sleep(500);
  op.client.sendMessage(id, enc("not json"));
  op.client.sendMessage(id, enc({ job_id: jobId, no_such_field: 1 }));
  await sleep(500);
  op.client.sendMessage(id, enc(request));
  await sleep(1500);
  result.operator = op.r;
  result.operator.robot_move_channel = move;
  op.client.close();
  fs.writeFileSync(resultFile, JSON.stringify(result, null, 1));
  process.exit(0);
})();
