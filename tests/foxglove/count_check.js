#!/usr/bin/env node
// A viewer for foxglove_raw_period_test, with a client nobody here wrote (@foxglove/ws-protocol's
// FoxgloveClient on ws): subscribes to every channel hg-foxglove advertises, decodes every JSON message it
// receives (strict UTF-8) and after SECONDS prints how many of each topic came, as one JSON line.
// usage: count_check.js ws://HOST:PORT SECONDS
"use strict";
const WebSocket = require("ws");
const { FoxgloveClient } = require("@foxglove/ws-protocol");

const [url, seconds] = process.argv.slice(2);
const counts = {};
const client = new FoxgloveClient({ ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]) });
const bySub = new Map();
client.on("advertise", (channels) => {
  for (const ch of channels) bySub.set(client.subscribe(ch.id), ch);
});
client.on("message", ({ subscriptionId, data }) => {
  const ch = bySub.get(subscriptionId);
  if (!ch) return;
  if (ch.encoding === "json") JSON.parse(new TextDecoder("utf-8", { fatal: true }).decode(data));
  counts[ch.topic] = (counts[ch.topic] || 0) + 1;
});
client.on("error", () => {});
setTimeout(() => {
  console.log(JSON.stringify(counts));
  process.exit(0);
}, Number(seconds) * 1000);
