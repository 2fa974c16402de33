#!/usr/bin/env node
// Reads an MCAP file that `starnav export mcap` wrote with @mcap/core (the indexed reader, which
// follows the summary and message indexes, and the stream reader, record by record) and decodes every
// message against its schema, independently of starnav:
//  - jsonschema channels: the schema must be Foxglove's own (@foxglove/schemas) for its name, and
//    every message must parse as JSON and validate against it (ajv);
//  - ros2msg channels: the schema must be ROS 2 Jazzy's definition (@foxglove/rosmsg-msgs-common)
//    of its type, and every message must decode with @foxglove/rosmsg2-serialization and re-encode
//    to the same bytes.
// Prints {"topics": {topic: {schema, encoding, messages}}, "messages": N} and exits 0, or names the
// first failure on stderr and exits 1.
//
// usage: node check-mcap.mjs FILE.mcap
import fs from "node:fs";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import * as zstd from "@foxglove/wasm-zstd";
import lz4Decompress from "@foxglove/wasm-lz4";
import * as jsonschema from "@foxglove/schemas/jsonschema.js";
import { parse as parseMessageDefinition } from "@foxglove/rosmsg";
import { MessageReader, MessageWriter } from "@foxglove/rosmsg2-serialization";
import Ajv from "ajv";
import { ros2msgText } from "./export-schemas.mjs";

function fail(message) {
  console.error(`check-mcap.mjs: ${message}`);
  process.exit(1);
}

const file = process.argv[2];
if (!file) fail("usage: node check-mcap.mjs FILE.mcap");
await Promise.all([zstd.isLoaded, lz4Decompress.isLoaded]);
const decompressHandlers = {
  zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
  lz4: (buffer, size) => lz4Decompress(buffer, Number(size)),
};
const bytes = fs.readFileSync(file);
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });

const ajv = new Ajv({ strict: false, allErrors: false });
const checkers = new Map();  // channel id -> (data: Uint8Array) => void
const topics = {};
for (const [id, channel] of reader.channelsById) {
  const schema = reader.schemasById.get(channel.schemaId);
  if (!schema) fail(`channel ${channel.topic} has no schema`);
  const text = new TextDecoder().decode(schema.data);
  topics[channel.topic] = { schema: schema.name, encoding: schema.encoding, messages: 0 };
  if (schema.encoding === "jsonschema") {
    if (channel.messageEncoding !== "json") fail(`${channel.topic}: message encoding ${channel.messageEncoding} with a JSON schema`);
    const name = schema.name.replace(/^foxglove\./, "");
    const theirs = jsonschema[name];
    if (!theirs) fail(`${channel.topic}: ${schema.name} is not one of Foxglove's schemas`);
    if (JSON.stringify(JSON.parse(text)) !== JSON.stringify(theirs)) fail(`${channel.topic}: the embedded ${schema.name} differs from @foxglove/schemas'`);
    const validate = ajv.compile(theirs);
    checkers.set(id, (data) => {
      const message = JSON.parse(new TextDecoder().decode(data));
      if (!validate(message)) fail(`${channel.topic}: a message does not validate against ${schema.name}: ${ajv.errorsText(validate.errors)}`);
    });
  } else if (schema.encoding === "ros2msg") {
    if (channel.messageEncoding !== "cdr") fail(`${channel.topic}: message encoding ${channel.messageEncoding} with a ros2msg schema`);
    const ros1Name = schema.name.replace("/msg/", "/");
    if (text !== ros2msgText(ros1Name)) fail(`${channel.topic}: the embedded ${schema.name} differs from ROS 2 Jazzy's definition`);
    const definitions = parseMessageDefinition(text, { ros2: true });
    const messageReader = new MessageReader(definitions);
    const messageWriter = new MessageWriter(definitions);
    checkers.set(id, (data) => {
      const message = messageReader.readMessage(data);
      const again = messageWriter.writeMessage(message);
      if (Buffer.compare(Buffer.from(again), Buffer.from(data)) !== 0) fail(`${channel.topic}: a ${schema.name} does not re-encode to its bytes`);
      if (schema.name === "nav_msgs/msg/OccupancyGrid" && message.data.length !== message.info.width * message.info.height)
        fail(`${channel.topic}: data of ${message.data.length} cells for ${message.info.width} x ${message.info.height}`);
    });
  } else {
    fail(`${channel.topic}: schema encoding ${schema.encoding} is neither jsonschema nor ros2msg`);
  }
}

let indexed = 0;
let lastTime = -1n;
for await (const message of reader.readMessages()) {
  indexed++;
  if (message.logTime < lastTime) fail("messages are not in time order");
  lastTime = message.logTime;
  const channel = reader.channelsById.get(message.channelId);
  topics[channel.topic].messages++;
  checkers.get(message.channelId)(message.data);
}
// Record by record: the same number of messages, every chunk's CRC checked.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
let streamed = 0;
for (let record; (record = stream.nextRecord()); ) if (record.type === "Message") streamed++;
if (!stream.done()) fail("the stream reader did not reach the end of the file");
if (streamed !== indexed) fail(`${indexed} messages through the indexes, ${streamed} record by record`);
const statistics = reader.statistics;
if (!statistics || Number(statistics.messageCount) !== indexed) fail("the statistics' message count differs from the messages");
console.log(JSON.stringify({ topics, messages: indexed }));
