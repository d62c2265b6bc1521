// Runs jobs in Babylon.js in headless Chromium: node run.mjs JOB.json
//
// JOB.json: { "data": dir served at /data/, "out": dir the images go to,
//             "jobs": [{ "name", "fn": "skybox" | "spheres", ...args }] }
// Each job's images are written to OUT/NAME_K.f32 (RGBA32F, rows
// top-down), a picture to OUT/NAME.png, its other results to
// OUT/NAME.json. Chromium is Debian's
// (/usr/bin/chromium, or $CHROMIUM), WebGL2 on SwiftShader; the exit
// status is non-zero when anything fails.
import http from "node:http";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { chromium } from "playwright-core";

const HERE = path.dirname(new URL(import.meta.url).pathname);
const TYPES = { ".js": "text/javascript", ".mjs": "text/javascript", ".html": "text/html",
  ".json": "application/json", ".wasm": "application/wasm" };

function serve(dataDir) {
  const srv = http.createServer((req, res) => {
    const u = new URL(req.url, "http://x");
    const p = decodeURIComponent(u.pathname);
    const [root, rel] = p.startsWith("/data/") ? [dataDir, p.slice(6)] : [HERE, p];
    const file = path.normalize(path.join(root, rel));
    if (!file.startsWith(path.normalize(root))) { res.writeHead(403); return res.end(); }
    fs.readFile(file, (err, data) => {
      if (err) { res.writeHead(404); return res.end("not found"); }
      res.writeHead(200, { "content-type": TYPES[path.extname(file)] || "application/octet-stream" });
      res.end(data);
    });
  });
  return new Promise((r) => srv.listen(0, "127.0.0.1", () => r(srv)));
}

const jobFile = process.argv[2];
if (!jobFile) { console.error("usage: node run.mjs JOB.json"); process.exit(2); }
const job = JSON.parse(fs.readFileSync(jobFile, "utf8"));
fs.mkdirSync(job.out, { recursive: true });
const srv = await serve(path.resolve(job.data));
const udd = fs.mkdtempSync(path.join(os.tmpdir(), "envmap-chromium-"));
const args = ["--headless", "--no-sandbox", "--disable-quic", "--no-first-run",
  "--disable-background-networking", "--disable-component-update", "--disable-sync",
  "--use-gl=angle", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"];
let status = 0;
const t0 = Date.now();
const context = await chromium.launchPersistentContext(udd, {
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium", headless: true, args });
try {
  const page = context.pages()[0] || await context.newPage();
  const log = [];
  page.on("console", (m) => log.push(`${m.type()}: ${m.text()}`));
  page.on("pageerror", (e) => log.push(`pageerror: ${e.message}`));
  page.setDefaultTimeout(600000);
  await page.goto(`http://127.0.0.1:${srv.address().port}/page.html`);
  await page.waitForFunction(() => window.pageReady === true);
  for (const j of job.jobs) {
    const t = Date.now();
    try {
      const res = await page.evaluate(({ fn, arg }) => window[fn](arg), { fn: j.fn, arg: j });
      res.images.forEach((b, k) => fs.writeFileSync(path.join(job.out, `${j.name}_${k}.f32`), Buffer.from(b, "base64")));
      delete res.images;
      if (res.png) {
        fs.writeFileSync(path.join(job.out, `${j.name}.png`), Buffer.from(res.png, "base64"));
        delete res.png;
      }
      res.seconds = (Date.now() - t) / 1000;
      fs.writeFileSync(path.join(job.out, `${j.name}.json`), JSON.stringify(res));
      console.log(`${j.name}: ${res.seconds.toFixed(1)} s`);
    } catch (e) {
      status = 1;
      console.error(`${j.name}: ${e.message}\n${log.slice(-20).join("\n")}`);
    }
  }
} finally {
  await context.close();
  srv.close();
  fs.rmSync(udd, { recursive: true, force: true });
}
console.log(`browser: ${((Date.now() - t0) / 1000).toFixed(1)} s`);
process.exit(status);
