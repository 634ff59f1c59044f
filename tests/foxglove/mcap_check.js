#!/usr/bin/env node
// Reads an MCAP file written by hg-mcap with readers nobody here wrote and checks it against the LCM
// log(s) it came from:
//   - @mcap/core's McapStreamReader (every record, chunk CRCs validated) and McapIndexedReader (summary,
//     summary CRC, chunk and message indexes), with @foxglove/wasm-zstd / wasm-lz4 for the chunks;
//   - the data section's CRC recomputed with @foxglove/crc;
//   - per LCM channel exactly the events of the log(s), in order, with the events' times as log times;
//     a raw (encoding lcm) channel carries the event's bytes unchanged;
//   - every JSON message validates (ajv) against its channel's schema, and the foxglove.* ones also
//     against Foxglove's own schemas (@foxglove/schemas); every schema is one Foxglove's and Lichtblick's
//     viewers can read (viewer_schema.js);
//   - the derived topics: one /hg/plate/points per plate cloud, whose packed points match the cloud (count
//     with hg-mcap's decimation, bounding box), one /hg/outline, /hg/grind_path, /hg/log per message;
//     each /hg/grind_path shows its path's smoothed edge (scene_check.js); a /hg/log line of a process's
//     log line (HG_LOG) has its process, level, time and text.
// usage: mcap_check.js FILE.mcap LOG.lcmlog [LOG.lcmlog...] [--max-points N] [--expect-tf] [--base-frame NAME]
//                      [--skip CHANNEL#EVENT]...
// (--skip: an event hg-mcap reported as not decoding, left out of the expectation; one log only)
// Exit 0 when every check passes, 1 with the reasons otherwise.
"use strict";
const fs = require("fs");
const { McapStreamReader, McapIndexedReader } = require("@mcap/core");
const zstd = require("@foxglove/wasm-zstd");
const lz4 = require("@foxglove/wasm-lz4");
const { crc32 } = require("@foxglove/crc");
const Ajv = require("ajv");
const foxgloveSchemas = require("@foxglove/schemas/jsonschema");
const { checkSmoothedEdge, outlineColors } = require("./scene_check");
const { viewerProblems } = require("./viewer_schema");

const failures = [];
function check(cond, what) {
  if (!cond) failures.push(what);
  return cond;
}

// The LCM log format (lcm-logger): big-endian sync word, event number, utime, channel length, data length.
function readLcmLog(path) {
  const b = fs.readFileSync(path);
  const events = [];
  let pos = 0;
  while (pos + 28 <= b.length) {
    if (b.readUInt32BE(pos) !== 0xeda1da01) throw new Error(`${path}: no sync word at byte ${pos}`);
    const utime = b.readBigInt64BE(pos + 12);
    const clen = b.readInt32BE(pos + 20), dlen = b.readInt32BE(pos + 24);
    const channel = b.toString("latin1", pos + 28, pos + 28 + clen);
    const data = b.subarray(pos + 28 + clen, pos + 28 + clen + dlen);
    events.push({ channel, utime, data, number: b.readBigInt64BE(pos + 4) });
    pos += 28 + clen + dlen;
  }
  if (pos !== b.length) throw new Error(`${path}: ${b.length - pos} bytes left after the last event`);
  return events;
}

const decompressHandlers = {
  zstd: (buf, size) => zstd.decompress(buf, Number(size)),
  lz4: (buf, size) => lz4(buf, Number(size)),
};

function streamRecords(bytes) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  const records = [];
  for (let r; (r = reader.nextRecord()); ) records.push(r);
  check(reader.done(), "stream reader: not at the end of the file after the last record");
  return records;
}

async function indexed(bytes) {
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
  return McapIndexedReader.Initialize({ readable, decompressHandlers });
}

// The plate's points back from a hullgrind.plate_cloud_t JSON message, as hg-mcap decimates them.
// u and v are float32: their JSON is the shortest text of the float, so Math.fround gives the float back.
function cloudExpectation(msg, maxPoints) {
  const n = msg.n;
  const step = maxPoints === 0 || n <= maxPoints ? 1 : Math.ceil(n / maxPoints);
  const o = msg.plane_origin, ua = msg.plane_u_axis, va = msg.plane_v_axis;
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  let count = 0;
  for (let i = 0; i < n; i += step) {
    for (let k = 0; k < 3; ++k) {
      const x = Math.fround(o[k] + Math.fround(msg.u[i]) * ua[k] + Math.fround(msg.v[i]) * va[k]);
      min[k] = Math.min(min[k], x);
      max[k] = Math.max(max[k], x);
    }
    ++count;
  }
  return { count, min, max };
}

function cloudActual(pc) {
  const raw = Buffer.from(pc.data, "base64");
  const stride = pc.point_stride;
  const off = {};
  for (const f of pc.fields) if (check(f.type === 7, `PointCloud field ${f.name} is not FLOAT32`)) off[f.name] = f.offset;
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  const count = raw.length / stride;
  for (let i = 0; i < count; ++i)
    ["x", "y", "z"].forEach((name, k) => {
      const x = raw.readFloatLE(i * stride + off[name]);
      min[k] = Math.min(min[k], x);
      max[k] = Math.max(max[k], x);
    });
  return { count, min, max };
}

const seenOutlineColors = new Set();
let pathsChecked = 0, logLinesChecked = 0;

// A /hg/log line made of a process's log line (log_line_t) says what that line says; foxglove.Log's levels
// are log_line_t's plus one (DEBUG 1 .. ERROR 4), a level outside LEVEL_* as the nearest one.
function checkLogLine(json, line) {
  const t = line.header.utime;
  const level = Math.min(Math.max(line.level, 0), 3) + 1;
  check(json.name === line.process && json.message === line.text && json.level === level &&
        json.timestamp.sec === Math.floor(t / 1e6) && json.timestamp.nsec === (t % 1e6) * 1000,
        `/hg/log: ${JSON.stringify(json)} is not the log line ${JSON.stringify(line)}`);
  ++logLinesChecked;
}

function checkDerived(topic, json, lastCloud, maxPoints, lastPath, lastLogSource) {
  if (topic === "/hg/log" && check(lastLogSource, "/hg/log before any HG_JOB_STATUS or HG_LOG") &&
      lastLogSource.type === "hullgrind.log_line_t")
    checkLogLine(json, lastLogSource.json);
  if (topic === "/hg/outline") for (const c of outlineColors(json)) seenOutlineColors.add(c);
  if (topic === "/hg/grind_path" && check(lastPath, "/hg/grind_path before any HG_GRIND_PATH")) {
    for (const f of checkSmoothedEdge(json, lastPath, [...seenOutlineColors])) check(false, `/hg/grind_path: ${f}`);
    ++pathsChecked;
  }
  if (topic === "/hg/plate/points" && check(lastCloud, "PointCloud before any HG_PLATE_CLOUD")) {
    const want = cloudExpectation(lastCloud, maxPoints), got = cloudActual(json);
    check(got.count === want.count, `PointCloud has ${got.count} points, the plate cloud gives ${want.count}`);
    for (let k = 0; k < 3; ++k)
      check(got.min[k] === want.min[k] && got.max[k] === want.max[k],
            `PointCloud bounding box axis ${k}: [${got.min[k]}, ${got.max[k]}] vs [${want.min[k]}, ${want.max[k]}]`);
    check(json.frame_id === lastCloud.header.frame_id, "PointCloud frame is not the cloud's");
  }
}

async function main() {
  const args = process.argv.slice(2);
  let maxPoints = 200000, expectTf = false, baseFrame = "robot_base";
  const skip = new Set();  // "CHANNEL#N": events hg-mcap reported as not decoding (--skip, its "skipped events")
  const logs = [];
  let file;
  for (let i = 0; i < args.length; ++i) {
    if (args[i] === "--max-points") maxPoints = Number(args[++i]);
    else if (args[i] === "--expect-tf") expectTf = true;
    else if (args[i] === "--base-frame") baseFrame = args[++i];  // the cell's frames.base
    else if (args[i] === "--skip") skip.add(args[++i]);
    else if (!file) file = args[i];
    else logs.push(args[i]);
  }
  if (!file || logs.length === 0) {
    console.error("usage: mcap_check.js FILE.mcap LOG.lcmlog [LOG.lcmlog...] [--max-points N] [--expect-tf]");
    process.exit(2);
  }
  await zstd.isLoaded;
  await lz4.isLoaded;
  const bytes = new Uint8Array(fs.readFileSync(file));
  const events = logs.flatMap(readLcmLog).filter((e) => !skip.has(`${e.channel}#${e.number}`));

  const records = streamRecords(bytes);
  const reader = await indexed(bytes);  // checks the summary CRC
  check(reader.dataSectionCrc === undefined || reader.dataSectionCrc !== 0, "data section CRC is 0 (not written)");
  check(crc32(bytes.subarray(0, Number(reader.dataEndOffset))) === reader.dataSectionCrc,
        "data section CRC does not match the bytes before Data End");

  const schemas = new Map(), channels = new Map();
  for (const r of records) {
    if (r.type === "Schema") schemas.set(r.id, r);
    if (r.type === "Channel") channels.set(r.id, r);
  }
  check(reader.channelsById.size === channels.size, "summary and data section list different channels");
  check(reader.chunkIndexes.length > 0, "no chunk index");
  const messages = records.filter((r) => r.type === "Message");
  check(reader.statistics && reader.statistics.messageCount === BigInt(messages.length),
        `statistics count ${reader.statistics && reader.statistics.messageCount} messages, the file has ${messages.length}`);
  let viaIndex = 0;
  for await (const m of reader.readMessages({ validateCrcs: true })) ++viaIndex;
  check(viaIndex === messages.length, `indexed reader reads ${viaIndex} messages, the stream ${messages.length}`);
  for (const [id, n] of reader.statistics.channelMessageCounts)
    check(BigInt(messages.filter((m) => m.channelId === id).length) === n, `statistics of channel ${id} are wrong`);

  const ajv = new Ajv({ strict: false, allErrors: false });
  const validators = new Map();
  const official = {};
  for (const [name, s] of Object.entries(foxgloveSchemas)) official["foxglove." + name] = ajv.compile(s);

  const lcmTopics = new Set(events.map((e) => e.channel));
  const perTopic = new Map();
  let ev = 0, lastCloud = null, lastPath = null, lastLogSource = null, validated = 0, lastType = null, cameraTfs = 0,
      lastStatus = null;
  for (const m of messages) {
    const ch = channels.get(m.channelId);
    perTopic.set(ch.topic, (perTopic.get(ch.topic) || 0) + 1);
    if (lcmTopics.has(ch.topic)) {
      // The LCM channels' messages are the log's events, in order.
      while (ev < events.length && events[ev].channel !== ch.topic) ++ev;  // skipped only if it is derived-free
      if (!check(ev < events.length, `message on ${ch.topic} matches no event of the log`)) break;
      check(m.logTime === events[ev].utime * 1000n, `${ch.topic}: log time ${m.logTime} is not the event's time`);
      if (ch.messageEncoding === "lcm") {
        check(Buffer.compare(Buffer.from(m.data), events[ev].data) === 0, `${ch.topic}: raw message is not the event's bytes`);
        ++ev;
        continue;
      }
      ++ev;
    }
    if (!check(ch.messageEncoding === "json", `${ch.topic}: encoding ${ch.messageEncoding}`)) continue;
    const schema = schemas.get(ch.schemaId);
    if (!check(schema && schema.encoding === "jsonschema", `${ch.topic}: no JSON Schema`)) continue;
    if (!validators.has(schema.id)) {
      const parsed = JSON.parse(Buffer.from(schema.data).toString());
      for (const p of viewerProblems(parsed)) check(false, `${ch.topic}: schema ${schema.name} unreadable by viewers: ${p}`);
      validators.set(schema.id, ajv.compile(parsed));
    }
    const json = JSON.parse(Buffer.from(m.data).toString("utf8"));
    const validate = validators.get(schema.id);
    check(validate(json), `${ch.topic}: message does not validate: ${ajv.errorsText(validate.errors)}`);
    if (official[schema.name])
      check(official[schema.name](json), `${ch.topic}: not a valid ${schema.name} by @foxglove/schemas: ${ajv.errorsText(official[schema.name].errors)}`);
    ++validated;
    if (lcmTopics.has(ch.topic)) lastType = schema.name;
    // base <- camera comes with each plate cloud, its parent the cell's frames.base (hg-mcap --cell).
    // The robot's TCP alone on /tf: the camera on a topic of its own, so that the last message of each topic
    // before any time places both (what a viewer shows when it opens the file there).
    if (ch.topic === "/tf") {
      const parent = (lastStatus && lastStatus.header.frame_id) || baseFrame;  // the status's frame, else the base
      check(json.parent_frame_id === parent && json.child_frame_id === "tcp",
            `/tf: ${json.parent_frame_id} <- ${json.child_frame_id}, expected ${parent} <- tcp`);
    }
    if (ch.topic === "/tf/camera" && lastType === "hullgrind.plate_cloud_t") {
      check(json.parent_frame_id === baseFrame && json.child_frame_id === lastCloud.header.frame_id,
            `/tf/camera of a plate cloud: ${json.parent_frame_id} <- ${json.child_frame_id}, expected ${baseFrame} <- ` +
            lastCloud.header.frame_id);
      ++cameraTfs;
    }
    if (schema.name === "hullgrind.plate_cloud_t") lastCloud = json;
    if (schema.name === "hullgrind.grind_path_t") lastPath = json;
    if (schema.name === "hullgrind.robot_status_t") lastStatus = json;
    if (schema.name === "hullgrind.job_status_t" || schema.name === "hullgrind.log_line_t")
      lastLogSource = { type: schema.name, json };
    checkDerived(ch.topic, json, lastCloud, maxPoints, lastPath, lastLogSource);
  }

  // Counts: every LCM channel exactly as in the log; the derived topics one per source message.
  const want = new Map();
  for (const e of events) want.set(e.channel, (want.get(e.channel) || 0) + 1);
  for (const [topic, n] of want) check(perTopic.get(topic) === n, `${topic}: ${perTopic.get(topic) || 0} messages, the log has ${n}`);
  const typeCount = (name) => messages.filter((m) => {
    const ch = channels.get(m.channelId);
    return lcmTopics.has(ch.topic) && schemas.get(ch.schemaId) && schemas.get(ch.schemaId).name === name;
  }).length;
  const derived = { "/hg/plate/points": ["hullgrind.plate_cloud_t"], "/hg/outline": ["hullgrind.outline_t"],
                    "/hg/grind_path": ["hullgrind.grind_path_t"],
                    "/hg/log": ["hullgrind.job_status_t", "hullgrind.log_line_t"] };
  for (const [topic, types] of Object.entries(derived)) {
    const n = types.reduce((sum, type) => sum + typeCount(type), 0);
    check((perTopic.get(topic) || 0) === n, `${topic}: ${perTopic.get(topic) || 0} messages, ${n} ${types.join(" + ")}`);
  }
  const tfWant = typeCount("hullgrind.robot_status_t");
  check((perTopic.get("/tf") || 0) === tfWant, `/tf: ${perTopic.get("/tf") || 0} transforms, expected ${tfWant}`);
  check((perTopic.get("/tf/camera") || 0) === cameraTfs, `/tf/camera: messages that are no plate cloud's camera`);
  check(cameraTfs === (expectTf ? typeCount("hullgrind.plate_cloud_t") : 0), `/tf/camera: ${cameraTfs} camera transforms`);
  for (const t of perTopic.keys()) check(lcmTopics.has(t) || t in derived || t === "/tf" || t === "/tf/camera", `unexpected topic ${t}`);

  const summary = [...perTopic].map(([t, n]) => `${t} ${n}`).join(", ");
  if (failures.length) {
    console.error(`mcap_check: ${file}: ${failures.length} failures:\n  ` + failures.slice(0, 20).join("\n  "));
    process.exit(1);
  }
  console.log(`mcap_check: ${file}: ok: ${messages.length} messages (${validated} JSON validated), ` +
              `${reader.chunkIndexes.length} chunks, ${pathsChecked} smoothed edges checked, ` +
              `${logLinesChecked} log lines checked; ${summary}`);
}

main().catch((e) => {
  console.error(`mcap_check: ${e.stack || e}`);
  process.exit(1);
});
