#!/usr/bin/env node
// A viewer for foxglove_priority_test, with a client nobody here wrote (@foxglove/ws-protocol's
// FoxgloveClient on ws): subscribes to every channel hg-foxglove advertises, prints "ready" once TOPIC is
// subscribed, decodes every message of TOPIC as JSON (strict UTF-8) and ends when it has the messages whose
// job_id are the JOB_IDs, printing them as one JSON line (exit 0); exit 1 after SECONDS without them. It
// prints "ready" when the first of them has come: then it is subscribed, and the test sends the others.
// usage: priority_check.js ws://HOST:PORT TOPIC SECONDS JOB_ID...
"use strict";
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");

const [url, topic, seconds, ...wanted] = process.argv.slice(2);
const got = {};
const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const bySub = new Map();
client.on("advertise", (channels) => {
  for (const ch of channels) {
    bySub.set(client.subscribe(ch.id), ch);
  }
});
client.on("message", ({ subscriptionId, data }) => {
  const ch = bySub.get(subscriptionId);
  if (!ch || ch.topic !== topic) return;
  const msg = JSON.parse(new TextDecoder("utf-8", { fatal: true }).decode(data));
  if (msg.job_id === wanted[0] && !(msg.job_id in got)) console.log("ready");
  got[msg.job_id] = msg;
  if (wanted.every((id) => id in got)) {
    console.log(JSON.stringify(wanted.map((id) => got[id])));
    process.exit(0);
  }
});
client.on("error", () => {});
setTimeout(() => {
  console.log(JSON.stringify({ timeout: true, got: Object.keys(got) }));
  process.exit(1);
}, Number(seconds) * 1000);
