// The viewer page in a real headless Chromium for `stereoball bench viewer`, driven over the
// DevTools protocol with Node's built-in WebSocket (node --experimental-websocket on Node 20).
//   node --experimental-websocket browser_client.mjs URL CHROMIUM
// Prints "ready" once the page draws images, then waits for a line on stdin, then prints one
// JSON line: {"images": N, "latenciesMs": [...]} counted since "ready" (the page's own
// capture -> drawn latencies, window.sbViewer). Exits 1 with "error: ..." on failure.

import { spawn } from "node:child_process";
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { createInterface } from "node:readline";

const [url, chromium] = process.argv.slice(2);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function startChromium() {
  const profile = mkdtempSync(join(tmpdir(), "sb-bench-chromium-"));
  const proc = spawn(chromium, [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--no-first-run", "--no-default-browser-check", "--remote-debugging-port=0",
    `--user-data-dir=${profile}`, "--window-size=1500,1000", "about:blank",
  ], { stdio: ["ignore", "ignore", "pipe"] });
  const endpoint = new Promise((resolve, reject) => {
    let err = "";
    const timer = setTimeout(() => reject(new Error("chromium did not start in 60 s")), 60000);
    proc.stderr.on("data", (d) => {
      err += d;
      const m = /DevTools listening on (ws:\/\/\S+)/.exec(err);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on("exit", (code) => reject(new Error(`chromium exited (${code}): ${err.slice(-300)}`)));
  });
  return { proc, profile, endpoint };
}

async function main() {
  const chrome = startChromium();
  try {
    const ws = new WebSocket(await chrome.endpoint);
    await new Promise((resolve, reject) => { ws.onopen = resolve; ws.onerror = reject; });
    let next = 1;
    const pending = new Map();
    ws.onmessage = (ev) => {
      const msg = JSON.parse(ev.data);
      const p = pending.get(msg.id);
      if (!p) return;
      pending.delete(msg.id);
      msg.error ? p.reject(new Error(msg.error.message)) : p.resolve(msg.result);
    };
    const send = (method, params = {}, sessionId) => new Promise((resolve, reject) => {
      const id = next++;
      pending.set(id, { resolve, reject });
      ws.send(JSON.stringify({ id, method, params, sessionId }));
      setTimeout(() => { if (pending.delete(id)) reject(new Error(`${method} timed out`)); }, 30000);
    });
    const { targetId } = await send("Target.createTarget", { url: "about:blank" });
    const { sessionId } = await send("Target.attachToTarget", { targetId, flatten: true });
    await send("Page.navigate", { url }, sessionId);
    const evaluate = async (expression) => {
      const r = await send("Runtime.evaluate", { expression, returnByValue: true }, sessionId);
      return JSON.parse(r.result.value ?? "null");
    };
    const end = Date.now() + 90000;
    let images = 0;
    while (Date.now() < end && images < 5) {
      images = (await evaluate("JSON.stringify(window.sbViewer ? sbViewer.images : 0)")) ?? 0;
      await sleep(300);
    }
    if (images < 5) throw new Error(`the page drew ${images} images in 90 s`);
    // Keep every latency from here on (the page itself keeps only its last 300).
    await evaluate("JSON.stringify((() => { sbViewer.benchStart = sbViewer.images; sbViewer.benchLat = [];" +
      " const push = sbViewer.latenciesMs.push.bind(sbViewer.latenciesMs);" +
      " sbViewer.latenciesMs.push = (v) => { sbViewer.benchLat.push(v); return push(v); }; return 0; })())");
    console.log("ready");
    const lines = createInterface({ input: process.stdin });
    await new Promise((r) => { lines.once("line", r); lines.once("close", r); });
    const result = await evaluate(
      "JSON.stringify({images: sbViewer.images - sbViewer.benchStart, latenciesMs: sbViewer.benchLat})");
    console.log(JSON.stringify(result));
    ws.close();
  } finally {
    chrome.proc.kill("SIGKILL");
    await sleep(500);
    try { rmSync(chrome.profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 }); }
    catch { /* helper processes may still hold it; it is in the temp folder */ }
  }
}

main().then(() => process.exit(0), (e) => { console.log(`error: ${e?.message ?? e}`); process.exit(1); });
