// Prints, as JSON, a few decoded values of the first message of each derived channel of an
// MCAP file (Foxglove's MCAP reader and CDR decoder, the schema stored in the file).
//   node derived_dump.mjs FILE.mcap
import { readFile } from "node:fs/promises";
import { McapIndexedReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";

const bytes = new Uint8Array(await readFile(process.argv[2]));
const reader = await McapIndexedReader.Initialize({
  readable: { size: async () => BigInt(bytes.byteLength),
              read: async (o, n) => bytes.subarray(Number(o), Number(o + n)) },
  decompressHandlers: await loadDecompressHandlers(),
});
const readers = new Map();
for (const [id, ch] of reader.channelsById) {
  if (!ch.topic.startsWith("view/")) continue;
  const schema = reader.schemasById.get(ch.schemaId);
  readers.set(id, { topic: ch.topic, r: new MessageReader(schema.name, parseIDL(new TextDecoder().decode(schema.data))) });
}
const jpegWidth = (d) => {
  for (let i = 2; i + 9 < d.length; i += 2 + ((d[i + 2] << 8) | d[i + 3]))
    if (d[i + 1] >= 0xc0 && d[i + 1] <= 0xc2) return (d[i + 7] << 8) | d[i + 8];
  return -1;
};
const out = {};
for await (const m of reader.readMessages()) {
  const ch = readers.get(m.channelId);
  if (!ch || out[ch.topic]) continue;
  const v = ch.r.readMessage(m.data);
  if (ch.topic.endsWith("/image")) out[ch.topic] = { format: v.format, width: jpegWidth(v.data) };
  else if (ch.topic.endsWith("/annotations") && v.circles.length)
    out[ch.topic] = { circle_x: v.circles[0].position.x };
  else if (ch.topic === "view/scene") {
    const ball = v.entities.find((e) => e.id === "ball_estimate");
    if (ball) out[ch.topic] = { ball_z: ball.spheres[0].pose.position.z };
  } else if (ch.topic === "view/transforms") out[ch.topic] = { n: v.transforms.length };
}
console.log(JSON.stringify(out));
