// acqd --preview in the live view (issue 23): frames stream at a few a second, the exposure set
// on the page reaches the camera, and End preview ends it. Saves a screenshot into SHOTS.
// usage: node live_view_preview.js PUPPETEER_CORE_DIR URL SHOTS
const puppeteer = require(process.argv[2]);
const url = process.argv[3];
const shots = process.argv[4];
const waitFor = (page, f, arg, what) =>
  page.waitForFunction(f, { timeout: 60000, polling: 100 }, arg).then(() => console.log("ok: " + what));

(async () => {
  const browser = await puppeteer.launch({ executablePath: "/usr/bin/chromium", headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"] });
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1320, height: 560 });
    await page.goto(url);
    await waitFor(page, () => document.getElementById("state").textContent === "preview" &&
      Number(document.getElementById("frame").dataset.seq) > 0, null, "the page shows the preview");
    const seq = await page.$eval("#frame", (e) => Number(e.dataset.seq));
    const start = Date.now();
    await waitFor(page, (s) => Number(document.getElementById("frame").dataset.seq) >= s + 3, seq,
      "the frame changes as the camera streams");
    const seconds = (Date.now() - start) / 1000;
    console.log("    3 frames in " + seconds.toFixed(1) + " s");
    await waitFor(page, () => document.getElementById("focus").width > 1 &&
      Number(document.getElementById("sharpness").textContent) > 0, null,
      "the focus aid shows the centre at full resolution and its sharpness");
    await page.$eval("#exposure-us", (e) => { e.value = "5000"; });
    await page.click("#set-exposure");
    await waitFor(page, () => document.getElementById("frame-info").textContent.includes("5.0 ms"),
      null, "the exposure set on the page reaches the camera (5.0 ms)");
    await page.screenshot({ path: shots + "/live_view_preview.png", fullPage: true });
    await page.click("#end-preview");
    await waitFor(page, () => ["aborted", "unreachable"].includes(document.getElementById("state").textContent),
      null, "End preview ends it");
  } finally {
    await browser.close();
  }
})().catch((e) => { console.error(e.message || e); process.exit(1); });
