/* Driving view: renders each state, the connection state, the tone; exposes window.hmi for tests. */
import * as F from './format.js';
import * as lanes from './lanes.js';
import { createSound } from './sound.js';
import { stream } from './stream.js';
import * as views from './views.js';

const doc = document;
const sound = createSound(window);
const $ = (id) => doc.getElementById(id);

const app = {
  msg: null,          // last {seq, state, gnss_age_ms, fix_quality}
  conn: 'disconnected',
  everLive: false,
  settings: views.Settings.current,
  darkQuery: window.matchMedia ? window.matchMedia('(prefers-color-scheme: dark)') : null,
};

/** textContent / attribute writes only when the value changes (10 Hz updates). */
function setText(el, text) {
  if (el.textContent !== text) el.textContent = text;
}

function setData(el, key, value) {
  const v = String(value);
  if (el.dataset[key] !== v) el.dataset[key] = v;
}

function setIcon(use, id) {
  const href = '#' + id;
  if (use.getAttribute('href') !== href) use.setAttribute('href', href);
}

// ---- theme and units ----

function applyTheme() {
  const t = app.settings.theme;
  const dark = t === 'night' || (t === 'auto' && app.darkQuery && app.darkQuery.matches);
  doc.documentElement.dataset.theme = dark ? 'night' : 'day';
  doc.documentElement.dataset.themeSetting = t;
  const meta = doc.querySelector('meta[name=theme-color]');
  if (meta) meta.setAttribute('content', dark ? '#000000' : '#101317');
}

function onSettings(s) {
  app.settings = s;
  applyTheme();
  sound.setAllowed(s.sound);
  const unit = F.speedUnitLabel(s.units);
  setText($('speed-unit'), unit);
  setText($('limit-unit'), unit);
  render();
}

// ---- rendering ----

/**
 * The one-red rule: only the banner (stage Warning/Urgent) or, when the banner is not red,
 * the speed (speed_alarm) may be red. The speed's alarm under a red banner is an amber ring.
 */
function renderSpeed(s, units, bannerRed) {
  const live = app.conn === 'live';
  setText($('speed'), F.speedText(s.speed_mps, units));
  const box = $('speed-box');
  setData(box, 'stale', !F.finite(s.speed_mps));
  const alarm = live && s.speed_alarm === true && F.finite(s.speed_mps);
  setData(box, 'alarm', alarm ? (bannerRed ? 'muted' : 'red') : 'false');
  setData(box, 'red', alarm && !bannerRed);
}

function renderAhead(s, units) {
  const a = app.conn === 'live' ? F.limitAhead(s, units) : null;
  const fig = $('limit-ahead');
  fig.hidden = !a;
  if (!a) return;
  setText($('ahead-value'), a.value);
  setText($('ahead-where'), a.where);
  const label = 'Lower limit ahead: ' + a.value + ' ' + F.speedUnitLabel(units) + ' ' + a.where;
  if (fig.getAttribute('aria-label') !== label) fig.setAttribute('aria-label', label);
}

function renderLimit(s, units) {
  const known = F.finite(s.speed_limit_mps);
  const fig = $('limit');
  setText($('limit-value'), known ? F.speedText(s.speed_limit_mps, units) : '--');
  setData(fig, 'known', known);
  setData(fig, 'reduced', known && !!s.reduced_limit);
  const label = known ? 'Speed limit ' + F.speedText(s.speed_limit_mps, units) + ' ' + F.speedUnitLabel(units) +
    (s.reduced_limit ? ', reduced for the work zone' : '') : 'Speed limit unknown';
  if (fig.getAttribute('aria-label') !== label) fig.setAttribute('aria-label', label);
}

function renderDistance(s, units) {
  const v = F.distanceView(s, units);
  setData($('distance-box'), 'mode', v.mode);
  setText($('distance-label'), v.label);
  setText($('distance'), v.value);
  setText($('distance-unit'), v.unit);
  $('distance-approx').hidden = !v.approx;
  $('pos-marker').hidden = !(app.conn === 'live' && F.positionOf(s) === 'Estimated');
}

function bannerFor(s, units) {
  if (app.conn !== 'live') {
    const since = app.msg ? stream.stats().since_last_ms : null;
    const ago = since !== null ? ' · last data ' + F.ageText(since) + ' ago' : '';
    if (!app.everLive && !app.msg) {
      // opened without the unit (e.g. from the offline shell): say so once a try failed
      const failed = stream.stats().stream_errors > 0;
      return { sev: 'offline', icon: 'i-plug-off', kind: 'disconnected', title: failed ? 'Disconnected' : 'Connecting…',
        detail: failed ? 'Vehicle unit not reachable · retrying' : 'Waiting for the vehicle unit' };
    }
    return {
      sev: 'offline', icon: 'i-plug-off', title: 'Disconnected', kind: 'disconnected',
      detail: (app.conn === 'stale' ? 'No data from the vehicle unit' : 'Reconnecting to the vehicle unit') + ago,
    };
  }
  return F.banner(s, units);
}

/** Returns whether the banner is red. */
function renderBanner(s, units) {
  const b = bannerFor(s, units);
  const el = $('alert-banner');
  const cls = 'banner sev-' + b.sev;
  if (el.className !== cls) el.className = cls;
  setData(el, 'kind', b.kind);
  setData(el, 'stage', app.conn === 'live' ? F.stageOf(s) : 'None');
  setData(el, 'red', b.sev === 'red');
  setIcon($('alert-icon'), b.icon);
  setText($('alert-title'), b.title);
  setText($('alert-detail'), b.detail || '');
  return b.sev === 'red';
}

function renderOthers(s, units) {
  const list = app.conn === 'live' ? (s.others || []) : [];
  const approx = F.positionOf(s) === 'Estimated';
  const ctx = { units, advice: s.advice, limit_mps: s.speed_limit_mps, approx };
  const items = list.map((a) => {
    const d = F.describeAlert(a, ctx);
    const ahead = F.aheadText(a.distance_m, units, approx);
    // chips are never red: a chip of an act-now kind is amber at most
    const sev = d.sev === 'red' ? 'amber' : d.sev;
    return { kind: a.kind, sev, icon: d.icon, text: d.short, ahead: ahead && ahead !== 'here' ? ahead : '' };
  });
  const key = JSON.stringify(items) + '|' + window.innerWidth;
  const ul = $('others');
  if (ul.__key === key) return;
  ul.__key = key;
  ul.replaceChildren.apply(ul, items.map((it) => {
    const li = doc.createElement('li');
    li.className = 'other sev-' + it.sev;
    li.dataset.kind = it.kind;
    li.innerHTML = '<svg class="ico" aria-hidden="true"><use href="#' + it.icon + '"/></svg>';
    const span = doc.createElement('span');
    span.textContent = it.text;
    li.appendChild(span);
    if (it.ahead) {
      const q = doc.createElement('span');
      q.className = 'qty other-ahead';
      q.textContent = it.ahead;
      li.appendChild(q);
    }
    return li;
  }));
  collapseOthers(ul);
}

/** Chips that do not fit are folded, from the end, into one "+N" chip. */
function collapseOthers(ul) {
  const chips = Array.from(ul.children);
  if (!chips.length || ul.scrollWidth <= ul.clientWidth + 1) return;
  const more = doc.createElement('li');
  more.className = 'other other-more sev-info';
  more.dataset.kind = 'more';
  ul.appendChild(more);
  let hidden = 0;
  for (let i = chips.length - 1; i >= 0 && ul.scrollWidth > ul.clientWidth + 1; i--) {
    chips[i].hidden = true;
    hidden += 1;
    more.textContent = '+' + hidden;
    more.setAttribute('aria-label', hidden + ' more ' + (hidden === 1 ? 'alert' : 'alerts') + ': ' +
      chips.slice(i).map((c) => c.textContent).join(', '));
  }
}

function chip(id, cls, text) {
  const el = $(id);
  const c = 'chip ' + cls + (el.classList.contains('chip-optional') ? ' chip-optional' : '');
  if (el.className !== c) el.className = c;
  const t = el.querySelector('.chip-text') || el;
  setText(t, text);
}

function renderChips(msg) {
  const s = msg ? msg.state : null;
  const live = app.conn === 'live';
  chip('conn-chip', live ? 'chip-ok' : 'chip-warn',
    live ? 'Live' : app.conn === 'stale' ? 'No data' : app.everLive ? 'Offline' : 'Connecting…');
  setData($('conn-chip'), 'state', app.conn);
  if (!s) return;
  const extra = $('gnss-chip').querySelector('.chip-extra');
  if (s.gnss_ok) {
    const q = F.fixName(msg.fix_quality);
    const age = F.finite(msg.gnss_age_ms) && msg.gnss_age_ms >= 500 ? ' · ' + F.ageText(msg.gnss_age_ms) : '';
    chip('gnss-chip', live ? 'chip-ok' : 'chip-muted', 'GNSS' + (q ? ' ' + q : ''));
    setText(extra, age);
  } else {
    const age = F.finite(msg.gnss_age_ms) ? ' · ' + F.ageText(msg.gnss_age_ms) : '';
    const est = F.positionOf(s) === 'Estimated';
    chip('gnss-chip', live ? 'chip-warn' : 'chip-muted', est ? 'No GNSS · estimating' : 'No GNSS');
    setText(extra, age);
  }
  const timeChip = $('time-chip');
  timeChip.hidden = !(live && s.time_status === 'Unverified');
  const rsu = F.roadsideChip(s, live);
  chip('rsu-chip', rsu.cls, rsu.text);
  setData($('rsu-chip'), 'trust', rsu.trust);
  const n = (x, one, many) => (F.finite(x) ? x : 0) + ' ' + ((x === 1) ? one : many);
  setText($('data-chip'), n(s.maps, 'map', 'maps') + ' · ' + n(s.zones, 'zone', 'zones'));
  fitChips();
}

/** The map/zone counts, then the GNSS age, give way when the status chips do not fit. */
function fitChips() {
  const box = doc.querySelector('.chips');
  const optional = [$('data-chip'), $('gnss-chip').querySelector('.chip-extra')];
  const fits = () => {
    const right = box.getBoundingClientRect().right + 0.5;
    return Array.from(box.children).every((c) => c.hidden || c.getBoundingClientRect().right <= right);
  };
  optional.forEach((el) => { el.hidden = false; });
  for (const el of optional) {
    if (fits()) break;
    el.hidden = true;
  }
}

function renderLanes(s) {
  const m = lanes.render($('lanes'), s, app.settings);
  const svg = $('lanes');
  const label = 'Lanes ahead: ' + lanes.describe(m);
  if (svg.getAttribute('aria-label') !== label) svg.setAttribute('aria-label', label);
  setText($('lanes-note'), m.approximate ? 'Lane order approximate' : '');
}

function render() {
  const body = doc.body;
  setData(body, 'conn', app.conn);
  renderChips(app.msg);
  const s = app.msg ? app.msg.state : {};
  const units = app.settings.units;
  setData(body, 'zone', s.zone_state || 'None');
  setData(body, 'primary', s.primary ? s.primary.kind : 'none');
  setData(body, 'gnss', s.gnss_ok === false ? 'lost' : s.gnss_ok ? 'ok' : 'unknown');
  setData(body, 'position', app.msg ? F.positionOf(s) : 'unknown');
  setData(body, 'time', s.time_status || 'Unknown');
  setData(body, 'roadside', s.roadside_data === false ? 'none' : s.roadside_data ? 'ok' : 'unknown');
  const red = renderBanner(s, units);
  renderSpeed(s, units, red);
  renderLimit(s, units);
  renderAhead(s, units);
  renderDistance(s, units);
  renderOthers(s, units);
  renderLanes(s);
  updateTone();
}

function updateTone() {
  const live = app.conn === 'live';
  sound.update(F.toneFor(app.msg && app.msg.state, live), live);
}

// ---- the one-red rule, checked from outside (tests) ----

/** A colour is red when its hue is within 20 degrees of pure red, saturated and mid-light. */
function isRed(css) {
  const m = /rgba?\(([^)]+)\)/.exec(css || '');
  if (!m) return false;
  const p = m[1].split(/[\s,/]+/).filter(Boolean).map(Number);
  if (p.length > 3 && p[3] < 0.3) return false;
  const [r, g, b] = p.map((v) => v / 255);
  const max = Math.max(r, g, b);
  const min = Math.min(r, g, b);
  const l = (max + min) / 2;
  const d = max - min;
  if (d === 0 || max !== r) return false;
  const sat = d / (1 - Math.abs(2 * l - 1));
  const hue = (((g - b) / d) * 60 + 360) % 360;
  return (hue <= 20 || hue >= 340) && sat >= 0.5 && l >= 0.18 && l <= 0.75;
}

function visible(el) {
  const r = el.getBoundingClientRect();
  if (r.width < 2 || r.height < 2) return false;
  if (r.right <= 0 || r.bottom <= 0 || r.left >= window.innerWidth || r.top >= window.innerHeight) return false;
  for (let e = el; e && e.nodeType === 1; e = e.parentElement) {
    const cs = getComputedStyle(e);
    if (cs.display === 'none' || cs.visibility === 'hidden' || Number(cs.opacity) < 0.3) return false;
  }
  return true;
}

/** Visible elements marked red by the renderer or painted red (text, background, border, fill). */
function redElements() {
  const found = [];
  doc.querySelectorAll('body *').forEach((el) => {
    if (el.closest('defs, symbol, script, style')) return;
    const cs = getComputedStyle(el);
    const text = Array.from(el.childNodes).some((n) => n.nodeType === 3 && n.textContent.trim());
    const svgShape = el instanceof SVGElement && el.tagName !== 'svg';
    const painted = isRed(cs.backgroundColor) || (text && isRed(cs.color)) ||
      (parseFloat(cs.borderTopWidth) >= 2 && isRed(cs.borderTopColor)) ||
      (svgShape && (isRed(cs.fill) || isRed(cs.stroke)));
    if ((el.dataset && el.dataset.red === 'true') || painted) {
      if (visible(el) && !found.some((f) => f.contains(el))) found.push(el);
    }
  });
  return found;
}

// ---- sound button ----

/** Sound status, visible on every layout: on, muted (settings) or needs a tap. */
function renderSound(state) {
  const allowed = app.settings.sound;
  const running = state === 'running';
  const needsTap = allowed && !running && state !== 'unsupported';
  $('sound-enable').hidden = !needsTap;
  const badge = $('sound-state');
  badge.hidden = needsTap;
  const mode = !allowed ? 'muted' : running ? 'on' : state === 'unsupported' ? 'unsupported' : 'tap';
  setIcon(badge.querySelector('use'), mode === 'on' ? 'i-sound' : 'i-sound-off');
  const short = { on: 'Sound on', muted: 'Muted', unsupported: 'No sound', tap: 'Tap for sound' }[mode];
  const label = { on: 'Sound on', muted: 'Sound muted in settings', unsupported: 'No sound in this browser', tap: 'Sound needs a tap' }[mode];
  setText($('sound-label'), short);
  badge.setAttribute('aria-label', label);
  badge.title = label;
  setData(badge, 'on', mode === 'on');
  setData(badge, 'sound', mode);
}

// ---- wiring ----

function onState(msg) {
  app.msg = msg;
  render();
}

function onConn(conn) {
  app.conn = conn;
  if (conn === 'live') {
    app.everLive = true;
    if (!views.Settings.loaded) views.Settings.load().catch(() => {});
  }
  render();
}

/** The service worker keeps the app shell, so a reload without the unit opens this app. */
function registerWorker() {
  const sw = navigator.serviceWorker;
  if (!sw || !isSecureContext) return;
  sw.register('/sw.js', { scope: '/' }).catch(() => { /* served without it: online only */ });
}

function init() {
  applyTheme();
  if (app.darkQuery && app.darkQuery.addEventListener) app.darkQuery.addEventListener('change', applyTheme);
  sound.init({ allowed: app.settings.sound, onChange: renderSound });
  $('sound-enable').addEventListener('click', () => sound.unlock(true));
  views.init({
    onSettings,
    linkStats: () => Object.assign(stream.stats(), {
      audio: sound.state(), tones_scheduled: sound.tonesScheduled(),
      theme: doc.documentElement.dataset.theme, units: app.settings.units,
    }),
    lastState: () => app.msg,
  });
  onSettings(app.settings);
  views.Settings.load().catch(() => {});
  stream.start({ url: '/events', onState, onConn });
  addEventListener('resize', () => render());
  registerWorker();
  // the "last data N s ago" text keeps counting while disconnected
  setInterval(() => { if (app.conn !== 'live') render(); }, 500);
}

window.hmi = {
  audioState: () => sound.state(),
  tonesScheduled: () => sound.tonesScheduled(),
  lastState: () => (app.msg ? app.msg.state : null),
  lastMessage: () => app.msg,
  connection: () => app.conn,
  settings: () => Object.assign({}, app.settings),
  redElements: () => redElements().length,
  redList: () => redElements().map((e) => e.id || e.className.baseVal || e.className || e.tagName),
  offline: () => ({ controlled: !!(navigator.serviceWorker && navigator.serviceWorker.controller) }),
};

init();
