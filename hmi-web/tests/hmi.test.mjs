// Browser tests of the driver display against the server given by HMI_SERVER_CMD, driven through
// HMI_DRIVER_CMD (see harness.mjs for both contracts): `npm test` runs them against the real daemon.
import { describe, it, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { env, Server, drive, watchEvents, launch, openPage, waitLive, shot, sleep, pairCookie, pairContext } from './harness.mjs';
import { STAGES, LAYOUTS, overflowReport } from './screen.mjs';

const SCREEN_MS = 500;                                            // server sent it -> on screen
const GNSS_MS = Number(process.env.HMI_GNSS_DEADLINE_MS || 1000); // dropout -> "No GNSS" on screen
const STALE_MS = 1500;

const cfg = env();
const server = new Server(cfg.server);
let url;
let ctx;      // default autoplay policy: sound needs a tap, as on a real tablet
let page;
let events;
let cookie;   // a session of node's own, for writes made with fetch

const go = (scene) => drive(url, scene, cfg.driver, server.stateDir);

/** Waits until the page shows msg: zone state, primary alert kind and speed text. */
async function onScreen(p, msg, timeout = 2000) {
  await p.waitForFunction((m) => {
    const s = m.state;
    const kind = s.primary ? s.primary.kind : null;
    const b = document.getElementById('alert-banner').dataset.kind;
    return window.hmi.connection() === 'live' && document.body.dataset.zone === s.zone_state &&
      (kind ? b === kind : b === 'none');
  }, msg, { timeout, polling: 'raf' });
}

/** Runs the driver steps of a stage scene; resolves with the first state of the stage. */
async function reach(stage) {
  for (const [scene, ready] of stage.steps) {
    const seen = ready ? events.waitFor((m) => ready(m.state), 15000, `${stage.name}: ${scene}`) : null;
    await go(scene);
    if (seen) await seen;
  }
  // the stage must still hold 0.5 s later (a scene switch passes through other states;
  // the daemon sends a state only when something changes)
  const until = performance.now() + (stage.timeout || 10000);
  for (;;) {
    const left = Math.max(1, until - performance.now());
    const first = await events.waitFor((m) => stage.pred(m.state), left, stage.name);
    await sleep(500);
    if (stage.pred(events.last.msg.state)) return events.last;
    if (performance.now() > until) return first;
  }
}

/** Waits until page p has rendered the state with sequence number seq (or a later one). */
function shown(p, seq) {
  return p.waitForFunction((n) => window.hmi.lastMessage() && window.hmi.lastMessage().seq >= n &&
    window.hmi.connection() === 'live', seq, { timeout: 2000, polling: 'raf' });
}

/** No element overflows or is cut, and at most one element is red: at each viewport. */
async function checkLayouts(p, label, extra = async () => {}) {
  for (const vp of LAYOUTS) {
    await p.setViewportSize({ width: vp.width, height: vp.height });
    await p.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const over = await p.evaluate(overflowReport);
    assert.deepEqual(over, [], `${label} at ${vp.width}x${vp.height}: nothing cut or overflowing`);
    const red = await p.evaluate(() => ({ n: window.hmi.redElements(), list: window.hmi.redList(), state: window.hmi.lastState() }));
    assert.ok(red.n <= 1, `${label} at ${vp.width}x${vp.height}: ${red.n} red elements (${red.list.join(', ')})`);
    const scroll = await p.evaluate(() => [document.scrollingElement.scrollWidth, document.scrollingElement.scrollHeight]);
    assert.ok(scroll[0] <= vp.width && scroll[1] <= vp.height, `${label}: no scrolling (${scroll})`);
    // every other alert is a visible chip, or counted in the "+N" chip
    const chips = await p.evaluate(() => {
      const shown = [...document.querySelectorAll('#others .other')].filter((c) => c.checkVisibility());
      const more = shown.find((c) => c.dataset.kind === 'more');
      return { shown: shown.length - (more ? 1 : 0), more: more ? Number(more.textContent.replace('+', '')) : 0,
        live: window.hmi.connection() === 'live' && document.body.dataset.view === 'drive', others: (window.hmi.lastState() || {}).others || [] };
    });
    if (chips.live) assert.equal(chips.shown + chips.more, chips.others.length, `${label} at ${vp.width}x${vp.height}: every alert chip shown or in "+N"`);
    await extra(vp, red.n, red.state);
    await shot(p, `${label}-${vp.name}`);
  }
}

/** Drives a scene, waits for the server to send a state matching pred, then for the screen. */
async function sceneOnScreen(scene, pred, what) {
  const seen = events.waitFor(pred, 10000, what);
  await go(scene);
  const { msg, t } = await seen;
  await onScreen(page, msg);
  return { msg, latency: performance.now() - t };
}

before(async () => {
  url = await server.start();
  events = watchEvents(url);
  ctx = await launch();
  // The main browser is a paired tablet; the pairing test below uses a fresh one.
  await pairContext(ctx, url, server.pin);
  cookie = await pairCookie(url, server.pin);
  page = await openPage(ctx, url);
  await waitLive(page, 10000);
});

after(async () => {
  if (events) events.close();
  if (ctx) await ctx.close();
  await server.stop();
  server.cleanup();
});

describe('driver display', () => {
  it('renders the live view (1280x800, no scroll, large touch targets, no errors)', async () => {
    const r = await fetch(url + '/healthz');
    assert.equal((await r.text()).trim(), 'ok');
    await sceneOnScreen('cruise', (m) => m.state.zone_state === 'None' && m.state.gnss_ok, 'cruise state');
    const info = await page.evaluate(() => {
      const vis = (id) => { const b = document.getElementById(id).getBoundingClientRect(); return { x: b.x, y: b.y, w: b.width, h: b.height }; };
      const buttons = [...document.querySelectorAll('button')].filter((b) => b.offsetParent).map((b) => b.getBoundingClientRect());
      return {
        speed: document.getElementById('speed').textContent,
        limit: document.getElementById('limit-value').textContent,
        lanes: document.querySelectorAll('#lanes .lane').length,
        car: document.querySelectorAll('#lanes .car').length,
        scrollW: document.scrollingElement.scrollWidth, scrollH: document.scrollingElement.scrollHeight,
        boxes: ['speed', 'limit', 'alert-banner', 'lanes', 'distance-box'].map(vis),
        minButton: Math.min(...buttons.map((b) => Math.min(b.width, b.height))),
        ariaLive: document.getElementById('alert-banner').getAttribute('aria-live'),
      };
    });
    const s = events.last.msg.state;
    assert.match(info.speed, /^\d+$/);
    if (s.speed_limit_mps !== null) assert.match(info.limit, /^\d+$/);
    assert.equal(info.ariaLive, 'assertive');
    assert.ok(info.lanes >= (s.road_lanes || []).length, 'one lane per road lane');
    assert.equal(info.car, s.lane ? 1 : 0);
    assert.ok(info.scrollW <= 1280 && info.scrollH <= 800, `no scrolling: ${info.scrollW}x${info.scrollH}`);
    for (const b of info.boxes) assert.ok(b.w > 0 && b.x >= 0 && b.y >= 0 && b.x + b.w <= 1280 && b.y + b.h <= 800, JSON.stringify(b));
    assert.ok(info.minButton >= 48, `touch targets >= 48 px (smallest ${info.minButton})`);
    assert.deepEqual(page.errors, []);
    await shot(page, 'normal');
  });

  it('a state change reaches the screen within 500 ms', async () => {
    const latencies = {};
    const steps = [
      ['approach', (m) => m.state.zone_state === 'Approaching'],
      ['warning', (m) => m.state.zone_state === 'Warning'],
      ['cruise', (m) => m.state.zone_state === 'None'],
    ];
    for (const [scene, pred] of steps) {
      const { latency } = await sceneOnScreen(scene, pred, scene);
      latencies[scene] = Math.round(latency);
    }
    console.log('# server -> screen latency (ms):', JSON.stringify(latencies));
    for (const [scene, ms] of Object.entries(latencies)) assert.ok(ms <= SCREEN_MS, `${scene}: ${ms} ms`);
  });

  it('sound needs one tap on a real tablet, then stays on', async () => {
    const before = await page.evaluate(() => ({ audio: window.hmi.audioState(), button: !document.getElementById('sound-enable').hidden, sound: window.hmi.settings().sound }));
    assert.equal(before.sound, true, 'sound is on by default');
    assert.notEqual(before.audio, 'running', 'no sound before a gesture under the default autoplay policy');
    assert.equal(before.button, true, '"Enable sound" shown');
    await page.click('#sound-enable');
    await page.waitForFunction(() => window.hmi.audioState() === 'running', null, { timeout: 2000 });
    assert.equal(await page.isHidden('#sound-enable'), true, 'button gone once running');
    assert.equal(await page.evaluate(() => localStorage.getItem('hmi.sound.unlocked')), '1', 'choice remembered');
  });

  it('tone: Warning plays one group when entered, not again; Urgent repeats every 2 s and stops when the stage drops', async () => {
    const actx = await launch({ autoplay: true });
    const stages = [];
    let stop = events.listen((m) => stages.push(m.state.stage));
    try {
      // record every oscillator frequency the page sets (the tone must be in the 1-5 kHz band)
      await actx.addInitScript(() => {
        const create = AudioContext.prototype.createOscillator;
        window.__freqs = [];
        AudioContext.prototype.createOscillator = function () {
          const o = create.call(this);
          queueMicrotask(() => window.__freqs.push(o.frequency.value));
          return o;
        };
      });
      const p = await openPage(actx, url);
      await waitLive(p);
      assert.equal(await p.evaluate(() => window.hmi.audioState()), 'running');
      const tones = () => p.evaluate(() => window.hmi.tonesScheduled());
      const calm = events.waitFor((m) => m.state.stage === 'None' && m.state.zone_state === 'None', 10000, 'stage None');
      await go('cruise');
      await shown(p, (await calm).msg.seq);
      await sleep(300);
      const n0 = await tones();

      // Warning: exactly one group on entering, none again within 5 s
      stages.length = 0;
      const warn = events.waitFor((m) => m.state.stage === 'Warning', 10000, 'stage Warning');
      await go('warning');
      const { msg } = await warn;
      await shown(p, msg.seq);
      const banner = await p.evaluate(() => {
        const b = document.getElementById('alert-banner');
        return { cls: b.className, live: b.getAttribute('aria-live'), stage: b.dataset.stage, title: document.getElementById('alert-title').textContent };
      });
      assert.match(banner.cls, /sev-red/, 'Warning is red');
      assert.equal(banner.stage, 'Warning');
      assert.equal(banner.live, 'assertive');
      await p.waitForFunction((n) => window.hmi.tonesScheduled() === n + 1, n0, { timeout: 1000 });
      await sleep(5000);
      const entries = stages.filter((st, i) => st === 'Warning' && (i === 0 || ['None', 'Information'].includes(stages[i - 1]))).length;
      assert.equal(entries, 1, `the warning scene holds Warning (stages seen: ${[...new Set(stages)]})`);
      assert.ok(stages.every((st) => st === 'Warning' || st === 'None' || st === 'Information'), 'no Urgent in the warning scene');
      assert.equal(await tones(), n0 + 1, 'one group for entering Warning, no repeat within 5 s');
      await shot(p, 'warning');

      // Urgent: a group at once, then every 2 s
      const urg = events.waitFor((m) => m.state.stage === 'Urgent', 10000, 'stage Urgent');
      await go('urgent');
      await shown(p, (await urg).msg.seq);
      assert.equal(await p.getAttribute('#alert-banner', 'data-stage'), 'Urgent');
      const n1 = await tones();
      assert.ok(n1 >= n0 + 2, 'a group at once on entering Urgent');
      await sleep(4300);
      const n2 = await tones();
      assert.ok(n2 >= n1 + 2, `Urgent repeats every 2 s: ${n1} -> ${n2} in 4.3 s`);
      const freqs = await p.evaluate(() => window.__freqs);
      assert.ok(freqs.length >= 2 && freqs.every((f) => f >= 1000 && f <= 5000), `tone frequencies ${freqs}`);
      await shot(p, 'urgent');

      // the link is lost: the tone stops at once; back in the same Urgent it repeats again
      await server.stop();
      await p.waitForFunction(() => window.hmi.connection() !== 'live', null, { timeout: 3000, polling: 50 });
      const nLost = await tones();
      await sleep(2500);
      assert.equal(await tones(), nLost, 'no tone while the link is lost');
      await server.start();
      events.close();
      events = watchEvents(url);
      stop = events.listen((m) => stages.push(m.state.stage));
      await waitLive(p, 10000);
      await p.waitForFunction((n) => window.hmi.tonesScheduled() > n, nLost, { timeout: 3000 });

      // the driver complies (Urgent -> Warning): the tone stops at once, no new group
      stages.length = 0;
      const back = events.waitFor((m) => m.state.stage === 'Warning', 10000, 'back to Warning');
      await go('warning');
      await shown(p, (await back).msg.seq);
      const n3 = await tones();
      await sleep(3000);
      assert.ok(!stages.slice(stages.indexOf('Warning')).includes('Urgent'), `the stage stayed below Urgent (${[...new Set(stages)]})`);
      assert.equal(await tones(), n3, 'no tone after Urgent dropped to Warning');
      const cleared = events.waitFor((m) => m.state.stage === 'None', 10000, 'stage None');
      await go('cruise');
      await shown(p, (await cleared).msg.seq);
      const n4 = await tones();
      await sleep(2500);
      assert.equal(await tones(), n4, 'silence once the warning cleared');
    } finally {
      stop();
      await actx.close();
    }
  });

  it('lane closed: hatched closed lane with cones, the car in it, change-lane advice', async () => {
    const { msg } = await sceneOnScreen('lane_closed', (m) => m.state.primary && m.state.primary.kind === 'LaneClosedOwn', 'LaneClosedOwn');
    const s = msg.state;
    const d = await page.evaluate(() => ({
      closed: [...document.querySelectorAll('#lanes g.lane.closed')].map((g) => Number(g.dataset.laneId)),
      hatch: document.querySelectorAll('#lanes g.lane.closed rect[fill="url(#hatch)"]').length,
      cones: document.querySelectorAll('#lanes .cone').length,
      carOnClosed: document.querySelectorAll('#lanes .car.on-closed').length,
      advice: (document.querySelector('#lanes .advice') || {}).dataset,
      title: document.getElementById('alert-title').textContent,
      sev: document.getElementById('alert-banner').className,
    }));
    assert.deepEqual(d.closed.sort(), [...s.closed_lanes].sort());
    assert.ok(d.hatch >= 1 && d.cones >= 1, 'hatched with cones');
    assert.equal(d.carOnClosed, 1, 'the car is drawn in the closed lane');
    assert.match(d.sev, /sev-red/);
    // The scene's car is in a closed lane with an open one beside it: advice is given.
    assert.notEqual(s.advice, 'None', 'change-lane advice in the lane_closed scene');
    assert.equal(d.advice && d.advice.advice, s.advice);
    assert.equal(d.title, s.advice === 'MoveLeft' ? 'Change lane left' : 'Change lane right');
    await shot(page, 'lane_closed');
  });

  it('overspeed: red banner; the speed alarm is not a second red element', async () => {
    const { msg } = await sceneOnScreen('overspeed', (m) => m.state.primary && m.state.primary.kind === 'Overspeed' && m.state.speed_alarm, 'Overspeed');
    assert.equal(msg.state.stage, 'Urgent');
    assert.match(await page.getAttribute('#alert-banner', 'class'), /sev-red/);
    assert.equal(await page.getAttribute('#speed-box', 'data-alarm'), 'muted', 'under a red banner the speed alarm is amber');
    assert.equal(await page.evaluate(() => window.hmi.redElements()), 1);
    await shot(page, 'overspeed');
  });

  it('speed alarm without a red banner: the speed is the one red element', async () => {
    const { msg } = await sceneOnScreen('speeding', (m) => m.state.speed_alarm && m.state.stage === 'None' && !m.state.primary, 'speed alarm, no alert');
    assert.equal(msg.state.zone_state, 'None');
    assert.equal(await page.getAttribute('#speed-box', 'data-alarm'), 'red');
    assert.equal(await page.getAttribute('#alert-banner', 'data-red'), 'false');
    assert.deepEqual(await page.evaluate(() => window.hmi.redList()), ['speed-box']);
    await shot(page, 'speeding');
  });

  it('in zone: "IN ZONE" and the reduced-limit sign', async () => {
    const { msg } = await sceneOnScreen('in_zone', (m) => m.state.zone_state === 'InZone', 'InZone');
    assert.equal(await page.textContent('#distance'), 'IN ZONE');
    // The scene's work zone has a reduced speed limit, so the sign must show it.
    assert.ok(msg.state.reduced_limit, 'the in_zone state has a reduced limit');
    assert.equal(await page.getAttribute('#limit', 'data-reduced'), 'true');
    assert.equal(await page.isVisible('.limit-plate'), true);
    // The bench roadside signs (IEEE 1609.2) and the unit requires it: marked signed.
    assert.equal(msg.state.unverified, 0, 'every zone shown came verified');
    assert.equal(await page.getAttribute('#rsu-chip', 'data-trust'), 'signed');
    assert.match(await page.textContent('#rsu-chip'), /signed/);
    await shot(page, 'in_zone');
  });

  it('"No GNSS" within 1 s of a dropout, "Position lost" (never green) past dead reckoning, and back', async () => {
    await sceneOnScreen('cruise', (m) => m.state.gnss_ok && m.state.zone_state === 'None', 'cruise');
    await go('gnss_lost');
    const t0 = performance.now();
    await page.waitForFunction(() => document.getElementById('gnss-chip').textContent.includes('No GNSS') &&
      document.body.dataset.gnss === 'lost', null, { timeout: 5000, polling: 'raf' });
    const ms = Math.round(performance.now() - t0);
    console.log(`# dropout -> "No GNSS" on screen: ${ms} ms`);
    assert.ok(ms <= GNSS_MS, `${ms} ms > ${GNSS_MS} ms`);
    const lost = await events.waitFor((m) => m.state.position === 'Lost', 15000, 'position Lost');
    await shown(page, lost.msg.seq);
    assert.equal(await page.textContent('#distance-label'), 'Position lost', 'no distance claimed without a position');
    assert.equal(await page.textContent('#alert-title'), 'Position lost');
    assert.doesNotMatch(await page.getAttribute('#alert-banner', 'class'), /sev-calm/, 'never green without a position');
    await shot(page, 'no_gnss');
    await go('gnss_back');
    await page.waitForFunction(() => document.body.dataset.gnss === 'ok', null, { timeout: 5000 });
  });

  for (const stage of STAGES) {
    it(`stage scene "${stage.name}": nothing cut at 360-430 px wide and 1280x800, one red element at most`, async () => {
      const p = await ctx.newPage();
      try {
        await p.setViewportSize({ width: 1280, height: 800 });
        await p.goto(url + '/');
        await waitLive(p);
        const { msg } = await reach(stage);
        await shown(p, msg.seq);
        await sleep(200);
        await checkLayouts(p, 'stage_' + stage.name, async (vp, red, s) => {
          assert.ok(stage.pred(s), `${stage.name}: the page still shows the stage (${JSON.stringify(s)})`);
          const d = await p.evaluate(() => {
            const b = document.getElementById('alert-banner');
            const vis = (id) => document.getElementById(id).checkVisibility();
            return { cls: b.className, red: b.dataset.red, stage: b.dataset.stage, title: document.getElementById('alert-title').textContent,
              label: document.getElementById('distance-label').textContent, distance: document.getElementById('distance').textContent,
              approx: vis('distance-approx'), marker: vis('pos-marker'), time: vis('time-chip'), timeText: document.getElementById('time-chip').textContent,
              speed: document.getElementById('speed').textContent, speedColor: getComputedStyle(document.getElementById('speed')).color,
              dim: getComputedStyle(document.documentElement).getPropertyValue('--dim').trim(),
              soundShown: vis('sound-state') || vis('sound-enable') };
          });
          const where = `${stage.name} ${vp.width}x${vp.height}`;
          assert.ok(d.soundShown, `${where}: sound status visible`);
          const bannerRed = s.stage === 'Warning' || s.stage === 'Urgent';
          assert.equal(d.red === 'true', bannerRed, `${where}: the banner is red exactly at Warning/Urgent (${s.stage})`);
          assert.equal(red, bannerRed || s.speed_alarm ? 1 : 0, `${where}: red elements`);
          if (s.stage === 'Information') assert.match(d.cls, /sev-amber/, `${where}: Information is amber`);
          if (s.speed_mps === null) assert.equal(d.speed, '--', `${where}: a stale speed is not shown as a number`);
          switch (stage.name) {
            case 'warning': assert.equal(d.stage, 'Warning'); break;
            case 'urgent': assert.equal(d.stage, 'Urgent'); break;
            case 'in_zone': assert.equal(d.distance, 'IN ZONE'); break;
            case 'estimated':
              assert.ok(d.marker, `${where}: ESTIMATED POSITION marker`);
              if (typeof s.distance_m === 'number' && s.distance_m > 0) assert.ok(d.approx && /^\d/.test(d.distance), `${where}: ≈ distance`);
              break;
            case 'lost':
              assert.equal(d.title, 'Position lost');
              assert.equal(d.label, 'Position lost');
              assert.doesNotMatch(d.cls, /sev-calm/);
              assert.equal(d.distance, '');
              break;
            case 'time_unverified':
              assert.ok(d.time && d.timeText.includes('Time unverified'), `${where}: "Time unverified" shown`);
              assert.notEqual(await p.getAttribute('#alert-banner', 'data-kind'), 'none', 'the zone is still shown');
              break;
            default: break;
          }
        });
        if (stage.name === 'urgent') {
          assert.match(await p.evaluate(() => getComputedStyle(document.getElementById('alert-banner')).animationName), /urgent-pulse/);
          await p.emulateMedia({ reducedMotion: 'reduce' });
          assert.equal(await p.evaluate(() => getComputedStyle(document.getElementById('alert-banner')).animationName), 'none', 'no pulse with reduced motion');
        }
        assert.deepEqual(p.errors || [], []);
      } finally {
        await p.close();
      }
      await go('gnss_back');
      await go('time_ok');
    });
  }

  it('"Disconnected" when the server stops; live again after it restarts', async () => {
    await waitLive(page);
    await server.stop();
    const t0 = performance.now();
    await page.waitForFunction(() => window.hmi.connection() !== 'live' &&
      document.getElementById('alert-title').textContent === 'Disconnected', null, { timeout: 5000, polling: 50 });
    const ms = Math.round(performance.now() - t0);
    assert.ok(ms <= STALE_MS + 500, `disconnected shown after ${ms} ms`);
    const grey = await page.evaluate(() => {
      const css = getComputedStyle(document.documentElement);
      return { speed: getComputedStyle(document.getElementById('speed')).color, others: getComputedStyle(document.getElementById('others')).visibility,
        dim: css.getPropertyValue('--dim').trim(), filter: getComputedStyle(document.getElementById('lanes')).filter };
    });
    assert.match(grey.filter, /grayscale/);
    assert.equal(grey.others, 'hidden');
    await sleep(1200);
    await shot(page, 'disconnected');
    await checkLayouts(page, 'stage_disconnected');
    await page.setViewportSize({ width: 1280, height: 800 });
    await server.start();
    const t1 = performance.now();
    await waitLive(page, 5000);
    console.log(`# server up -> live again: ${Math.round(performance.now() - t1)} ms`);
    events.close();
    events = watchEvents(url);
    assert.notEqual(await page.textContent('#alert-title'), 'Disconnected');
  });

  it('offline: a reload without the unit opens the app (its own "Disconnected" screen), which goes live by itself when the unit is back', async () => {
    const types = {};
    for (const f of ['manifest.webmanifest', 'sw.js', 'icon.svg', 'icon-maskable.svg']) {
      const r = await fetch(url + '/' + f);
      assert.equal(r.status, 200, f);
      types[f] = r.headers.get('content-type');
      if (f === 'sw.js') assert.doesNotMatch(await r.text(), /@HMI_SHELL_VERSION@/, 'the shell version is stamped in');
    }
    assert.match(types['manifest.webmanifest'], /^application\/manifest\+json/);
    assert.match(types['sw.js'], /^text\/javascript/);
    assert.match(types['icon.svg'], /^image\/svg\+xml/);
    const octx = await launch();
    try {
      const p = await openPage(octx, url);
      await waitLive(p);
      const sw = await p.evaluate(async () => {
        const reg = await navigator.serviceWorker.ready;
        return { scope: reg.scope, script: reg.active && reg.active.scriptURL };
      });
      assert.equal(sw.scope, url + '/');
      assert.equal(sw.script, url + '/sw.js');
      await p.waitForFunction(() => !!navigator.serviceWorker.controller, null, { timeout: 5000 });
      // the live data never comes from the cache
      const cached = await p.evaluate(async () => {
        const names = await caches.keys();
        const out = [];
        for (const n of names) out.push(...(await (await caches.open(n)).keys()).map((r) => new URL(r.url).pathname));
        return { names, paths: out };
      });
      assert.ok(cached.names.length === 1 && cached.names[0].startsWith('hmi-shell-'), `one versioned cache: ${cached.names}`);
      assert.ok(cached.paths.includes('/index.html') && cached.paths.includes('/app.js'), `the shell is cached: ${cached.paths}`);
      assert.ok(!cached.paths.some((x) => x === '/events' || x.startsWith('/api/')), `no live data cached: ${cached.paths}`);
      await server.stop();
      await p.reload();
      await p.waitForFunction(() => window.hmi && document.getElementById('alert-banner').dataset.kind === 'disconnected' &&
        document.getElementById('alert-title').textContent === 'Disconnected', null, { timeout: 8000 });
      assert.equal(await p.evaluate(() => window.hmi.connection()), 'disconnected');
      await shot(p, 'offline_reload');
      await server.start();
      events.close();
      events = watchEvents(url);
      await waitLive(p, 10000);
      const seq = (await events.waitFor(() => true, 5000)).msg.seq;
      await shown(p, seq);
      assert.notEqual(await p.textContent('#alert-title'), 'Disconnected');
    } finally {
      await octx.close();
    }
  });

  it('accessibility: zoom allowed, one h1, landmarks; night theme without glare', async () => {
    const a = await page.evaluate(() => ({
      viewport: document.querySelector('meta[name=viewport]').content,
      h1: document.querySelectorAll('h1').length,
      header: document.querySelectorAll('header').length,
      main: document.querySelectorAll('main').length,
      nav: document.querySelectorAll('nav').length,
      manifest: !!document.querySelector('link[rel=manifest]'),
    }));
    assert.doesNotMatch(a.viewport, /user-scalable\s*=\s*(no|0)|maximum-scale\s*=\s*1(\.0)?\b/);
    assert.equal(a.h1, 1, 'exactly one h1');
    assert.ok(a.header === 1 && a.main === 1 && a.nav >= 1, JSON.stringify(a));
    assert.ok(a.manifest);
    await page.evaluate(() => { document.documentElement.dataset.theme = 'night'; });
    const night = await page.evaluate(() => {
      const f = (sel) => getComputedStyle(document.querySelector(sel)).filter;
      const white = [...document.querySelectorAll('body *')].filter((el) => el.checkVisibility() && !el.closest('svg') &&
        getComputedStyle(el).backgroundColor === 'rgb(255, 255, 255)').map((el) => el.id || el.className);
      return { sign: f('#limit .limit-sign'), icon: f('.banner-icon'), white };
    });
    await page.evaluate(() => window.dispatchEvent(new Event('resize')));
    assert.match(night.sign, /brightness\(0?\.75\)/, 'the sign is dimmed at night');
    assert.match(night.icon, /brightness\(0?\.75\)/, 'icons are dimmed at night');
    assert.deepEqual(night.white, [], 'no pure white areas at night');
    await page.evaluate((t) => { document.documentElement.dataset.theme = t; }, 'day');
  });

  it('pairing: an unpaired tablet is asked for the PIN once; a wrong PIN is refused, the right one pairs and the write goes through', async () => {
    const before = await (await fetch(url + '/api/settings')).json();
    const unpaired = await fetch(url + '/api/settings', { method: 'PUT', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ ...before, warning_distance_m: 130 }) });
    assert.equal(unpaired.status, 401, 'a write without a session');
    const tctx = await launch();
    try {
      const p = await openPage(tctx, url);
      await waitLive(p);
      await p.click('#nav-settings');
      await p.waitForSelector('#settings:not([hidden])');
      await p.waitForFunction(() => document.getElementById('set-distance').value !== '');
      await p.fill('#set-distance', '130');
      await p.click('#settings-save');
      await p.waitForSelector('#pair-dialog[open]', { timeout: 5000 });
      assert.match(await p.textContent('#settings-msg'), /not paired/);
      // A wrong PIN: refused, the dialog stays, nothing saved.
      const wrong = server.pin === '000000' ? '111111' : '000000';
      await p.fill('#pair-pin', wrong);
      await p.click('#pair-submit');
      await p.waitForFunction(() => /Wrong PIN/.test(document.getElementById('pair-msg').textContent), null, { timeout: 5000 });
      assert.match(await p.textContent('#pair-msg'), /4 tries left/);
      assert.equal(await p.evaluate(() => document.getElementById('pair-dialog').open), true);
      assert.equal((await (await fetch(url + '/api/settings')).json()).warning_distance_m, before.warning_distance_m);
      await shot(p, 'pairing');
      // The right PIN: paired, and the write it was asked for goes through.
      await p.fill('#pair-pin', server.pin);
      await p.click('#pair-submit');
      await p.waitForFunction(() => !document.getElementById('pair-dialog').open &&
        document.getElementById('settings-msg').textContent === 'Saved.', null, { timeout: 5000 });
      assert.equal((await (await fetch(url + '/api/settings')).json()).warning_distance_m, 130);
      // The session is an HttpOnly, SameSite=Strict cookie the page cannot read.
      const session = (await tctx.cookies(url)).find((c) => c.name === 'obu_session');
      assert.ok(session, 'a session cookie');
      assert.equal(session.httpOnly, true);
      assert.equal(session.sameSite, 'Strict');
      assert.equal(session.value.length, 64, '256 bits');
      assert.equal(await p.evaluate(() => document.cookie.includes('obu_session')), false);
      // Paired once: the next write asks for nothing (and puts the distance back).
      let dialogs = 0;
      await p.exposeFunction('__pairDialogShown', () => { dialogs += 1; });
      await p.evaluate(() => new MutationObserver(() => {
        if (document.getElementById('pair-dialog').open) window.__pairDialogShown();
      }).observe(document.getElementById('pair-dialog'), { attributes: true }));
      await p.fill('#set-distance', String(before.warning_distance_m));
      await p.click('#settings-save');
      await p.waitForFunction(() => document.getElementById('settings-msg').textContent === 'Saved.', null, { timeout: 5000 });
      assert.equal(dialogs, 0, 'no PIN asked for a second time');
      assert.equal((await (await fetch(url + '/api/settings')).json()).warning_distance_m, before.warning_distance_m);
      assert.deepEqual(p.errors, []);
    } finally {
      await tctx.close();
    }
  });

  it('contract: the daemon serves the core\'s contract, the app\'s copy is the same, the form takes its ranges', async () => {
    const served = await (await fetch(url + '/contract.json')).json();
    const copy = JSON.parse(fs.readFileSync(new URL('../contract.json', import.meta.url), 'utf8'));
    assert.deepEqual(served, copy, 'hmi-web/contract.json differs from the daemon\'s (obu --print-hmi-contract)');
    await page.click('#nav-settings');
    await page.waitForSelector('#settings:not([hidden])');
    const form = await page.evaluate(() => {
      const f = document.getElementById('settings-form').elements;
      const units = [...f.units].find((r) => r.checked).value;
      return { units, lead: [f.lead_time_s.min, f.lead_time_s.max, f.lead_time_s.step].map(Number),
        distance: [f.warning_distance_m.min, f.warning_distance_m.max].map(Number), unit: f.warning_distance_m.dataset.unit };
    });
    const lead = served.settings.lead_time_s;
    assert.deepEqual(form.lead, [lead.min, lead.max, lead.step]);
    const d = served.settings.warning_distance_m;
    if (form.units === 'kmh') assert.deepEqual([...form.distance, form.unit], [d.min, d.max, 'm']);
    else assert.deepEqual([...form.distance, form.unit], [Math.ceil(d.min * 3.28084), Math.floor(d.max * 3.28084), 'ft']);
    await page.click('#settings .nav-back');
  });

  it('settings: validated form, server errors shown, mph survives a server restart', async () => {
    await page.click('#nav-settings');
    await page.waitForSelector('#settings:not([hidden])');
    await page.waitForFunction(() => document.getElementById('set-distance').value !== '');
    // client-side validation: nothing is sent
    let puts = 0;
    const count = (r) => { if (r.method() === 'PUT') puts += 1; };
    page.on('request', count);
    await page.fill('#set-distance', '5');
    await page.click('#settings-save');
    assert.match(await page.textContent('#err-warning_distance_m'), /20 and 2000/);
    assert.equal(puts, 0);
    await page.fill('#set-distance', '150');
    // the server's own 400 for a bad field
    const bad = await fetch(url + '/api/settings', { method: 'PUT', headers: { 'Content-Type': 'application/json', Cookie: cookie },
      body: JSON.stringify({ warning_distance_m: 100, lead_time_s: 99, sound: true, units: 'kmh', theme: 'auto' }) });
    assert.equal(bad.status, 400);
    assert.match((await bad.json()).error, /lead_time_s/);
    // the page shows a server error naming the field (answer replaced to reach that path)
    await page.route('**/api/settings', (route) => (route.request().method() === 'PUT'
      ? route.fulfill({ status: 400, contentType: 'application/json', body: '{"error":"lead_time_s: out of range"}' })
      : route.continue()));
    await page.click('#settings-save');
    await page.waitForFunction(() => document.getElementById('settings-msg').textContent.includes('lead_time_s'));
    assert.match(await page.textContent('#err-lead_time_s'), /lead_time_s/);
    await page.unroute('**/api/settings');
    // a real save: mph
    await page.check('input[name=units][value=mph]', { force: true });
    await page.click('#settings-save');
    await page.waitForFunction(() => document.getElementById('settings-msg').textContent === 'Saved.');
    page.off('request', count);
    await shot(page, 'settings');
    let stored = await (await fetch(url + '/api/settings')).json();
    assert.equal(stored.units, 'mph');
    assert.equal(stored.warning_distance_m, 150);
    // with mph the warning distance is shown and entered in ft, stored in metres
    assert.equal(await page.inputValue('#set-distance'), '492');
    assert.match(await page.textContent('#set-distance-range'), /ft, 66–6561/);
    await page.fill('#set-distance', '330');
    await page.click('#settings-save');
    await page.waitForFunction(() => document.getElementById('settings-msg').textContent === 'Saved.');
    const inFt = await (await fetch(url + '/api/settings')).json();
    assert.ok(Math.abs(inFt.warning_distance_m - 100.6) < 0.1, `330 ft stored as ${inFt.warning_distance_m} m`);
    await page.fill('#set-distance', '492');
    await page.click('#settings-save');
    await page.waitForFunction(() => document.getElementById('settings-msg').textContent === 'Saved.');
    await page.click('.nav-back >> nth=0');
    assert.equal(await page.textContent('#speed-unit'), 'mph');
    // restart the server, reload the page: still mph, from the server
    await server.stop();
    await server.start();
    events.close();
    events = watchEvents(url);
    await page.evaluate(() => localStorage.removeItem('hmi.settings'));
    await page.reload();
    await waitLive(page, 10000);
    stored = await (await fetch(url + '/api/settings')).json();
    assert.equal(stored.units, 'mph');
    await page.waitForFunction(() => document.getElementById('speed-unit').textContent === 'mph');
    const { msg } = await events.waitFor((m) => m.state.speed_mps !== null, 5000);
    const mph = Math.round(msg.state.speed_mps * 2.23694);
    const shown = Number(await page.textContent('#speed'));
    assert.ok(Math.abs(shown - mph) <= 2, `speed ${shown} mph ~ ${mph}`);
    await sceneOnScreen('approach', (m) => m.state.zone_state === 'Approaching' && m.state.distance_m > 0, 'approach');
    assert.match(await page.textContent('#distance-unit'), /^(ft|mi)$/);
    await shot(page, 'mph');
  });

  it('night theme (and auto follows the system), contrast of the alert colours', async () => {
    await page.click('#nav-settings');
    await page.waitForSelector('#settings:not([hidden])');
    await page.check('input[name=units][value=kmh]', { force: true });
    await page.fill('#set-distance', '100');
    await page.check('input[name=theme][value=night]', { force: true });
    await page.click('#settings-save');
    await page.waitForFunction(() => document.getElementById('settings-msg').textContent === 'Saved.');
    await page.click('.nav-back >> nth=0');
    assert.equal(await page.getAttribute('html', 'data-theme'), 'night');
    assert.equal(await page.evaluate(() => getComputedStyle(document.body).backgroundColor), 'rgb(0, 0, 0)');
    await sceneOnScreen('lane_closed', (m) => m.state.primary && m.state.primary.kind === 'LaneClosedOwn', 'LaneClosedOwn');
    await shot(page, 'night');

    for (const theme of ['night', 'day']) {
      const ratios = await page.evaluate(contrastReport, theme);
      for (const [name, r] of Object.entries(ratios)) assert.ok(r >= 4.5, `${theme} ${name}: contrast ${r.toFixed(2)} < 4.5`);
    }

    const auto = await fetch(url + '/api/settings', { method: 'PUT', headers: { 'Content-Type': 'application/json', Cookie: cookie },
      body: JSON.stringify({ ...(await (await fetch(url + '/api/settings')).json()), theme: 'auto' }) });
    assert.equal(auto.status, 200);
    await page.reload();
    await waitLive(page);
    await page.emulateMedia({ colorScheme: 'dark' });
    await page.waitForFunction(() => document.documentElement.dataset.theme === 'night');
    await page.emulateMedia({ colorScheme: 'light' });
    await page.waitForFunction(() => document.documentElement.dataset.theme === 'day');
  });

  it('portrait phone layout (390x844)', async () => {
    const phone = await ctx.newPage();
    try {
      await phone.setViewportSize({ width: 390, height: 844 });
      await phone.goto(url + '/');
      await waitLive(phone);
      const seen = events.waitFor((m) => m.state.primary && m.state.primary.kind === 'LaneClosedOwn', 10000);
      await go('lane_closed');
      await onScreen(phone, (await seen).msg);
      const info = await phone.evaluate(() => {
        const box = (id) => document.getElementById(id).getBoundingClientRect().toJSON();
        const buttons = [...document.querySelectorAll('button')].filter((b) => b.offsetParent).map((b) => b.getBoundingClientRect());
        return { scrollW: document.scrollingElement.scrollWidth, scrollH: document.scrollingElement.scrollHeight,
          boxes: ['speed', 'limit', 'alert-banner', 'lanes', 'distance-box', 'nav-settings'].map(box),
          minButton: Math.min(...buttons.map((b) => Math.min(b.width, b.height))),
          speedPx: parseFloat(getComputedStyle(document.getElementById('speed')).fontSize) };
      });
      assert.ok(info.scrollW <= 390 && info.scrollH <= 844, `no scrolling: ${info.scrollW}x${info.scrollH}`);
      for (const b of info.boxes) assert.ok(b.width > 0 && b.x >= 0 && b.right <= 390 && b.bottom <= 844, JSON.stringify(b));
      assert.ok(info.minButton >= 44, `touch targets ${info.minButton}`);
      assert.ok(info.speedPx >= 80, `speed ${info.speedPx}px`);
      await shot(phone, 'phone');
      await phone.emulateMedia({ colorScheme: 'dark' });
      await shot(phone, 'phone_night');
    } finally {
      await phone.close();
    }
  });

  it('settings and diagnostics pages: nothing cut at 360-430 px wide and 1280x800', async () => {
    const p = await ctx.newPage();
    try {
      await p.goto(url + '/#settings');
      await waitLive(p);
      await p.waitForFunction(() => document.getElementById('set-distance').value !== '');
      await checkLayouts(p, 'page_settings');
      await p.goto(url + '/#diag');
      await p.waitForFunction(() => document.querySelectorAll('#diag-status dt').length > 0, null, { timeout: 5000 });
      await checkLayouts(p, 'page_diag');
    } finally {
      await p.close();
    }
  });

  it('diagnostics view shows /api/status and the link', async () => {
    await page.click('#nav-diag');
    await page.waitForFunction(() => document.querySelectorAll('#diag-status dt').length > 0 && document.querySelectorAll('#diag-link dt').length > 0, null, { timeout: 5000 });
    const status = await (await fetch(url + '/api/status')).json();
    const text = await page.textContent('#diag-status');
    for (const k of Object.keys(status).slice(0, 3)) assert.ok(text.includes(k.replace(/_/g, ' ')), `shows ${k}`);
    await shot(page, 'diagnostics');
    await page.click('.nav-back >> nth=1');
    await page.waitForSelector('#drive:not([hidden])');
  });
});

/** In the page: WCAG contrast of each banner colour and of the main numbers, for a theme. */
function contrastReport(theme) {
  const html = document.documentElement;
  const prev = html.dataset.theme;
  html.dataset.theme = theme;
  const rgb = (c) => c.match(/[\d.]+/g).slice(0, 3).map(Number);
  const lum = (c) => {
    const [r, g, b] = rgb(c).map((v) => { v /= 255; return v <= 0.03928 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4; });
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
  };
  const ratio = (a, b) => { const [x, y] = [lum(a), lum(b)].sort((p, q) => q - p); return (x + 0.05) / (y + 0.05); };
  const out = {};
  for (const sev of ['red', 'amber', 'orange', 'zone', 'info', 'calm', 'offline']) {
    const el = document.createElement('div');
    el.className = 'banner sev-' + sev;
    el.innerHTML = '<div class="alert-title">X</div>';
    document.body.appendChild(el);
    const cs = getComputedStyle(el);
    out['banner ' + sev] = ratio(getComputedStyle(el.firstChild).color, cs.backgroundColor);
    el.remove();
  }
  const panel = getComputedStyle(document.querySelector('.panel')).backgroundColor;
  out.speed = ratio(getComputedStyle(document.getElementById('speed')).color, panel);
  out['limit sign'] = ratio(getComputedStyle(document.querySelector('.limit-value')).color, getComputedStyle(document.querySelector('.limit-sign')).backgroundColor);
  html.dataset.theme = prev;
  return out;
}
