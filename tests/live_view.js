// The live view in a real browser (issue 23): headless Chromium (Debian's) driven by
// puppeteer-core through a simulated session with operator prompts. Checks the DOM (state,
// progress moving, a frame image that changes), confirms two prompts and aborts at the third
// from the page's buttons, sees acqd's end as "unreachable", and that no request passes without
// the token. Saves screenshots into SHOTS.
// usage: node live_view.js PUPPETEER_CORE_DIR URL SHOTS
const puppeteer = require(process.argv[2]);
const url = process.argv[3];
const shots = process.argv[4];

function check(ok, what) {
  if (!ok) throw new Error("FAIL: " + what);
  console.log("ok: " + what);
}
const text = (page, id) => page.$eval("#" + id, (e) => e.textContent);
const waitFor = (page, f, arg, what) =>
  page.waitForFunction(f, { timeout: 60000, polling: 100 }, arg).then(() => console.log("ok: " + what));

(async () => {
  const browser = await puppeteer.launch({
    executablePath: "/usr/bin/chromium",
    headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"],
  });
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1320, height: 560 });
    await page.goto(url);
    for (let k = 1; k <= 3; ++k) {
      await waitFor(page, (k) => document.getElementById("state").textContent === "waiting" &&
        document.getElementById("prompt").textContent.includes("pose " + k + " of 3"), k,
        "the page shows prompt " + k + " (waiting)");
      const frames = Number(await text(page, "frames"));
      const progress = await page.$eval("#progress", (e) => e.value);
      check(frames === k - 1, "frames " + frames + " before confirming prompt " + k);
      if (k === 1) await page.screenshot({ path: shots + "/live_view_prompt.png", fullPage: true });
      if (k === 3) {
        await page.click("#abort");
        break;
      }
      await page.click("#confirm");
      await waitFor(page, (n) => Number(document.getElementById("frames").textContent) > n, frames,
        "confirmed from the page: a frame taken after prompt " + k);
      await waitFor(page, (k) => Number(document.getElementById("frame").dataset.seq) >= k, k,
        "the frame image changed to frame " + k);
      const after = await page.$eval("#progress", (e) => e.value);
      check(after > progress, "progress moved (" + progress.toFixed(3) + " -> " + after.toFixed(3) + ")");
      if (k === 2) await page.screenshot({ path: shots + "/live_view_frame.png", fullPage: true });
    }
    // Aborted at prompt 3: acqd ends; the page says it cannot reach it and keeps trying.
    await waitFor(page, () => ["aborted", "unreachable"].includes(document.getElementById("state").textContent),
      null, "the abort from the page ended the session");
    await waitFor(page, () => document.getElementById("state").textContent === "unreachable" &&
      document.getElementById("connection").textContent.includes("retrying"), null,
      "acqd gone: the page says so and retries");
    await page.screenshot({ path: shots + "/live_view_unreachable.png", fullPage: true });
    // No token, a wrong token: refused, the page and the API alike.
    const base = url.split("?")[0];
    const statuses = await page.evaluate(async (base) => {
      const out = [];
      for (const path of ["", "api/status", "api/frame", "api/status?token=wrong"])
        out.push((await fetch(base + path)).status);
      out.push((await fetch(base + "api/command?name=abort", { method: "POST" })).status);
      return out;
    }, base);
    check(statuses.every((s) => s === 403), "without the token every request is refused (" + statuses + ")");
  } finally {
    await browser.close();
  }
})().catch((e) => { console.error(e.message || e); process.exit(1); });
