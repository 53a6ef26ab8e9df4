// Loads the viewer page in a real headless Chromium (driven over the DevTools protocol with
// the `ws` package) and checks, from the page's own state (window.sbViewer), that images,
// detection overlays and track states arrive and keep updating. Writes viewer.png and
// state.json to OUT_DIR.
//   node browser_check.mjs URL OUT_DIR CHROMIUM [--reconnect | --overlay=X,Y,R]
// With --reconnect it writes OUT_DIR/phase1 once live and OUT_DIR/down once the page has seen
// the viewer go away, then expects the page to reconnect (the test restarts the viewer) and
// images to flow again. With --overlay it expects the left
// circle drawn at X,Y with radius R (canvas pixels, within 0.01 px).
// Exit 0 when all checks pass, 1 with FAIL lines otherwise.

import { writeFileSync } from "node:fs";
import { join } from "node:path";
import WebSocket from "ws";

import { openPage, sleep } from "./view_chromium.mjs";

const [url, outDir, chromium, mode] = process.argv.slice(2);
const problems = [];
const fail = (t) => problems.push(t);

async function main() {
  const page = await openPage(chromium, url, WebSocket);
  try {
    const state = () => page.evaluate(
      "JSON.stringify(window.sbViewer ? {images: sbViewer.images, overlays: sbViewer.overlays," +
      " scenes: sbViewer.scenes, trackUpdates: sbViewer.trackUpdates, trackState: sbViewer.trackState," +
      " connected: sbViewer.connected, connects: sbViewer.connects, latenciesMs: sbViewer.latenciesMs," +
      " lastOverlay: sbViewer.lastOverlay," +
      " nodes: sbViewer.scene ? sbViewer.scene.nodes.map(n => n.component) : []} : null)");
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
    if (mode?.startsWith("--overlay=") && problems.length === 0) {
      const [x, y, r] = mode.slice(10).split(",").map(Number);
      const o = later?.lastOverlay;
      if (!o || Math.abs(o.x_px - x) > 0.01 || Math.abs(o.y_px - y) > 0.01 || Math.abs(o.radius_px - r) > 0.01)
        fail(`left circle drawn at ${JSON.stringify(o)}, expected x ${x} y ${y} radius ${r}`);
    }
    if (mode === "--reconnect" && problems.length === 0) {
      writeFileSync(join(outDir, "phase1"), "live\n");
      const down = await waitFor((s) => !s.connected, 30000);
      if (down && down.connected) fail("the page never saw the viewer go away");
      writeFileSync(join(outDir, "down"), "down\n");
      const back = await waitFor((s) => s.connected && s.connects >= 2, 60000);
      if (!back || back.connects < 2) fail(`the page did not reconnect: ${JSON.stringify(back)}`);
      const flowing = back && await waitFor((s) => s.images >= back.images + 5, 30000);
      if (back && flowing && flowing.images < back.images + 5) fail("no images after reconnecting");
      final = flowing ?? back;
    }
    const shot = await page.send("Page.captureScreenshot", { format: "png" });
    writeFileSync(join(outDir, "viewer.png"), Buffer.from(shot.data, "base64"));
    const lat = (final?.latenciesMs ?? []).slice().sort((a, b) => a - b);
    const summary = { ...final, latenciesMs: undefined,
                      latency_p50_ms: lat.length ? lat[lat.length >> 1] : null, samples: lat.length };
    writeFileSync(join(outDir, "state.json"), JSON.stringify(summary, null, 2));
    console.log(`page state: ${JSON.stringify(summary)}`);
  } finally {
    await page.close();
  }
  if (problems.length) { for (const p of problems) console.error(`FAIL ${p}`); process.exit(1); }
  console.log(`OK screenshot ${join(outDir, "viewer.png")}`);
  process.exit(0);
}

main().catch((e) => { console.error(`FAIL ${e?.stack ?? e}`); process.exit(1); });
