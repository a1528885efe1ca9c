// Writes the README screenshots: each stage on the tablet (1280x800) and the phone (390x844),
// into hmi-web/screenshots/<stage>-<tablet|phone>.png (device scale 1). Runs against the
// server of HMI_SERVER_CMD / HMI_DRIVER_CMD like the tests (`npm run screenshots` uses the
// real daemon), and fails when a screen overflows or shows more than one red element.
import path from 'node:path';
import fs from 'node:fs';
import { env, Server, drive, watchEvents, launch, openPage, waitLive, TESTS_DIR } from './harness.mjs';
import { STAGES, VIEWPORTS, overflowReport } from './screen.mjs';

const OUT = process.env.HMI_SCREENSHOTS_DIR || path.join(TESTS_DIR, '..', 'screenshots');
const cfg = env();
const server = new Server(cfg.server);
fs.mkdirSync(OUT, { recursive: true });
const problems = [];

async function capture(page, stage) {
  for (const vp of VIEWPORTS) {
    await page.setViewportSize({ width: vp.width, height: vp.height });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const over = await page.evaluate(overflowReport);
    const red = await page.evaluate(() => window.hmi.redElements());
    if (over.length) problems.push(`${stage} ${vp.name}: ${over.join('; ')}`);
    if (red > 1) problems.push(`${stage} ${vp.name}: ${red} red elements`);
    await page.screenshot({ path: path.join(OUT, `${stage}-${vp.name}.png`) });
    console.log(`${stage}-${vp.name}.png`);
  }
}

const url = await server.start();
const events = watchEvents(url);
const ctx = await launch({ autoplay: true });
try {
  const page = await openPage(ctx, url);
  await waitLive(page, 10000);
  for (const st of STAGES) {
    for (const [scene, ready] of st.steps) {
      const seen = ready ? events.waitFor((m) => ready(m.state), 15000, `${st.name}: ${scene}`) : null;
      await drive(url, scene, cfg.driver, server.stateDir);
      if (seen) await seen;
    }
    const { msg } = await events.waitFor((m) => st.pred(m.state), st.timeout || 10000, st.name);
    await page.waitForFunction((seq) => window.hmi.lastMessage() && window.hmi.lastMessage().seq >= seq, msg.seq, { timeout: 2000 });
    await page.waitForTimeout(300);
    await capture(page, st.name);
  }
  await drive(url, 'gnss_back', cfg.driver, server.stateDir);
  await drive(url, 'time_ok', cfg.driver, server.stateDir);
  await drive(url, 'warning', cfg.driver, server.stateDir);
  await page.waitForTimeout(1500);
  await server.stop();
  await page.waitForFunction(() => document.getElementById('alert-title').textContent === 'Disconnected', null, { timeout: 5000 });
  await page.waitForTimeout(1200);
  await capture(page, 'disconnected');
} finally {
  events.close();
  await ctx.close();
  await server.stop();
  server.cleanup();
}
if (problems.length) {
  console.error(problems.join('\n'));
  process.exit(1);
}
