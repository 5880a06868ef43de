// Keeps the live view open in headless Chromium until the session ends (a benchmark's page
// load: tools/bench_live_view.sh). With --blank the browser shows an empty page instead, and
// node asks the server for the state once a second: what the browser costs by itself.
// usage: node live_view_watch.js PUPPETEER_CORE_DIR URL [--blank]
const puppeteer = require(process.argv[2]);
const url = process.argv[3], blank = process.argv[4] === "--blank";
const ended = (state) => ["done", "failed", "aborted", "stopped", "unreachable"].includes(state);
(async () => {
  const browser = await puppeteer.launch({ executablePath: "/usr/bin/chromium", headless: true,
    args: ["--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage"] });
  const page = await browser.newPage();
  await page.goto(blank ? "about:blank" : url);
  let frames = 0;
  for (;;) {
    await new Promise((r) => setTimeout(r, 1000));
    if (blank) {
      const status = new URL("/api/status", url);
      status.searchParams.set("token", new URL(url).searchParams.get("token"));
      if (ended((await (await fetch(status)).json()).state)) break;
      continue;
    }
    const state = await page.$eval("#state", (e) => e.textContent);
    frames = Number(await page.$eval("#frame", (e) => e.dataset.seq));
    if (ended(state)) break;
  }
  console.log(blank ? "blank page closed" : "page closed; the last frame it showed: #" + frames);
  await browser.close();
})().catch((e) => { console.error(e); process.exit(1); });
