#!/usr/bin/env node
// ROS 1 bag -> ROS 2 recording, written apart from starnav (its own readers are what the result
// tests): the ROS 1 bag is read with @foxglove/rosbag (chunks in file order, records in file order
// within each chunk) and @foxglove/rosmsg-serialization, each message turned into its ROS 2 form
// (header.seq dropped, Time's nsec renamed nanosec, types named pkg/msg/Type) and serialised as CDR by
// @foxglove/rosmsg2-serialization with ROS 2 Jazzy's definitions (@foxglove/rosmsg-msgs-common),
// then stored by @mcap/core (MCAP) or better-sqlite3 (rosbag2's SQLite3 tables).
//
// usage: node convert.mjs IN.bag OUT --storage mcap|sqlite3 [--compression zstd|lz4|none]
//          [--max-messages N] [--drop-topic T ...] [--no-summary] [--split-messages N]
//   OUT ending in .mcap or .db3 is one file; otherwise a rosbag2 folder (metadata.yaml and the
//   files OUT/NAME_i.mcap|db3, a new file every --split-messages messages).
//   --max-messages keeps the first N messages in file order (a prefix of the log, for quick tests).
//   --no-summary writes an MCAP without summary, indexes or statistics (readers must scan it).
import fs from "node:fs";
import path from "node:path";
import { Bag } from "@foxglove/rosbag";
import BagReader from "@foxglove/rosbag/dist/cjs/BagReader.js";
import { MessageData } from "@foxglove/rosbag/dist/cjs/record.js";
import { parse as parseMessageDefinition, stringify } from "@foxglove/rosmsg";
import { MessageReader as Ros1Reader } from "@foxglove/rosmsg-serialization";
import { MessageWriter as Ros2Writer } from "@foxglove/rosmsg2-serialization";
import { ros2jazzy } from "@foxglove/rosmsg-msgs-common";
import { McapWriter } from "@mcap/core";
import Bzip2 from "@foxglove/wasm-bz2";
import lz4Decompress from "@foxglove/wasm-lz4";
import * as zstd from "@foxglove/wasm-zstd";
import lz4js from "lz4js";
import Database from "better-sqlite3";

function usage(message) {
  console.error(`convert.mjs: ${message}`);
  process.exit(2);
}

const args = process.argv.slice(2);
const positional = [];
const options = { storage: null, compression: "zstd", maxMessages: Infinity, drop: [], summary: true, split: Infinity };
for (let i = 0; i < args.length; i++) {
  const a = args[i];
  const value = () => {
    if (i + 1 >= args.length) usage(`${a} needs a value`);
    return args[++i];
  };
  if (a === "--storage") options.storage = value();
  else if (a === "--compression") options.compression = value();
  else if (a === "--max-messages") options.maxMessages = Number(value());
  else if (a === "--drop-topic") options.drop.push(value());
  else if (a === "--no-summary") options.summary = false;
  else if (a === "--split-messages") options.split = Number(value());
  else if (a.startsWith("--")) usage(`unknown option ${a}`);
  else positional.push(a);
}
if (positional.length !== 2) usage("expected IN.bag OUT");
const [input, output] = positional;
if (options.storage !== "mcap" && options.storage !== "sqlite3") usage("--storage mcap or sqlite3");
if (!["zstd", "lz4", "none"].includes(options.compression)) usage("--compression zstd, lz4 or none");

const [bzip2] = await Promise.all([Bzip2.init(), lz4Decompress.isLoaded, zstd.isLoaded]);

// ---- The ROS 1 bag, in file order ----------------------------------------------------------------
const fd = fs.openSync(input, "r");
const filelike = {
  size: () => fs.fstatSync(fd).size,
  read: async (offset, length) => {
    const b = Buffer.alloc(length);
    fs.readSync(fd, b, 0, length, offset);
    return b;
  },
};
const decompress = {
  bz2: (buffer, size) => bzip2.decompress(buffer, size, { small: false }),
  lz4: (buffer, size) => lz4Decompress(buffer, size),
};
const bag = new Bag(filelike, { decompress, parse: false });
await bag.open();
const reader = new BagReader.default(filelike);

// ROS 1 type -> ROS 2 type and the ROS 2 definitions (Jazzy) of it and what it contains.
function ros2Name(type) {
  const [pkg, name] = type.split("/");
  return `${pkg}/msg/${name}`;
}
function definitionsOf(ros1Type) {
  const out = [];
  const seen = new Set();
  const visit = (t, root) => {
    if (seen.has(t)) return;
    seen.add(t);
    const def = ros2jazzy[t];
    if (!def) throw new Error(`no ROS 2 definition of ${t}`);
    out.push(root ? { ...def, name: undefined } : def);
    for (const f of def.definitions) if (f.isComplex) visit(f.type, false);
  };
  visit(ros1Type, true);
  return out;
}
// A ROS 1 message as its ROS 2 form: Time {sec, nsec} -> {sec, nanosec}; headers lose seq.
function toRos2(value) {
  if (Array.isArray(value) || ArrayBuffer.isView(value)) return Array.isArray(value) ? value.map(toRos2) : value;
  if (value === null || typeof value !== "object") return value;
  const keys = Object.keys(value);
  if (keys.length === 2 && "sec" in value && "nsec" in value) return { sec: value.sec, nanosec: value.nsec };
  const out = {};
  for (const k of keys) {
    if (k === "seq" && "stamp" in value && "frame_id" in value) continue;
    out[k] = toRos2(value[k]);
  }
  return out;
}

const topics = new Map();  // ROS 1 connection id -> {topic, type, reader, writer, schema}
for (const [id, c] of bag.connections) {
  if (options.drop.includes(c.topic)) continue;
  const ros1 = new Ros1Reader(parseMessageDefinition(c.messageDefinition));
  const defs = definitionsOf(c.type);
  topics.set(id, {
    topic: c.topic,
    type: ros2Name(c.type),
    ros1,
    ros2: new Ros2Writer(defs),
    schema: stringify(defs),
  });
}

// Every message in file order: chunks by file offset, records by offset within their chunk.
async function* messages() {
  const chunks = [...bag.chunkInfos].sort((a, b) => a.chunkPosition - b.chunkPosition);
  for (const info of chunks) {
    const { chunk, indices } = await reader.readChunk(info, decompress);
    const offsets = [];
    for (const index of indices) for (const e of index.indices) offsets.push(e.offset);
    offsets.sort((a, b) => a - b);
    for (const offset of offsets) yield reader.readRecordFromBuffer(chunk.data.subarray(offset), chunk.dataOffset ?? 0, MessageData);
  }
}

const converted = [];
let count = 0;
for await (const m of messages()) {
  if (count >= options.maxMessages) break;
  count++;
  const t = topics.get(m.conn);
  if (!t) continue;
  const message = toRos2(t.ros1.readMessage(m.data));
  const time = BigInt(m.time.sec) * 1000000000n + BigInt(m.time.nsec);
  converted.push({ t, time, data: t.ros2.writeMessage(message) });
}

// ---- The ROS 2 recording -----------------------------------------------------------------------
const single = /\.(mcap|db3)$/.test(output);
const folder = single ? path.dirname(output) : output;
const stem = single ? path.basename(output).replace(/\.(mcap|db3)$/, "") : path.basename(output);
fs.mkdirSync(folder, { recursive: true });
const parts = [];
for (let i = 0; i < converted.length || parts.length === 0; i += Math.min(options.split, converted.length || 1)) {
  parts.push(converted.slice(i, i + options.split));
  if (converted.length === 0) break;
}

const compressChunk =
  options.compression === "zstd"
    ? (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) })
    : options.compression === "lz4"
      ? (data) => ({ compression: "lz4", compressedData: lz4js.compress(data) })
      : undefined;

async function writeMcap(file, list) {
  const out = fs.openSync(file, "w");
  let position = 0n;
  const writable = {
    position: () => position,
    write: async (buffer) => {
      fs.writeSync(out, buffer);
      position += BigInt(buffer.byteLength);
    },
  };
  const writer = new McapWriter({
    writable,
    compressChunk,
    chunkSize: 1024 * 1024,
    useStatistics: options.summary,
    useSummaryOffsets: options.summary,
    useChunkIndex: options.summary,
    useMessageIndex: options.summary,
    repeatSchemas: options.summary,
    repeatChannels: options.summary,
    useAttachmentIndex: options.summary,
    useMetadataIndex: options.summary,
  });
  await writer.start({ profile: "ros2", library: "starnav tools/ros2-convert (@mcap/core)" });
  const channels = new Map();
  for (const t of topics.values()) {
    if (channels.has(t.topic)) continue;
    const schemaId = await writer.registerSchema({ name: t.type, encoding: "ros2msg", data: new TextEncoder().encode(t.schema) });
    channels.set(t.topic, await writer.registerChannel({ schemaId, topic: t.topic, messageEncoding: "cdr", metadata: new Map() }));
  }
  const sequences = new Map();
  for (const m of list) {
    const channelId = channels.get(m.t.topic);
    const sequence = (sequences.get(channelId) ?? 0) + 1;
    sequences.set(channelId, sequence);
    await writer.addMessage({ channelId, sequence, logTime: m.time, publishTime: m.time, data: m.data });
  }
  await writer.end();
  fs.closeSync(out);
}

function writeSqlite(file, list) {
  fs.rmSync(file, { force: true });
  const db = new Database(file);
  db.exec(`CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
           INSERT INTO schema VALUES (4, 'jazzy');
           CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
             serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL, type_description_hash TEXT NOT NULL);
           CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL);
           CREATE INDEX timestamp_idx ON messages (timestamp ASC);`);
  const ids = new Map();
  const addTopic = db.prepare("INSERT INTO topics (name, type, serialization_format, offered_qos_profiles, type_description_hash) VALUES (?, ?, 'cdr', '', '')");
  for (const t of topics.values()) if (!ids.has(t.topic)) ids.set(t.topic, addTopic.run(t.topic, t.type).lastInsertRowid);
  const addMessage = db.prepare("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)");
  db.transaction(() => {
    for (const m of list) addMessage.run(ids.get(m.t.topic), m.time, Buffer.from(m.data.buffer, m.data.byteOffset, m.data.byteLength));
  })();
  db.close();
}

const extension = options.storage === "mcap" ? "mcap" : "db3";
const files = [];
for (let i = 0; i < parts.length; i++) {
  const name = single ? path.basename(output) : `${stem}_${i}.${extension}`;
  const file = path.join(folder, name);
  if (options.storage === "mcap") await writeMcap(file, parts[i]);
  else writeSqlite(file, parts[i]);
  files.push({ name, list: parts[i] });
}

if (!single) {
  // rosbag2's metadata.yaml (version 5 layout), the counts of what was written.
  const perTopic = new Map();
  for (const m of converted) perTopic.set(m.t.topic, (perTopic.get(m.t.topic) ?? 0) + 1);
  const lines = ["rosbag2_bagfile_information:", "  version: 5", `  storage_identifier: ${options.storage}`, "  relative_file_paths:"];
  for (const f of files) lines.push(`    - ${f.name}`);
  lines.push(`  message_count: ${converted.length}`, "  topics_with_message_count:");
  const seen = new Set();
  for (const t of topics.values()) {
    if (seen.has(t.topic)) continue;
    seen.add(t.topic);
    lines.push("    - topic_metadata:", `        name: ${t.topic}`, `        type: ${t.type}`, "        serialization_format: cdr",
               '        offered_qos_profiles: ""', `      message_count: ${perTopic.get(t.topic) ?? 0}`);
  }
  lines.push('  compression_format: ""', '  compression_mode: ""');
  fs.writeFileSync(path.join(folder, "metadata.yaml"), lines.join("\n") + "\n");
}
console.log(`converted ${converted.length} messages of ${input} into ${output} (${options.storage}, ${options.compression}${options.summary ? "" : ", no summary"})`);
