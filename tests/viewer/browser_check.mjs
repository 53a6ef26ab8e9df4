// Loads the viewer page in a real headless Chromium (driven over the DevTools protocol with
// the `ws` package) and checks, from the page's own state (window.sbViewer), that images,
// detection overlays and track states arrive and keep updating. Writes viewer.png and
// state.json to OUT_DIR.
//   node browser_check.mjs URL OUT_DIR CHROMIUM [--reconnect]
// With --reconnect it writes OUT_DIR/phase1 once live, then expects the page to reconnect
// (the test restarts the viewer) and images to flow again.
// Exit 0 when all checks pass, 1 with FAIL lines otherwise.

import { spawn } from "node:child_process";
import { mkdtempSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import WebSocket from "ws";

const [url, outDir, chromium, mode] = process.argv.slice(2);
const problems = [];
const fail = (t) => problems.push(t);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function startChromium() {
  const profile = mkdtempSync(join(tmpdir(), "sb-chromium-"));
  const proc = spawn(chromium, [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--no-first-run", "--no-default-browser-check", "--remote-debugging-port=0",
    `--user-data-dir=${profile}`, "--window-size=1500,1000", "about:blank",
  ], { stdio: ["ignore", "ignore", "pipe"] });
  const endpoint = new Promise((resolve, reject) => {
    let err = "";
    const timer = setTimeout(() => reject(new Error(`chromium did not start: ${err.slice(-500)}`)), 60000);
    proc.stderr.on("data", (d) => {
      err += d;
      const m = /DevTools listening on (ws:\/\/\S+)/.exec(err);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on("exit", (code) => reject(new Error(`chromium exited (${code}): ${err.slice(-500)}`)));
  });
  return { proc, profile, endpoint };
}

// Minimal DevTools protocol client: numbered requests, one flattened page session.
class Cdp {
  constructor(ws) {
    this.ws = ws; this.next = 1; this.pending = new Map();
    ws.on("message", (data) => {
      const msg = JSON.parse(data);
      const p = this.pending.get(msg.id);
      if (!p) return;
      this.pending.delete(msg.id);
      msg.error ? p.reject(new Error(msg.error.message)) : p.resolve(msg.result);
    });
  }
  send(method, params = {}, sessionId) {
    const id = this.next++;
    this.ws.send(JSON.stringify({ id, method, params, sessionId }));
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      setTimeout(() => { if (this.pending.delete(id)) reject(new Error(`${method} timed out`)); }, 30000);
    });
  }
}

async function main() {
  const chrome = startChromium();
  const cleanup = async () => {
    const exited = new Promise((r) => chrome.proc.once("exit", r));
    chrome.proc.kill("SIGKILL");
    await Promise.race([exited, sleep(5000)]);
    // Chromium's helper processes may still be writing to the profile for a moment.
    try { rmSync(chrome.profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 }); }
    catch (e) { console.log(`note: profile ${chrome.profile} not removed: ${e.message}`); }
  };
  try {
    const ws = new WebSocket(await chrome.endpoint, { perMessageDeflate: false });
    await new Promise((r, j) => { ws.on("open", r); ws.on("error", j); });
    const cdp = new Cdp(ws);
    const { targetId } = await cdp.send("Target.createTarget", { url: "about:blank" });
    const { sessionId } = await cdp.send("Target.attachToTarget", { targetId, flatten: true });
    await cdp.send("Page.enable", {}, sessionId);
    await cdp.send("Page.navigate", { url }, sessionId);
    const state = async () => {
      const r = await cdp.send("Runtime.evaluate", {
        expression: "JSON.stringify(window.sbViewer ? {images: sbViewer.images, overlays: sbViewer.overlays," +
          " scenes: sbViewer.scenes, trackUpdates: sbViewer.trackUpdates, trackState: sbViewer.trackState," +
          " connected: sbViewer.connected, connects: sbViewer.connects, latenciesMs: sbViewer.latenciesMs," +
          " nodes: sbViewer.scene ? sbViewer.scene.nodes.map(n => n.component) : []} : null)",
        returnByValue: true }, sessionId);
      return JSON.parse(r.result.value ?? "null");
    };
    // Phase 1: images, overlays and track updates arrive, then keep arriving.
    const waitFor = async (pred, ms) => {
      const end = Date.now() + ms;
      let s = null;
      while (Date.now() < end) { s = await state(); if (s && pred(s)) return s; await sleep(300); }
      return s;
    };
    const first = await waitFor((s) => s.images >= 5 && s.overlays >= 3 && s.trackUpdates >= 3, 90000);
    if (!first || first.images < 5) fail(`images did not arrive: ${JSON.stringify(first)}`);
    else if (first.overlays < 3) fail(`no detection overlay drawn: ${JSON.stringify(first)}`);
    else if (first.trackUpdates < 3) fail(`no track updates: ${JSON.stringify(first)}`);
    const later = await waitFor((s) => first && s.images >= first.images + 5 &&
      s.overlays > first.overlays && s.trackUpdates > first.trackUpdates, 60000);
    if (first && later && !(later.images >= first.images + 5 && later.trackUpdates > first.trackUpdates &&
        later.overlays > first.overlays)) fail(`page stopped updating: ${JSON.stringify(first)} -> ${JSON.stringify(later)}`);
    if (later && !["idle", "following", "searching"].includes(later.trackState))
      fail(`track state '${later?.trackState}' is not one of idle/following/searching`);
    let final = later;
    if (mode === "--reconnect" && problems.length === 0) {
      writeFileSync(join(outDir, "phase1"), "live\n");
      const down = await waitFor((s) => !s.connected, 30000);
      if (down && down.connected) fail("the page never saw the viewer go away");
      const back = await waitFor((s) => s.connected && s.connects >= 2, 60000);
      if (!back || back.connects < 2) fail(`the page did not reconnect: ${JSON.stringify(back)}`);
      const flowing = back && await waitFor((s) => s.images >= back.images + 5, 30000);
      if (back && flowing && flowing.images < back.images + 5) fail("no images after reconnecting");
      final = flowing ?? back;
    }
    const shot = await cdp.send("Page.captureScreenshot", { format: "png" }, sessionId);
    writeFileSync(join(outDir, "viewer.png"), Buffer.from(shot.data, "base64"));
    const lat = (final?.latenciesMs ?? []).slice().sort((a, b) => a - b);
    const summary = { ...final, latenciesMs: undefined,
                      latency_p50_ms: lat.length ? lat[lat.length >> 1] : null, samples: lat.length };
    writeFileSync(join(outDir, "state.json"), JSON.stringify(summary, null, 2));
    console.log(`page state: ${JSON.stringify(summary)}`);
    ws.close();
  } finally {
    await cleanup();
  }
  if (problems.length) { for (const p of problems) console.error(`FAIL ${p}`); process.exit(1); }
  console.log(`OK screenshot ${join(outDir, "viewer.png")}`);
  process.exit(0);
}

main().catch((e) => { console.error(`FAIL ${e?.stack ?? e}`); process.exit(1); });
