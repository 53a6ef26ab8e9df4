// Independent check of a StereoBall MCAP file with Foxglove's own packages (the code path
// Foxglove uses): @mcap/core reads the footer, summary and chunk indexes; @mcap/support
// provides zstd; every message of every channel is decoded with @foxglove/omgidl-serialization
// using the omgidl schema stored in the file.
//   node validate.mjs FILE.mcap [EXPECTED.json]
// Exit 0 when everything checks out, 1 with one line per problem otherwise.

import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";

const problems = [];
const fail = (text) => problems.push(text);

// Plain JSON-comparable form of a decoded value: bigint -> string, typed arrays -> arrays,
// long byte arrays -> {$len, $sum} (as the fixture writes them).
function normalize(v) {
  if (typeof v === "bigint") return v.toString();
  if (ArrayBuffer.isView(v) || Array.isArray(v)) {
    const arr = Array.from(v, normalize);
    if (v instanceof Uint8Array && arr.length > 1000) {
      return { $len: arr.length, $sum: arr.reduce((a, b) => a + b, 0) };
    }
    return arr;
  }
  if (v && typeof v === "object") {
    return Object.fromEntries(Object.entries(v).map(([k, x]) => [k, normalize(x)]));
  }
  return v;
}

// Compares decoded against expected; floats compared exactly (the fixture uses exact values).
function compare(path, got, want) {
  if (want !== null && typeof want === "object") {
    if (got === null || typeof got !== "object") return fail(`${path}: expected an object/array`);
    const keys = new Set([...Object.keys(want), ...Object.keys(got)]);
    for (const k of keys) compare(`${path}.${k}`, got[k], want[k]);
    return;
  }
  if (got !== want) fail(`${path}: decoded ${JSON.stringify(got)}, expected ${JSON.stringify(want)}`);
}

async function main() {
  const [file, expectedFile] = process.argv.slice(2);
  if (!file) {
    console.error("usage: node validate.mjs FILE.mcap [EXPECTED.json]");
    process.exit(2);
  }
  const bytes = new Uint8Array(await readFile(file));
  const readable = {
    size: async () => BigInt(bytes.byteLength),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
  const decompressHandlers = await loadDecompressHandlers();
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });

  if (reader.chunkIndexes.length === 0) fail("summary has no chunk indexes");
  if (!reader.statistics) fail("summary has no statistics record");
  if (reader.channelsById.size === 0) fail("summary has no channels");

  const decoders = new Map();
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    if (!schema) { fail(`channel ${channel.topic}: schema ${channel.schemaId} missing`); continue; }
    if (schema.encoding !== "omgidl") fail(`schema ${schema.name}: encoding '${schema.encoding}'`);
    if (channel.messageEncoding !== "cdr") fail(`channel ${channel.topic}: '${channel.messageEncoding}'`);
    const definitions = parseIDL(new TextDecoder().decode(schema.data));
    decoders.set(id, { topic: channel.topic, schema: schema.name,
                       reader: new MessageReader(schema.name, definitions) });
  }

  // Indexed read (uses chunk indexes and message indexes), CRCs validated.
  const decoded = [];
  const counts = new Map();
  let lastLogTime = -1n;
  for await (const m of reader.readMessages({ validateCrcs: true })) {
    const d = decoders.get(m.channelId);
    if (!d) { fail(`message on unknown channel ${m.channelId}`); continue; }
    if (m.logTime < lastLogTime) fail(`log time goes backwards at sequence ${m.sequence}`);
    lastLogTime = m.logTime;
    counts.set(m.channelId, (counts.get(m.channelId) ?? 0n) + 1n);
    let value;
    try {
      value = d.reader.readMessage(m.data);
    } catch (e) {
      fail(`${d.topic} sequence ${m.sequence}: cannot decode as ${d.schema}: ${e.message}`);
      continue;
    }
    decoded.push({ topic: d.topic, schema: d.schema, sequence: m.sequence,
                   log_time: m.logTime.toString(), publish_time: m.publishTime.toString(),
                   value: normalize(value) });
  }
  if (reader.statistics) {
    for (const [id, n] of reader.statistics.channelMessageCounts) {
      if ((counts.get(id) ?? 0n) !== n) fail(`channel ${id}: statistics say ${n}, read ${counts.get(id) ?? 0n}`);
    }
    if (BigInt(decoded.length) !== reader.statistics.messageCount) {
      fail(`statistics say ${reader.statistics.messageCount} messages, decoded ${decoded.length}`);
    }
  }

  // Linear read of every record with CRC validation, as a streaming client would do it.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  let streamed = 0;
  let sawFooter = false;
  for (let rec; (rec = stream.nextRecord()); ) {
    if (rec.type === "Message") streamed++;
    if (rec.type === "Footer") sawFooter = true;
  }
  if (!stream.done()) fail("stream reader did not reach the end of the file");
  if (!sawFooter) fail("stream reader saw no footer");
  if (streamed !== decoded.length) fail(`stream read ${streamed} messages, indexed read ${decoded.length}`);

  if (expectedFile) {
    const expected = JSON.parse(await readFile(expectedFile, "utf8"));
    if (expected.length !== decoded.length) fail(`expected ${expected.length} messages, decoded ${decoded.length}`);
    const bySeq = new Map(decoded.map((d) => [d.sequence, d]));
    for (const want of expected) {
      const got = bySeq.get(want.sequence);
      if (!got) { fail(`message ${want.sequence} (${want.topic}) missing`); continue; }
      compare(`${want.topic}#${want.sequence}`, got, want);
    }
  }

  const topics = [...decoders.values()].map((d) => d.topic).join(", ");
  if (problems.length > 0) {
    for (const p of problems.slice(0, 50)) console.error(`FAIL ${p}`);
    console.error(`${problems.length} problem(s) in ${file}`);
    process.exit(1);
  }
  console.log(`OK ${file}: ${decoded.length} messages on ${decoders.size} channels (${topics}), ` +
              `${reader.chunkIndexes.length} chunks, all decoded with the stored omgidl schemas`);
}

main().catch((e) => {
  console.error(`FAIL ${e?.message ?? e}`);
  process.exit(1);
});
