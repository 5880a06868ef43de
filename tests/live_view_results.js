// The live view's session files (issue 23): while a simulated session runs to its end with the
// page open, each merged pose's thumbnail joins the strip (a real PNG the browser decoded), and
// once processed the map's quick looks, the validation renders and the report appear, and stay
// after acqd has ended. Mode "finished": a server given --session with no acqd shows the same.
// Saves a screenshot into SHOTS.
// usage: node live_view_results.js PUPPETEER_CORE_DIR URL SHOTS running|finished
const puppeteer = require(process.argv[2]);
const url = process.argv[3];
const shots = process.argv[4];
const mode = process.argv[5];
const waitFor = (page, f, arg, what, timeout) =>
  page.waitForFunction(f, { timeout: timeout || 120000, polling: 200 }, arg)
    .then(() => console.log("ok: " + what));
// How many images under `selector` the browser has decoded (a 404 or a broken PNG decodes to 0).
const decoded = (selector) => Array.from(document.querySelectorAll(selector + " img"))
  .filter((img) => img.complete && img.naturalWidth > 0).length;

(async () => {
  const browser = await puppeteer.launch({ executablePath: "/usr/bin/chromium", headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"] });
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1320, height: 900 });
    await page.goto(url);
    if (mode === "running") {
      // The background merges write each pose's thumbnail while the gantry moves on.
      await waitFor(page, () => document.getElementById("state").textContent === "running" &&
        document.getElementById("results").style.display === "none" &&
        Number(document.getElementById("pose-count").textContent) >= 1, null,
        "a pose's thumbnail on the strip while the session runs");
      await waitFor(page, (d) => eval(d)("#poses") >= 1, decoded.toString(),
        "the thumbnail is an image the browser decoded");
    }
    await waitFor(page, () => document.getElementById("results").style.display === "block", null,
      "the results shown once the session is processed");
    await waitFor(page, (d) => eval(d)("#quicklooks") >= 2 && eval(d)("#validation") >= 1,
      decoded.toString(), "quick looks and validation renders decoded");
    const looks = await page.$$eval("#quicklooks figcaption", (c) => c.map((e) => e.textContent));
    if (!looks.includes("diffuse") || !looks.includes("specular"))
      throw new Error("FAIL: the quick looks lack diffuse or specular: " + looks);
    console.log("ok: quick looks " + looks.join(", "));
    await waitFor(page, () => document.getElementById("report-text").textContent.includes("validation"),
      null, "the report's text on the page");
    const poses = Number(await page.$eval("#pose-count", (e) => e.textContent));
    if (poses < 10) throw new Error("FAIL: only " + poses + " poses on the strip");
    console.log("ok: " + poses + " poses on the strip");
    if (mode === "running") {
      await waitFor(page, () => document.getElementById("state").textContent === "unreachable",
        null, "acqd ended");
      const still = await page.evaluate(() => document.getElementById("results").style.display);
      if (still !== "block") throw new Error("FAIL: the results went away with acqd");
      console.log("ok: the results stay after acqd has ended");
    }
    await page.screenshot({ path: shots + "/live_view_results.png", fullPage: true });
  } finally {
    await browser.close();
  }
})().catch((e) => { console.error(e.message || e); process.exit(1); });
