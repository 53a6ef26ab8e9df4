// The viewer page in a real headless Chromium for `stereoball bench viewer`, driven over the
// DevTools protocol with Node's built-in WebSocket (node --experimental-websocket on Node 20).
//   node --experimental-websocket browser_client.mjs URL CHROMIUM
// Prints "ready" once the page draws images; each "mark" line on stdin restarts the counts
// (answered "marked"); any other line prints one JSON line: {"images": N, "skipped": N,
// "latenciesMs": [...], "stages": [[...], ...]} counted since the last mark (the page's own
// capture -> drawn latencies and their stages, window.sbViewer).
// Exits 1 with "error: ..." on failure.

import { createInterface } from "node:readline";

import { openPage, sleep } from "./view_chromium.mjs";

const [url, chromium] = process.argv.slice(2);

async function main() {
  const page = await openPage(chromium, url, WebSocket);
  try {
    const end = Date.now() + 90000;
    let images = 0;
    while (Date.now() < end && images < 5) {
      images = (await page.evaluate("JSON.stringify(window.sbViewer ? sbViewer.images : 0)")) ?? 0;
      await sleep(300);
    }
    if (images < 5) throw new Error(`the page drew ${images} images in 90 s`);
    // Counts restart at each "mark" line and keep every sample from there (the page itself keeps
    // only its last 300); a baseline viewer's page may have no skipped count or stages.
    const mark = () => page.evaluate("JSON.stringify((() => { const s = sbViewer;" +
      " s.benchStart = s.images; s.benchSkipped = s.skipped ?? 0; s.benchLat = []; s.benchStages = [];" +
      " for (const [from, to] of [['latenciesMs', 'benchLat'], ['stages', 'benchStages']]) {" +
      "   if (!s[from] || s[from].benchHooked) continue;" +
      "   const push = s[from].push.bind(s[from]);" +
      "   s[from].push = (v) => { s[to].push(v); return push(v); };" +
      "   s[from].benchHooked = true; }" +
      " return 0; })())");
    await mark();
    console.log("ready");
    const lines = createInterface({ input: process.stdin });
    for await (const line of lines) {
      if (line === "mark") { await mark(); console.log("marked"); continue; }
      break;  // "report", or stdin closed
    }
    const result = await page.evaluate(
      "JSON.stringify({images: sbViewer.images - sbViewer.benchStart, skipped: (sbViewer.skipped ?? 0) -" +
      " sbViewer.benchSkipped, latenciesMs: sbViewer.benchLat, stages: sbViewer.benchStages})");
    console.log(JSON.stringify(result));
  } finally {
    await page.close();
  }
}

main().then(() => process.exit(0), (e) => { console.log(`error: ${e?.message ?? e}`); process.exit(1); });
