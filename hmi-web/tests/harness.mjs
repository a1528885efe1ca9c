// Test harness: starts the HMI server (HMI_SERVER_CMD), drives it (HMI_DRIVER_CMD), watches its
// event stream from node, and launches Debian's chromium through playwright-core.
//
// Server contract for HMI_SERVER_CMD (run with `sh -c` in this folder, in its own process group):
//   - env HMI_PORT: the port to listen on (the same on every restart, so the page reconnects);
//   - env HMI_STATE_DIR: a directory kept across restarts (settings must persist there);
//   - env HMI_PIN: the pairing PIN the server must take (POST /api/pair), the same on every
//     restart; settings writes need the session cookie it gives (401 without);
//   - prints its base URL (e.g. http://127.0.0.1:43123) as the first line of stdout;
//   - stops on SIGTERM to its process group.
// Driver contract for HMI_DRIVER_CMD: `sh -c "$HMI_DRIVER_CMD <scene>"` with env HMI_URL and
// HMI_STATE_DIR (the server's); puts the vehicle into that scene and exits 0 once its inputs
// are being fed (non-zero: unknown scene).
// Every test runs against whichever server is given; none depends on a state only the
// development stand-in can produce (those tests were removed: see hmi-web/README.md).

import { spawn } from 'node:child_process';
import crypto from 'node:crypto';
import fs from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const TESTS_DIR = path.dirname(fileURLToPath(import.meta.url));
export const ARTIFACTS = path.join(TESTS_DIR, 'artifacts');
export const CHROMIUM = process.env.CHROMIUM_PATH || '/usr/bin/chromium';
const START_TIMEOUT_MS = Number(process.env.HMI_SERVER_START_TIMEOUT_MS || 60000);

export function env() {
  const server = process.env.HMI_SERVER_CMD;
  const driver = process.env.HMI_DRIVER_CMD;
  if (!server || !driver) {
    throw new Error('set HMI_SERVER_CMD and HMI_DRIVER_CMD (or run `npm test`: the real daemon through hil-sim)');
  }
  return { server, driver };
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function freePort() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.unref();
    s.on('error', reject);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

export class Server {
  constructor(cmd) {
    this.cmd = cmd;
    this.port = Number(process.env.HMI_PORT || 0) || null;
    this.stateDir = fs.mkdtempSync(path.join(os.tmpdir(), 'hmi-state-'));
    // A fresh PIN for every run: nothing in the tests can pair without being told it.
    this.pin = String(crypto.randomInt(0, 1000000)).padStart(6, '0');
    this.url = null;
    this.proc = null;
    fs.mkdirSync(ARTIFACTS, { recursive: true });
    this.log = fs.createWriteStream(path.join(ARTIFACTS, 'server.log'), { flags: 'a' });
  }

  async start() {
    if (!this.port) this.port = await freePort();
    const proc = spawn('sh', ['-c', this.cmd], {
      cwd: TESTS_DIR,
      detached: true,
      stdio: ['ignore', 'pipe', 'pipe'],
      env: { ...process.env, HMI_PORT: String(this.port), HMI_STATE_DIR: this.stateDir, HMI_PIN: this.pin },
    });
    this.proc = proc;
    proc.exited = new Promise((r) => proc.once('exit', r));
    proc.stderr.pipe(this.log, { end: false });
    const url = await firstLine(proc, START_TIMEOUT_MS);
    proc.stdout.pipe(this.log, { end: false });
    if (!/^https?:\/\/\S+$/.test(url)) throw new Error(`server printed ${JSON.stringify(url)}, not a URL`);
    const base = url.replace(/\/+$/, '');
    if (this.url && this.url !== base) throw new Error(`server came back on ${base}, not ${this.url}: the page cannot reconnect`);
    this.url = base;
    await waitHealthy(this.url, START_TIMEOUT_MS);
    return this.url;
  }

  async stop() {
    const proc = this.proc;
    if (!proc || proc.exitCode !== null || proc.signalCode !== null) return;
    try { process.kill(-proc.pid, 'SIGTERM'); } catch { /* gone */ }
    const done = await Promise.race([proc.exited.then(() => true), sleep(5000).then(() => false)]);
    if (!done) {
      try { process.kill(-proc.pid, 'SIGKILL'); } catch { /* gone */ }
      await proc.exited;
    }
    this.proc = null;
  }

  cleanup() {
    fs.rmSync(this.stateDir, { recursive: true, force: true });
    this.log.end();
  }
}

function firstLine(proc, timeoutMs) {
  return new Promise((resolve, reject) => {
    let buf = '';
    const timer = setTimeout(() => fail(new Error(`no URL on stdout within ${timeoutMs} ms`)), timeoutMs);
    const onData = (d) => {
      buf += d.toString();
      const i = buf.indexOf('\n');
      if (i >= 0) finish(buf.slice(0, i).trim());
    };
    const onExit = (code) => fail(new Error(`server exited (${code}) before printing its URL; see artifacts/server.log`));
    function finish(v) { cleanup(); resolve(v); }
    function fail(e) { cleanup(); reject(e); }
    function cleanup() {
      clearTimeout(timer);
      proc.stdout.off('data', onData);
      proc.off('exit', onExit);
    }
    proc.stdout.on('data', onData);
    proc.once('exit', onExit);
  });
}

async function waitHealthy(url, timeoutMs) {
  const until = Date.now() + timeoutMs;
  for (;;) {
    try {
      const r = await fetch(url + '/healthz', { signal: AbortSignal.timeout(1000) });
      if (r.ok && (await r.text()).trim() === 'ok') return;
    } catch { /* not up yet */ }
    if (Date.now() > until) throw new Error(`${url}/healthz not ok within ${timeoutMs} ms`);
    await sleep(100);
  }
}

/** Pairs with pin from node; resolves to the `Cookie` header value of the session. */
export async function pairCookie(url, pin) {
  const r = await fetch(url + '/api/pair', {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ pin }),
  });
  if (r.status !== 200) throw new Error(`pairing answered ${r.status}: ${await r.text()}`);
  const set = r.headers.get('set-cookie') || '';
  const pair = set.split(';')[0];
  if (!pair.includes('=')) throw new Error(`no session cookie: ${JSON.stringify(set)}`);
  return pair;
}

/** Pairs a browser context (its request context shares the browser's cookies). */
export async function pairContext(ctx, url, pin) {
  const r = await ctx.request.post(url + '/api/pair', { data: { pin } });
  if (r.status() !== 200) throw new Error(`pairing answered ${r.status()}: ${await r.text()}`);
}

/** Runs the driver for one scene; resolves when it exits 0, rejects with its stderr otherwise. */
export function drive(url, scene, cmd = env().driver, stateDir = '') {
  return new Promise((resolve, reject) => {
    const p = spawn('sh', ['-c', `${cmd} ${scene}`], {
      cwd: TESTS_DIR,
      stdio: ['ignore', 'ignore', 'pipe'],
      env: { ...process.env, HMI_URL: url, HMI_STATE_DIR: stateDir },
    });
    let err = '';
    p.stderr.on('data', (d) => { err += d; });
    const timer = setTimeout(() => p.kill('SIGKILL'), 30000);
    p.on('exit', (code) => {
      clearTimeout(timer);
      if (code === 0) resolve();
      else reject(new Error(`driver "${scene}" exited ${code}: ${err.trim()}`));
    });
  });
}

/** Follows /events from node: the reference clock for "the server sent it". */
export function watchEvents(url) {
  const ctrl = new AbortController();
  const waiters = new Set();
  const listeners = new Set();
  const w = {
    last: null,
    count: 0,
    close: () => ctrl.abort(),
    /** Calls fn(msg) for every state from now on; returns a function that stops it. */
    listen(fn) {
      listeners.add(fn);
      return () => listeners.delete(fn);
    },
    /** The first state from now on that satisfies pred: { msg, t } with t = performance.now(). */
    waitFor(pred, timeoutMs = 5000, what = 'state') {
      return new Promise((resolve, reject) => {
        const waiter = { pred, resolve };
        waiter.timer = setTimeout(() => {
          waiters.delete(waiter);
          reject(new Error(`no ${what} within ${timeoutMs} ms; last: ${JSON.stringify(w.last && w.last.msg.state)}`));
        }, timeoutMs);
        waiters.add(waiter);
      });
    },
  };
  (async () => {
    const res = await fetch(url + '/events', { signal: ctrl.signal, headers: { Accept: 'text/event-stream' } });
    const dec = new TextDecoder();
    let buf = '';
    for await (const chunk of res.body) {
      buf += dec.decode(chunk, { stream: true });
      let i;
      while ((i = buf.search(/\r?\n\r?\n/)) >= 0) {
        const block = buf.slice(0, i);
        buf = buf.slice(i).replace(/^\r?\n\r?\n/, '');
        onBlock(block);
      }
    }
  })().catch(() => {});
  function onBlock(block) {
    let event = 'message';
    const data = [];
    for (const line of block.split(/\r?\n/)) {
      if (line.startsWith(':')) continue;
      const [k, ...rest] = line.split(':');
      const v = rest.join(':').replace(/^ /, '');
      if (k === 'event') event = v;
      else if (k === 'data') data.push(v);
    }
    if (event !== 'state' || !data.length) return;
    const msg = JSON.parse(data.join('\n'));
    const t = performance.now();
    w.last = { msg, t };
    w.count += 1;
    for (const fn of listeners) fn(msg);
    for (const waiter of waiters) {
      if (waiter.pred(msg)) {
        clearTimeout(waiter.timer);
        waiters.delete(waiter);
        waiter.resolve({ msg, t });
      }
    }
  }
  return w;
}

/** Headless Debian chromium with a fresh profile. */
export async function launch({ autoplay = false, viewport = { width: 1280, height: 800 }, colorScheme = 'light' } = {}) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'hmi-chromium-'));
  const args = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'];
  if (autoplay) args.push('--autoplay-policy=no-user-gesture-required');
  const ctx = await chromium.launchPersistentContext(dir, {
    executablePath: CHROMIUM, headless: true, args, viewport, colorScheme, deviceScaleFactor: 1,
  });
  const close = ctx.close.bind(ctx);
  ctx.close = async () => {
    await close();
    fs.rmSync(dir, { recursive: true, force: true });
  };
  return ctx;
}

/** A page on url that records uncaught errors. */
export async function openPage(ctx, url) {
  const page = ctx.pages()[0] || (await ctx.newPage());
  page.errors = [];
  page.on('pageerror', (e) => page.errors.push(String(e)));
  await page.goto(url + '/');
  return page;
}

export function waitLive(page, timeout = 5000) {
  return page.waitForFunction(() => window.hmi && window.hmi.connection() === 'live', null, { timeout, polling: 50 });
}

export async function shot(page, name) {
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const file = path.join(ARTIFACTS, name + '.png');
  await page.screenshot({ path: file });
  return file;
}
