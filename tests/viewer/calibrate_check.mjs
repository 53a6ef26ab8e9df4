// Loads the calibration page (stereoball view --calibrate) in a real headless Chromium and
// checks, from the page's own state (window.sbCalib), that both eyes arrive with the board
// corners drawn, that poses are taken, that a passing verdict is shown, and that the page's
// button writes the calibration. Writes calibrate.png and state.json to OUT_DIR.
//   node calibrate_check.mjs URL OUT_DIR CHROMIUM [TIMEOUT_S]
// Exit 0 when all checks pass, 1 with FAIL lines otherwise.

import { writeFileSync } from "node:fs";
import { join } from "node:path";
import WebSocket from "ws";

import { openPage, sleep } from "./view_chromium.mjs";

const [url, outDir, chromium, timeoutArg] = process.argv.slice(2);
const timeoutMs = Number(timeoutArg ?? 80) * 1000;
const problems = [];
const fail = (t) => problems.push(t);

async function main() {
  const page = await openPage(chromium, url, WebSocket);
  const end = Date.now() + timeoutMs;
  let s = null;
  try {
    const state = () => page.evaluate(
      "JSON.stringify(window.sbCalib && sbCalib.state ? {images: sbCalib.images, " +
      "cornersDrawn: sbCalib.cornersDrawn, phase: sbCalib.state.phase, message: sbCalib.state.message, " +
      "poses: sbCalib.state.poses.length, verdict: sbCalib.state.verdict, written: sbCalib.state.written, " +
      "write_error: sbCalib.state.write_error, " +
      "writeEnabled: !document.getElementById('write').disabled} : null)");
    const waitFor = async (pred) => {
      while (Date.now() < end) {
        s = await state();
        if (s && pred(s)) return true;
        if (s && s.phase === "failed") return false;
        await sleep(250);
      }
      return false;
    };
    if (!await waitFor((x) => x.images >= 3 && x.cornersDrawn.left >= 3 && x.cornersDrawn.right >= 3))
      fail(`no board corners drawn on both eyes: ${JSON.stringify(s)}`);
    else if (!await waitFor((x) => x.poses >= 1)) fail(`no pose taken: ${JSON.stringify(s)}`);
    else {
      // A picture of the page while it collects (for the real-robot guide).
      await sleep(1500);
      const shot = await page.send("Page.captureScreenshot", { format: "png" });
      writeFileSync(join(outDir, "collecting.png"), Buffer.from(shot.data, "base64"));
      // On a loaded machine fewer poses may be taken in time: with the six a calibration needs
      // and 20 s left, press "calibrate now" (what a person does when the bars are full).
      let pressed = false;
      const verdictOrPress = async (x) => {
        if (x.phase === "verdict") return true;
        if (!pressed && x.poses >= 6 && Date.now() > end - 20000) {
          pressed = true;
          console.log(`pressing "calibrate now" with ${x.poses} poses`);
          await page.evaluate("JSON.stringify(document.getElementById('finish').click())");
        }
        return false;
      };
      let got = false;
      while (!got && Date.now() < end) {
        s = await state();
        if (s && s.phase === "failed") break;
        got = s ? await verdictOrPress(s) : false;
        if (!got) await sleep(250);
      }
      if (!got) fail(`no verdict: ${JSON.stringify(s)}`);
      else if (!s.verdict.pass) fail(`the verdict failed: ${JSON.stringify(s.verdict.failures)}`);
      else if (!s.writeEnabled) fail("the write button is not enabled after a passing verdict");
      else {
        await page.evaluate("JSON.stringify(document.getElementById('write').click())");
        if (!await waitFor((x) => x.written || x.write_error))
          fail(`nothing written: ${JSON.stringify(s)}`);
        else if (s.write_error) fail(`writing failed: ${s.write_error}`);
      }
    }
    const shot = await page.send("Page.captureScreenshot", { format: "png" });
    writeFileSync(join(outDir, "calibrate.png"), Buffer.from(shot.data, "base64"));
    writeFileSync(join(outDir, "state.json"), JSON.stringify(s, null, 2));
    console.log(`page state: ${JSON.stringify({ ...s, verdict: s?.verdict ? { ...s.verdict, per_pose: undefined } : null })}`);
  } finally {
    await page.close();
  }
  if (problems.length) { for (const p of problems) console.error(`FAIL ${p}`); process.exit(1); }
  console.log(`OK wrote ${s.written}`);
  process.exit(0);
}

main().catch((e) => { console.error(`FAIL ${e?.stack ?? e}`); process.exit(1); });
