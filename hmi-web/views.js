/* Settings (bound to /api/settings; a write from an unpaired tablet asks for the PIN, see
 * pair.js) and diagnostics (/api/status) views, and the router. The settings' defaults and
 * ranges are the core's, from contract.json. */
import * as F from './format.js';
import { pair } from './pair.js';

const doc = document;
const $ = (id) => doc.getElementById(id);

// ---- settings ----

const SETTINGS = F.contract.settings;
const DEFAULTS = Object.fromEntries(Object.entries(SETTINGS).map(([k, v]) => [k, v.default]));
/** The numeric settings the form checks (the warning distance in the form's unit, see setDistanceUnit). */
const RULES = { warning_distance_m: SETTINGS.warning_distance_m, lead_time_s: SETTINGS.lead_time_s };
const CACHE = 'hmi.settings';

function cached() {
  try {
    const s = JSON.parse(localStorage.getItem(CACHE) || 'null');
    return s && typeof s === 'object' ? Object.assign({}, DEFAULTS, s) : Object.assign({}, DEFAULTS);
  } catch (e) {
    return Object.assign({}, DEFAULTS);
  }
}

function remember(s) {
  try { localStorage.setItem(CACHE, JSON.stringify(s)); } catch (e) { /* private mode */ }
}

/** Only known fields with the right types; anything else falls back to the current value. */
function sanitize(s, base) {
  const out = Object.assign({}, base);
  if (!s || typeof s !== 'object') return out;
  if (typeof s.warning_distance_m === 'number') out.warning_distance_m = s.warning_distance_m;
  if (typeof s.lead_time_s === 'number') out.lead_time_s = s.lead_time_s;
  if (typeof s.sound === 'boolean') out.sound = s.sound;
  if (SETTINGS.units.choices.includes(s.units)) out.units = s.units;
  if (SETTINGS.theme.choices.includes(s.theme)) out.theme = s.theme;
  return out;
}

const Settings = {
  current: cached(),
  loaded: false,
  loading: null,
  onApply: () => {},

  apply(s) {
    this.current = sanitize(s, this.current);
    remember(this.current);
    this.onApply(this.current);
  },

  load() {
    if (this.loading) return this.loading;
    this.loading = fetch('/api/settings', { cache: 'no-store' })
      .then((r) => (r.ok ? r.json() : Promise.reject(new Error('HTTP ' + r.status))))
      .then((s) => { this.loaded = true; this.apply(s); fillForm(this.current); return this.current; })
      .catch((e) => { message('Could not load settings (' + e.message + '); showing the last known values.', 'error'); throw e; })
      .finally(() => { this.loading = null; });
    return this.loading;
  },
};

function form() {
  return $('settings-form');
}

/** The distance field shows the form's units: ft with mph, metres otherwise. */
function setDistanceUnit(units, metres) {
  const input = form().elements.warning_distance_m;
  const r = F.formDistanceRange(units);
  input.min = r.min;
  input.max = r.max;
  input.dataset.unit = r.unit;
  $('set-distance-range').textContent = '(' + r.unit + ', ' + r.min + '–' + r.max + ')';
  if (metres !== null && Number.isFinite(metres)) input.value = F.formDistance(metres, units);
}

/** Metres in the distance field now (null when it is not a number). */
function distanceMetres() {
  const input = form().elements.warning_distance_m;
  const v = Number(input.value);
  if (input.value.trim() === '' || !Number.isFinite(v)) return null;
  return F.metresFromForm(v, input.dataset.unit === 'ft' ? 'mph' : 'kmh');
}

function fillForm(s) {
  const f = form();
  setDistanceUnit(s.units, s.warning_distance_m);
  f.elements.lead_time_s.value = s.lead_time_s;
  f.elements.sound.checked = !!s.sound;
  f.querySelectorAll('input[name=units]').forEach((r) => { r.checked = r.value === s.units; });
  f.querySelectorAll('input[name=theme]').forEach((r) => { r.checked = r.value === s.theme; });
  clearErrors();
}

function message(text, kind) {
  const m = $('settings-msg');
  m.textContent = text;
  m.dataset.kind = kind || '';
}

function clearErrors() {
  Object.keys(RULES).forEach((k) => fieldError(k, ''));
}

function fieldError(name, text) {
  const el = $('err-' + name);
  const input = form().elements[name];
  if (el) el.textContent = text;
  if (input && input.setAttribute) input.setAttribute('aria-invalid', text ? 'true' : 'false');
}

function radio(name) {
  const r = form().querySelector('input[name=' + name + ']:checked');
  return r ? r.value : null;
}

/** Reads and checks the form; returns { value } or { errors }. */
function readForm() {
  const f = form();
  const errors = {};
  const value = {
    warning_distance_m: distanceMetres(),
    lead_time_s: Number(f.elements.lead_time_s.value),
    sound: f.elements.sound.checked,
    units: radio('units'),
    theme: radio('theme'),
  };
  Object.keys(RULES).forEach((k) => {
    const input = f.elements[k];
    const raw = input.value.trim();
    const shown = Number(raw);
    const r = k === 'warning_distance_m' ? { min: Number(input.min), max: Number(input.max) } : RULES[k];
    if (raw === '' || !Number.isFinite(shown) || !Number.isFinite(value[k])) errors[k] = 'Enter a number';
    else if (shown < r.min || shown > r.max) errors[k] = `Between ${r.min} and ${r.max}` + (input.dataset.unit ? ' ' + input.dataset.unit : '');
  });
  if (!value.units) errors.units = 'Choose units';
  if (!value.theme) errors.theme = 'Choose a theme';
  return Object.keys(errors).length ? { errors } : { value };
}

function save(ev) {
  ev.preventDefault();
  clearErrors();
  const r = readForm();
  if (r.errors) {
    Object.keys(r.errors).forEach((k) => fieldError(k, r.errors[k]));
    message('Not saved: check the marked fields.', 'error');
    return;
  }
  message('Saving…', 'busy');
  $('settings-save').disabled = true;
  put(r.value, true).finally(() => { $('settings-save').disabled = false; });
}

/** PUTs the settings; on 401 asks for pairing (once) and tries again when paired. */
function put(value, mayPair) {
  return fetch('/api/settings', {
    method: 'PUT',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(value),
  })
    .then((resp) => resp.text().then((t) => ({ resp, body: parse(t) })))
    .then(({ resp, body }) => {
      if (resp.ok) {
        Settings.apply(body && typeof body === 'object' && !body.error ? body : value);
        fillForm(Settings.current);
        message('Saved.', 'ok');
        return null;
      }
      if (resp.status === 401 && mayPair) {
        message('This tablet is not paired with the unit yet: enter its PIN.', 'busy');
        return pair.ask().then((paired) => {
          if (!paired) { message('Not saved: this tablet is not paired with the unit.', 'error'); return null; }
          message('Paired. Saving…', 'busy');
          return put(value, false);
        });
      }
      const err = (body && body.error) || 'HTTP ' + resp.status;
      const field = Object.keys(value).find((k) => err.indexOf(k) >= 0);
      if (field && RULES[field]) fieldError(field, err);
      message('Not saved: the unit said “' + err + '”.', 'error');
      return null;
    })
    .catch(() => message('Not saved: the unit is not reachable.', 'error'));
}

function parse(t) {
  try { return JSON.parse(t); } catch (e) { return null; }
}

// ---- diagnostics ----

const Diag = { timer: null, lastOk: 0, linkStats: () => ({}), lastState: () => null };

function label(k) {
  return String(k).replace(/_/g, ' ');
}

function fmt(v) {
  if (v === null || v === undefined) return '—';
  if (typeof v === 'number') return Number.isInteger(v) ? String(v) : v.toFixed(2);
  if (typeof v === 'boolean') return v ? 'yes' : 'no';
  if (Array.isArray(v)) return v.length ? v.map(fmt).join(', ') : '—';
  return String(v);
}

function kvRows(dl, obj) {
  const frag = doc.createDocumentFragment();
  Object.keys(obj).forEach((k) => {
    const dt = doc.createElement('dt');
    const dd = doc.createElement('dd');
    dt.textContent = label(k);
    dd.textContent = fmt(obj[k]);
    frag.appendChild(dt);
    frag.appendChild(dd);
  });
  dl.replaceChildren(frag);
}

/** Any JSON: scalars as key/value rows, objects as titled groups (one level deep, then inline). */
function statusTree(box, obj) {
  const frag = doc.createDocumentFragment();
  const flat = {};
  const groups = [];
  Object.keys(obj || {}).forEach((k) => {
    const v = obj[k];
    if (v && typeof v === 'object' && !Array.isArray(v)) groups.push([k, v]);
    else flat[k] = v;
  });
  if (Object.keys(flat).length) {
    const dl = doc.createElement('dl');
    dl.className = 'kv';
    kvRows(dl, flat);
    frag.appendChild(dl);
  }
  groups.forEach(([k, v]) => {
    const h = doc.createElement('h4');
    h.textContent = label(k);
    const dl = doc.createElement('dl');
    dl.className = 'kv';
    const inner = {};
    Object.keys(v).forEach((kk) => { inner[kk] = v[kk] && typeof v[kk] === 'object' && !Array.isArray(v[kk]) ? JSON.stringify(v[kk]) : v[kk]; });
    kvRows(dl, inner);
    frag.appendChild(h);
    frag.appendChild(dl);
  });
  box.replaceChildren(frag);
}

function pollStatus() {
  fetch('/api/status', { cache: 'no-store' })
    .then((r) => (r.ok ? r.json() : Promise.reject(new Error('HTTP ' + r.status))))
    .then((j) => { Diag.lastOk = Date.now(); statusTree($('diag-status'), j); $('diag-status-age').textContent = ''; })
    .catch((e) => { $('diag-status-age').textContent = '(not reachable: ' + e.message + ')'; });
}

function refreshDiag() {
  kvRows($('diag-link'), Diag.linkStats());
  const msg = Diag.lastState();
  if (!msg) return;
  const s = msg.state || {};
  const rows = {
    seq: msg.seq, gnss_age_ms: msg.gnss_age_ms, fix_quality: msg.fix_quality, time_ms: s.time_ms,
    speed_mps: s.speed_mps, speed_limit_mps: s.speed_limit_mps, reduced_limit: s.reduced_limit,
    zone_state: s.zone_state, distance_m: s.distance_m,
    primary: s.primary ? s.primary.kind : null, others: (s.others || []).map((a) => a.kind),
    lane: s.lane ? s.lane.map + '/' + s.lane.lane : null, lane_confidence: s.lane_confidence,
    road_lanes: s.road_lanes, closed_lanes: s.closed_lanes, advice: s.advice, gnss_ok: s.gnss_ok,
    roadside_data: s.roadside_data, maps: s.maps, zones: s.zones,
  };
  Object.keys(s.counters || {}).forEach((k) => { rows['counter ' + k] = s.counters[k]; });
  kvRows($('diag-state'), rows);
}

// ---- router ----

const VIEWS = ['drive', 'settings', 'diag'];
let onView = () => {};

function route() {
  const want = (location.hash || '').replace(/^#\/?/, '');
  const view = VIEWS.indexOf(want) > 0 ? want : 'drive';
  doc.body.dataset.view = view;
  $('drive').hidden = view !== 'drive';
  $('settings').hidden = view !== 'settings';
  $('diag').hidden = view !== 'diag';
  clearInterval(Diag.timer);
  Diag.timer = null;
  if (view === 'settings') { fillForm(Settings.current); message('', ''); Settings.load().catch(() => {}); }
  if (view === 'diag') {
    refreshDiag();
    pollStatus();
    Diag.timer = setInterval(() => { refreshDiag(); pollStatus(); }, 1000);
  }
  onView(view);
}

function go(view) {
  const h = view === 'drive' ? '#' : '#' + view;
  if (location.hash === h || (view === 'drive' && !location.hash)) route();
  else location.hash = h;
}

function init(opts) {
  Settings.onApply = opts.onSettings;
  Diag.linkStats = opts.linkStats;
  Diag.lastState = opts.lastState;
  onView = opts.onView || onView;
  const lead = form().elements.lead_time_s;
  const l = RULES.lead_time_s;
  [lead.min, lead.max, lead.step] = [l.min, l.max, l.step];
  $('set-lead-range').textContent = '(' + l.unit + ', ' + l.min + '–' + l.max + ')';
  form().elements.warning_distance_m.step = RULES.warning_distance_m.step;
  setDistanceUnit(Settings.current.units, null);
  form().addEventListener('submit', save);
  form().querySelectorAll('input[name=units]').forEach((r) => r.addEventListener('change', () => {
    setDistanceUnit(r.value, distanceMetres());
  }));
  $('settings-reload').addEventListener('click', () => { message('Loading…', 'busy'); Settings.load().then(() => message('Loaded.', 'ok'), () => {}); });
  $('nav-settings').addEventListener('click', () => go('settings'));
  $('nav-diag').addEventListener('click', () => go('diag'));
  doc.querySelectorAll('.nav-back').forEach((b) => b.addEventListener('click', () => go('drive')));
  addEventListener('hashchange', route);
  addEventListener('keydown', (e) => {
    // Escape in the pairing dialog closes the dialog only.
    if (e.key === 'Escape' && !pair.isOpen()) go('drive');
  });
  route();
}

export { init, Settings, go, DEFAULTS, sanitize };
