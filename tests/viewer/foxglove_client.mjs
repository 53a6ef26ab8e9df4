// Independent check of `stereoball view`'s Foxglove WebSocket server with Foxglove's own
// client (@foxglove/ws-protocol), IDL parser and CDR reader, and Foxglove's published schema
// definitions (@foxglove/schemas):
//   node foxglove_client.mjs WS_URL EXPECTED.json
// EXPECTED.json says what the test published. Exit 0 when everything checks out, else 1
// with one FAIL line per problem.

import { readFile } from "node:fs/promises";
import WebSocket from "ws";
import wsProtocol from "@foxglove/ws-protocol";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import internal from "@foxglove/schemas/internal.js";

const { FoxgloveClient } = wsProtocol;
const { foxgloveMessageSchemas } = internal;
const problems = [];
const fail = (text) => problems.push(text);
const near = (a, b, tol = 1e-6) => typeof a === "number" && Math.abs(a - b) <= tol;

// Our IDL types against Foxglove's definitions: same fields, same order, same kinds. Foxglove
// may have added fields at the end since (decoding still works: the schema travels along);
// those are listed as notes.
function checkSchemaAgainstFoxglove(definitions, notes) {
  const primitive = { float64: "float64", uint32: "uint32", int32: "int32", string: "string",
                      boolean: "bool", bytes: "uint8", uint8: "uint8" };
  for (const def of definitions) {
    if (def.aggregatedKind !== "struct") continue;
    const short = def.name.replace(/^foxglove::/, "");
    const theirs = foxgloveMessageSchemas[short === "Time" ? "Timestamp" : short];
    if (!theirs) continue;
    const ours = def.definitions;
    for (let i = 0; i < ours.length; i++) {
      const f = theirs.fields[i];
      if (!f) { fail(`schema ${def.name}: field ${ours[i].name} is not in Foxglove's ${short}`); break; }
      if (f.name !== ours[i].name) { fail(`schema ${def.name}: field ${i} is ${ours[i].name}, Foxglove has ${f.name}`); continue; }
      const array = Boolean(f.array) || f.type.name === "bytes";
      if (array !== Boolean(ours[i].isArray)) fail(`schema ${def.name}.${f.name}: sequence mismatch`);
      if (f.type.type === "primitive" && primitive[f.type.name] !== ours[i].type)
        fail(`schema ${def.name}.${f.name}: type ${ours[i].type}, Foxglove ${f.type.name}`);
    }
    for (let i = ours.length; i < theirs.fields.length; i++)
      notes.add(`${short}.${theirs.fields[i].name} (newer Foxglove field, not sent)`);
  }
}

// Width and height from a JPEG's SOF marker.
function jpegSize(bytes) {
  for (let i = 2; i + 9 < bytes.length;) {
    if (bytes[i] !== 0xff) return null;
    const marker = bytes[i + 1], len = (bytes[i + 2] << 8) | bytes[i + 3];
    if (marker >= 0xc0 && marker <= 0xc2) {
      return { height: (bytes[i + 5] << 8) | bytes[i + 6], width: (bytes[i + 7] << 8) | bytes[i + 8] };
    }
    i += 2 + len;
  }
  return null;
}

function checkImage(m, want, frameId) {
  const size = jpegSize(m.data);
  return m.format === "jpeg" && m.frame_id === frameId && m.data[0] === 0xff && m.data[1] === 0xd8 &&
    size && size.width === want.width && size.height === want.height &&
    m.timestamp.sec === want.sec && m.timestamp.nsec === want.nsec;
}

function checkAnnotations(m, circle) {
  const c = m.circles[0];
  return c && near(c.position.x, circle.x, 1e-3) && near(c.position.y, circle.y, 1e-3) &&
    near(c.diameter, 2 * circle.radius, 1e-3) && m.points.length === 2 &&
    near(m.points[1].points[0].y, circle.y, 1e-3) && m.texts[0].text.startsWith("score");
}

function checkScene(m, want) {
  const byId = Object.fromEntries(m.entities.map((e) => [e.id, e]));
  const ball = byId.ball_estimate, truth = byId.ground_truth_ball;
  return byId.robot && byId.robot.cubes.length === 1 && ball && ball.frame_id === "camera" &&
    want.track_position.every((v, i) => near(ball.spheres[0].pose.position["xyz"[i]], v)) &&
    truth && want.truth_ball_world.every((v, i) => near(truth.spheres[0].pose.position["xyz"[i]], v));
}

function checkTransforms(m, want) {
  const t = m.transforms.find((x) => x.parent_frame_id === "world" && x.child_frame_id === "robot");
  return t && near(t.translation.x, want.robot_xy[0]) && near(t.translation.y, want.robot_xy[1]) &&
    m.transforms.some((x) => x.parent_frame_id === "robot" && x.child_frame_id === "camera");
}

async function main() {
  const [url, expectedFile] = process.argv.slice(2);
  const want = JSON.parse(await readFile(expectedFile, "utf8"));
  const checks = {
    "view/left/image": (m) => checkImage(m, want.image, "camera"),
    "view/right/image": (m) => checkImage(m, want.image, "camera_right"),
    "view/left/annotations": (m) => checkAnnotations(m, want.left_circle),
    "view/right/annotations": (m) => checkAnnotations(m, want.right_circle),
    "view/scene": (m) => checkScene(m, want),
    "view/transforms": (m) => checkTransforms(m, want),
    "view/plot": (m) => m.track_state === want.track_state && near(m.distance_m, want.distance_m),
  };
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const channels = new Map(), passed = new Set(), statuses = [], notes = new Set();
  let messages = 0, serverInfo = null;

  client.on("serverInfo", (info) => { serverInfo = info; });
  client.on("status", (s) => statuses.push(s));
  client.on("error", (e) => fail(`client error: ${e.message ?? e}`));
  client.on("advertise", (list) => {
    for (const ch of list) {
      let decode;
      if (ch.encoding === "cdr" && ch.schemaEncoding === "omgidl") {
        const definitions = parseIDL(ch.schema);
        checkSchemaAgainstFoxglove(definitions, notes);
        const reader = new MessageReader(ch.schemaName, definitions);
        decode = (data) => reader.readMessage(data);
      } else if (ch.encoding === "json" && ch.schemaEncoding === "jsonschema") {
        JSON.parse(ch.schema);
        decode = (data) => JSON.parse(new TextDecoder().decode(data));
      } else {
        fail(`channel ${ch.topic}: unexpected encoding ${ch.encoding}/${ch.schemaEncoding}`);
        continue;
      }
      const sub = client.subscribe(ch.id);
      channels.set(sub, { ...ch, decode });
    }
  });
  client.on("message", ({ subscriptionId, data }) => {
    messages++;
    const ch = channels.get(subscriptionId);
    if (!ch) return fail(`message for unknown subscription ${subscriptionId}`);
    let value;
    const bytes = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
    try { value = ch.decode(bytes); } catch (e) { return fail(`${ch.topic}: cannot decode: ${e.message}`); }
    const check = checks[ch.topic];
    if (check && !passed.has(ch.topic) && check(value)) passed.add(ch.topic);
  });

  const deadline = Date.now() + want.timeout_ms;
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  while (Date.now() < deadline && passed.size < Object.keys(checks).length) await sleep(50);

  if (!serverInfo) fail("no serverInfo");
  for (const [topic, schemaName] of Object.entries(want.channels)) {
    const ch = [...channels.values()].find((c) => c.topic === topic);
    if (!ch) fail(`channel ${topic} not advertised`);
    else if (ch.schemaName !== schemaName) fail(`channel ${topic}: schema ${ch.schemaName}, expected ${schemaName}`);
  }
  for (const topic of Object.keys(checks))
    if (!passed.has(topic)) fail(`${topic}: no message matching what was published`);

  // Bad input: the server answers with a status and keeps serving this connection.
  const before = statuses.length;
  ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 900, channelId: 4242 }] }));
  ws.send(JSON.stringify({ op: "unsubscribe", subscriptionIds: [777] }));
  ws.send("this is not JSON");
  ws.send(new Uint8Array([1, 2, 3]));
  ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: "x", channelId: 1 }] }));
  await sleep(1500);
  const replies = statuses.slice(before).map((s) => `${s.level}:${s.message}`);
  const expectReply = (re, what) => { if (!replies.some((r) => re.test(r))) fail(`no status for ${what}: got ${JSON.stringify(replies)}`); };
  expectReply(/^1:.*unknown channel 4242/, "an unknown channel");
  expectReply(/^1:.*unknown subscription id 777/, "an unknown subscription id");
  expectReply(/^2:not valid JSON/, "text that is not JSON");
  expectReply(/^2:binary client messages/, "a binary client message");
  expectReply(/^2:subscribe: each subscription needs integer/, "a malformed subscribe");
  const count = messages;
  await sleep(1000);
  if (messages <= count) fail("no messages after the bad input: the server stopped serving");
  client.close();

  if (notes.size) console.log(`note: ${[...notes].join("; ")}`);
  if (problems.length) {
    for (const p of problems) console.error(`FAIL ${p}`);
    process.exit(1);
  }
  console.log(`OK ${channels.size} channels, ${messages} messages decoded, every published value found`);
  process.exit(0);
}

main().catch((e) => { console.error(`FAIL ${e?.stack ?? e}`); process.exit(1); });
