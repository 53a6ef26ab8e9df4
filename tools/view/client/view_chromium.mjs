// Headless Chromium showing a page, driven over the DevTools protocol: shared by the viewer's
// browser test (tests/viewer/browser_check.mjs) and its benchmark
// (tools/bench-viewer/browser_client.mjs). WebSocketImpl is the WebSocket class to use:
// Node's built-in one (node --experimental-websocket on Node 20) or the `ws` package's.

import { spawn } from "node:child_process";
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Starts Chromium with a throw-away profile; endpoint resolves to its DevTools address.
function startChromium(chromium) {
  const profile = mkdtempSync(join(tmpdir(), "sb-chromium-"));
  const proc = spawn(chromium, [
    "--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
    "--no-first-run", "--no-default-browser-check", "--remote-debugging-port=0",
    `--user-data-dir=${profile}`, "--window-size=1500,1000", "about:blank",
  ], { stdio: ["ignore", "ignore", "pipe"] });
  const endpoint = new Promise((resolve, reject) => {
    let err = "";
    const timer = setTimeout(() => reject(new Error(`chromium did not start in 60 s: ${err.slice(-500)}`)), 60000);
    proc.stderr.on("data", (d) => {
      err += d;
      const m = /DevTools listening on (ws:\/\/\S+)/.exec(err);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    proc.on("exit", (code) => reject(new Error(`chromium exited (${code}): ${err.slice(-500)}`)));
  });
  return { proc, profile, endpoint };
}

// Numbered DevTools requests over one WebSocket, each answered or timed out after 30 s.
class Cdp {
  constructor(ws) {
    this.ws = ws; this.next = 1; this.pending = new Map();
    ws.addEventListener("message", (ev) => {
      const msg = JSON.parse(ev.data);
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

// Starts Chromium, opens url in a new page and returns { send(method, params), evaluate(expr)
// -> the JSON value of a JSON.stringify expression, close() }. close() always stops Chromium
// and removes its profile.
export async function openPage(chromium, url, WebSocketImpl) {
  const chrome = startChromium(chromium);
  let ws = null;
  const close = async () => {
    if (ws) ws.close();
    const exited = new Promise((r) => chrome.proc.once("exit", r));
    chrome.proc.kill("SIGKILL");
    await Promise.race([exited, sleep(5000)]);
    // Chromium's helper processes may still be writing to the profile for a moment.
    try { rmSync(chrome.profile, { recursive: true, force: true, maxRetries: 10, retryDelay: 200 }); }
    catch (e) { console.error(`note: profile ${chrome.profile} not removed: ${e.message}`); }
  };
  try {
    ws = new WebSocketImpl(await chrome.endpoint);
    await new Promise((resolve, reject) => {
      ws.addEventListener("open", resolve);
      ws.addEventListener("error", () => reject(new Error("cannot reach Chromium's DevTools")));
    });
    const cdp = new Cdp(ws);
    const { targetId } = await cdp.send("Target.createTarget", { url: "about:blank" });
    const { sessionId } = await cdp.send("Target.attachToTarget", { targetId, flatten: true });
    await cdp.send("Page.enable", {}, sessionId);
    await cdp.send("Page.navigate", { url }, sessionId);
    const send = (method, params = {}) => cdp.send(method, params, sessionId);
    const evaluate = async (expression) => {
      const r = await send("Runtime.evaluate", { expression, returnByValue: true });
      return JSON.parse(r.result.value ?? "null");
    };
    return { send, evaluate, close };
  } catch (e) {
    await close();
    throw e;
  }
}
