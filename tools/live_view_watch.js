// Keeps the live view open in headless Chromium until the session ends (a benchmark's page
// load: tools/bench_live_view.sh). usage: node live_view_watch.js PUPPETEER_CORE_DIR URL
const puppeteer = require(process.argv[2]);
(async () => {
  const browser = await puppeteer.launch({ executablePath: "/usr/bin/chromium", headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"] });
  const page = await browser.newPage();
  await page.goto(process.argv[3]);
  let frames = 0;
  for (;;) {
    await new Promise((r) => setTimeout(r, 1000));
    const state = await page.$eval("#state", (e) => e.textContent);
    frames = Number(await page.$eval("#frame", (e) => e.dataset.seq));
    if (["done", "failed", "aborted", "stopped", "unreachable"].includes(state)) break;
  }
  console.log("page closed; the last frame it showed: #" + frames);
  await browser.close();
})().catch((e) => { console.error(e); process.exit(1); });
