#!/usr/bin/env node
// A Foxglove viewer for the benchmarks: @foxglove/ws-protocol's client subscribed to every channel hg-foxglove
// advertises, reading everything (as Foxglove's 3-D panel does with /hg/plate/points). On SIGTERM prints
// one JSON line: messages and bytes received per topic. $HG_VIEWER_EXCLUDE (a regular expression): topics
// not subscribed to.
//   NODE_PATH=build/npm/node_modules tools/bench/foxglove_client.js [ws://127.0.0.1:8765]
"use strict";
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");

const url = process.argv[2] || "ws://127.0.0.1:8765";
const exclude = process.env.HG_VIEWER_EXCLUDE ? new RegExp(process.env.HG_VIEWER_EXCLUDE) : null;
const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const topics = new Map(), counts = {};
client.on("advertise", (channels) => {
  for (const ch of channels) if (!(exclude && exclude.test(ch.topic))) topics.set(client.subscribe(ch.id), ch.topic);
});
client.on("message", ({ subscriptionId, data }) => {
  const t = topics.get(subscriptionId) || "?";
  const c = counts[t] || (counts[t] = { messages: 0, bytes: 0 });
  ++c.messages;
  c.bytes += data.byteLength;
});
client.on("error", () => {});
process.on("SIGTERM", () => {
  console.log(JSON.stringify(counts));
  process.exit(0);
});
