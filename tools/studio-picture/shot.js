// Loads a page in headless Chromium (Debian's, via playwright-core), waits,
// optionally clicks CLICK=x,y, and saves a screenshot:
//   node shot.js URL OUT.png WAIT_MS
const { chromium } = require("playwright-core");
(async () => {
  const [url, out, wait] = [process.argv[2], process.argv[3], Number(process.argv[4] || 8000)];
  const browser = await chromium.launch({
    executablePath: "/usr/bin/chromium",
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--use-gl=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"],
  });
  const page = await browser.newPage({ viewport: { width: 1400, height: 860 } });
  page.on("console", (m) => { if (m.type() === "error" || m.type() === "warning") console.log("console:", m.type(), m.text().slice(0, 300)); });
  page.on("pageerror", (e) => console.log("pageerror:", String(e).slice(0, 500)));
  await page.goto(url);
  await page.waitForTimeout(wait);
  if (process.env.CLICK) { const [x, y] = process.env.CLICK.split(",").map(Number); await page.mouse.click(x, y); await page.waitForTimeout(1500); }
  await page.screenshot({ path: out });
  if (process.argv[5]) { const fs = require("fs"); fs.writeFileSync(process.argv[5], await page.content()); }
  await browser.close();
})();
