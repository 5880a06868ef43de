// The live view's requests without a browser (tools/bench_live_view.sh's "requests" runs): the
// page's own schedule replayed with node's fetch, so that the cost of the requests (acqctl serve
// and acqd answering them) is measured apart from a browser's work on the capturing machine.
// The schedule is the page's (src/daemon/live_view.html): the status every 0.5 s; the frame when
// the frame count moved, or every 5 s; the file list every 4 s when the status changed, every
// 10 s regardless; each new thumbnail fetched once (as a browser showing the strip would: the
// page loads them lazily, so this asks for more than a page that is not scrolled).
// usage: node live_view_requests.js URL   (ends when acqd's session ends or acqd goes away)
const base = new URL(process.argv[2]);
const token = base.searchParams.get("token");
const get = async (path) => {
  const u = new URL(path, base);
  u.searchParams.set("token", token);
  const reply = await fetch(u);
  if (!reply.ok) throw new Error(path + ": HTTP " + reply.status);
  return path.startsWith("/api/file?") ? reply.arrayBuffer() : reply.json();
};
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
(async () => {
  let lastStatus = "", lastFrames = -1, frameAt = 0, listedStatus = "", listedAt = 0;
  let requests = 0;
  const thumbnails = new Set();
  for (;;) {
    const s = await get("/api/status");
    ++requests;
    const text = JSON.stringify(s);
    if (["done", "failed", "aborted", "stopped", "unreachable"].includes(s.state)) break;
    if (text !== lastStatus) lastStatus = text;
    if (s.frames !== lastFrames || Date.now() - frameAt > 5000) {
      lastFrames = s.frames;
      frameAt = Date.now();
      await get("/api/frame");
      ++requests;
    }
    const listDue = Date.now() - listedAt >= 4000 &&
        (lastStatus !== listedStatus || Date.now() - listedAt >= 10000);
    if (listDue) {
      listedStatus = lastStatus;
      listedAt = Date.now();
      const files = await get("/api/files");
      ++requests;
      for (const name of files.hdr || []) {
        if (thumbnails.has(name)) continue;
        thumbnails.add(name);
        await get("/api/file?path=hdr/" + encodeURIComponent(name));
        ++requests;
      }
    }
    await sleep(500);
  }
  console.log("requests replayed: " + requests + ", thumbnails: " + thumbnails.size);
})().catch((e) => { console.error(e.message || e); process.exit(1); });
