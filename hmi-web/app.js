/* Driving view: renders each state, the connection state, the tone; exposes window.hmi for tests. */
(function (root) {
  'use strict';

  const doc = root.document;
  const F = root.HmiFormat;
  const $ = (id) => doc.getElementById(id);

  const app = {
    msg: null,          // last {seq, state, gnss_age_ms, fix_quality}
    conn: 'disconnected',
    everLive: false,
    settings: root.HmiViews.Settings.current,
    darkQuery: root.matchMedia ? root.matchMedia('(prefers-color-scheme: dark)') : null,
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
    root.HmiSound.setAllowed(s.sound);
    const unit = F.speedUnitLabel(s.units);
    setText($('speed-unit'), unit);
    setText($('limit-unit'), unit);
    render();
  }

  // ---- rendering ----

  function renderSpeed(s, units) {
    setText($('speed'), F.speedText(s.speed_mps, units));
    const kinds = [s.primary].concat(s.others || []).filter(Boolean).map((a) => a.kind);
    setData($('speed-box'), 'over', kinds.indexOf('Overspeed') >= 0);
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
  }

  function bannerFor(s, units) {
    if (app.conn !== 'live') {
      const since = app.msg ? root.HmiStream.stats().since_last_ms : null;
      const ago = since !== null ? ' · last data ' + F.ageText(since) + ' ago' : '';
      if (!app.everLive && !app.msg) return { sev: 'offline', icon: 'i-plug-off', title: 'Connecting…', detail: 'Waiting for the vehicle unit', kind: 'disconnected' };
      return {
        sev: 'offline', icon: 'i-plug-off', title: 'Disconnected', kind: 'disconnected',
        detail: (app.conn === 'stale' ? 'No data from the vehicle unit' : 'Reconnecting to the vehicle unit') + ago,
      };
    }
    const ctx = { units, advice: s.advice, limit_mps: s.speed_limit_mps };
    if (s.primary) return Object.assign({ kind: s.primary.kind }, F.describeAlert(s.primary, ctx));
    return Object.assign({ kind: 'none' }, F.calmBanner(s, units));
  }

  function renderBanner(s, units) {
    const b = bannerFor(s, units);
    const el = $('alert-banner');
    const cls = 'banner sev-' + b.sev;
    if (el.className !== cls) el.className = cls;
    setData(el, 'kind', b.kind);
    setIcon($('alert-icon'), b.icon);
    setText($('alert-title'), b.title);
    setText($('alert-detail'), b.detail || '');
  }

  function renderOthers(s, units) {
    const list = app.conn === 'live' ? (s.others || []).slice(0, 4) : [];
    const ctx = { units, advice: s.advice, limit_mps: s.speed_limit_mps };
    const items = list.map((a) => {
      const d = F.describeAlert(a, ctx);
      const ahead = F.aheadText(a.distance_m, units);
      return { kind: a.kind, sev: d.sev, icon: d.icon, text: d.short + (ahead && ahead !== 'here' ? ' · ' + ahead : '') };
    });
    const key = JSON.stringify(items);
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
      return li;
    }));
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
    chip('conn-chip', live ? 'chip-ok' : app.conn === 'stale' ? 'chip-warn' : 'chip-bad',
      live ? 'Live' : app.conn === 'stale' ? 'No data' : app.everLive ? 'Offline' : 'Connecting…');
    setData($('conn-chip'), 'state', app.conn);
    if (!s) return;
    if (s.gnss_ok) {
      const q = F.fixName(msg.fix_quality);
      const age = F.finite(msg.gnss_age_ms) && msg.gnss_age_ms >= 500 ? ' · ' + F.ageText(msg.gnss_age_ms) : '';
      chip('gnss-chip', live ? 'chip-ok' : 'chip-muted', 'GNSS' + (q ? ' ' + q : '') + age);
    } else {
      const age = F.finite(msg.gnss_age_ms) ? ' · ' + F.ageText(msg.gnss_age_ms) : '';
      chip('gnss-chip', live ? 'chip-bad' : 'chip-muted', 'No GNSS' + age);
    }
    const rsu = F.roadsideChip(s, live);
    chip('rsu-chip', rsu.cls, rsu.text);
    setData($('rsu-chip'), 'trust', rsu.trust);
    const n = (x, one, many) => (F.finite(x) ? x : 0) + ' ' + ((x === 1) ? one : many);
    setText($('data-chip'), n(s.maps, 'map', 'maps') + ' · ' + n(s.zones, 'zone', 'zones'));
  }

  function renderLanes(s) {
    const m = root.HmiLanes.render($('lanes'), s, app.settings);
    const svg = $('lanes');
    const label = 'Lanes ahead: ' + root.HmiLanes.describe(m);
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
    setData(body, 'roadside', s.roadside_data === false ? 'none' : s.roadside_data ? 'ok' : 'unknown');
    renderSpeed(s, units);
    renderLimit(s, units);
    renderDistance(s, units);
    renderBanner(s, units);
    renderOthers(s, units);
    renderLanes(s);
    updateTone();
  }

  function updateTone() {
    const s = app.msg && app.msg.state;
    const want = app.conn === 'live' && F.toneWanted(s);
    root.HmiSound.update(want, F.toneLevel(s));
  }

  // ---- sound button ----

  function renderSound(state) {
    const allowed = app.settings.sound;
    const running = state === 'running';
    $('sound-enable').hidden = !allowed || running || state === 'unsupported';
    const badge = $('sound-state');
    setIcon(badge.querySelector('use'), allowed && running ? 'i-sound' : 'i-sound-off');
    const label = !allowed ? 'Sound off in settings' : running ? 'Sound on' : 'Sound not enabled';
    badge.setAttribute('aria-label', label);
    badge.title = label;
    setData(badge, 'on', allowed && running);
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
      if (!root.HmiViews.Settings.loaded) root.HmiViews.Settings.load().catch(() => {});
    }
    render();
  }

  function init() {
    applyTheme();
    if (app.darkQuery && app.darkQuery.addEventListener) app.darkQuery.addEventListener('change', applyTheme);
    root.HmiSound.init({ allowed: app.settings.sound, onChange: renderSound });
    $('sound-enable').addEventListener('click', () => root.HmiSound.unlock(true));
    root.HmiViews.init({
      onSettings,
      linkStats: () => Object.assign(root.HmiStream.stats(), {
        audio: root.HmiSound.state(), tones_scheduled: root.HmiSound.tonesScheduled(),
        theme: doc.documentElement.dataset.theme, units: app.settings.units,
      }),
      lastState: () => app.msg,
    });
    onSettings(app.settings);
    root.HmiViews.Settings.load().catch(() => {});
    root.HmiStream.start({ url: '/events', onState, onConn });
    // the "last data N s ago" text keeps counting while disconnected
    root.setInterval(() => { if (app.conn !== 'live') render(); }, 500);
  }

  root.hmi = {
    audioState: () => root.HmiSound.state(),
    tonesScheduled: () => root.HmiSound.tonesScheduled(),
    lastState: () => (app.msg ? app.msg.state : null),
    lastMessage: () => app.msg,
    connection: () => app.conn,
    settings: () => Object.assign({}, app.settings),
  };

  init();
})(window);
