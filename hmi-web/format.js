/* Pure formatting and alert wording. No DOM: also loaded by the node unit tests. */

/** The core's contract (alert kinds, stages, the settings' ranges), served beside the app. */
const contract = await (await fetch(new URL('./contract.json', import.meta.url))).json();
const MPS_TO = { kmh: 3.6, mph: 2.23694 };
const M_TO_FT = 3.28084;
const FT_PER_MILE = 5280;

/** Alert kinds, highest priority first (the core's order; the server already picks `primary`). */
const KINDS = contract.alert_kinds;

function finite(x) {
  return typeof x === 'number' && Number.isFinite(x);
}

function unitsOf(units) {
  return units === 'mph' ? 'mph' : 'kmh';
}

function speedUnitLabel(units) {
  return unitsOf(units) === 'mph' ? 'mph' : 'km/h';
}

/** Speed in the display unit, rounded; null when unknown. */
function speedValue(mps, units) {
  if (!finite(mps)) return null;
  const v = Math.round(Math.max(0, mps) * MPS_TO[unitsOf(units)]);
  return v === 0 ? 0 : v; // no "-0"
}

function speedText(mps, units) {
  const v = speedValue(mps, units);
  return v === null ? '--' : String(v);
}

function roundTo(x, step) {
  return Math.round(x / step) * step;
}

/**
 * A distance for the driver: coarse when far (the countdown must not flicker),
 * fine when near. Returns { value, unit } with value a string; null when unknown.
 */
function distanceParts(m, units) {
  if (!finite(m)) return null;
  const d = Math.abs(m);
  if (unitsOf(units) === 'mph') {
    const ft = d * M_TO_FT;
    if (ft >= 1000) return { value: (ft / FT_PER_MILE).toFixed(ft >= 10 * FT_PER_MILE ? 0 : 1), unit: 'mi' };
    if (ft >= 300) return { value: String(roundTo(ft, 50)), unit: 'ft' };
    return { value: String(roundTo(ft, 10)), unit: 'ft' };
  }
  if (d >= 1000) return { value: (d / 1000).toFixed(d >= 10000 ? 0 : 1), unit: 'km' };
  if (d >= 200) return { value: String(roundTo(d, 10)), unit: 'm' };
  if (d >= 50) return { value: String(roundTo(d, 5)), unit: 'm' };
  return { value: String(Math.round(d)), unit: 'm' };
}

function distanceText(m, units) {
  const p = distanceParts(m, units);
  return p ? p.value + ' ' + p.unit : '';
}

function limitText(mps, units) {
  return speedText(mps, units) + ' ' + speedUnitLabel(units);
}

/** "in 120 m" / "here" / "" for an alert distance; "in ≈ 120 m" when estimated. */
function aheadText(m, units, approx) {
  if (!finite(m)) return '';
  if (m <= 0) return 'here';
  return 'in ' + (approx ? '≈ ' : '') + distanceText(m, units);
}

/**
 * Wording, colour and icon of one alert.
 * sev: red (act now), amber (prepare), orange (work zone info), info (system).
 */
function describeAlert(alert, ctx) {
  const units = ctx && ctx.units;
  const advice = (ctx && ctx.advice) || 'None';
  const a = alert || {};
  const ahead = aheadText(a.distance_m, units, ctx && ctx.approx);
  const limit = finite(a.limit_mps) ? a.limit_mps : (ctx && ctx.limit_mps);
  switch (a.kind) {
    case 'WorkerInLane':
      return { sev: 'red', icon: 'i-worker', title: 'WORKER IN LANE AHEAD', short: 'Worker in lane',
        detail: 'A worker in your lane' + (ahead ? ' ' + ahead : '') };
    case 'WorkersNearRoad':
      return { sev: 'orange', icon: 'i-worker', title: 'Workers near the road', short: 'Workers',
        detail: ahead };
    case 'Overspeed':
      return { sev: 'red', icon: 'i-gauge', title: 'Slow down',
        short: 'Too fast', detail: finite(limit) ? 'Limit ' + limitText(limit, units) : 'Over the limit' };
    case 'LaneClosedOwn': {
      const dir = advice === 'MoveLeft' ? 'left' : advice === 'MoveRight' ? 'right' : '';
      return { sev: 'red', icon: dir ? 'i-arrow-' + dir : 'i-cone',
        title: dir ? 'Change lane ' + dir : 'Your lane is closed',
        short: 'Lane closed',
        detail: 'Your lane is closed' + (ahead ? ' ' + ahead : '') };
    }
    case 'ReducedSpeedAhead':
      return { sev: 'amber', icon: 'i-limit', title: 'Reduced speed ahead', short: 'Reduced speed',
        detail: [finite(limit) ? limitText(limit, units) : '', ahead].filter(Boolean).join(' ') };
    case 'LaneClosedOther':
      return { sev: 'amber', icon: 'i-cone', title: 'Lane closed ahead', short: 'Lane closed',
        detail: 'Another lane' + (ahead ? ' · ' + ahead : '') };
    case 'WorkZoneAhead':
      return { sev: 'orange', icon: 'i-diamond', title: 'Work zone ahead', short: 'Work zone',
        detail: ahead };
    case 'GnssStale':
      return { sev: 'info', icon: 'i-sat-off', title: 'No GNSS position', short: 'No GNSS',
        detail: 'Position unknown · lane warnings off' };
    case 'MapMissing':
      return { sev: 'info', icon: 'i-map-off', title: 'No lane map', short: 'No lane map',
        detail: 'Lane warnings unavailable' };
    case 'NoRoadsideData':
      return { sev: 'info', icon: 'i-antenna-off', title: 'No roadside data', short: 'No roadside data',
        detail: 'Work-zone warnings unavailable' };
    default:
      return { sev: 'info', icon: 'i-info', title: String(a.kind || 'Alert'), short: String(a.kind || 'Alert'),
        detail: ahead };
  }
}

/** Alert stages, lowest first (the core's). */
const STAGES = contract.stages;

/**
 * The stage of the primary alert: the one source of colour and sound. A state without
 * `stage` (a core that does not stage its alerts) is staged here: an act-now alert is
 * Urgent, the zone warning Warning, an alert while approaching Information.
 */
function stageOf(state) {
  const s = state || {};
  if (STAGES.indexOf(s.stage) >= 0) return s.stage;
  const k = s.primary && s.primary.kind;
  if (k === 'Overspeed' || k === 'LaneClosedOwn') return 'Urgent';
  if (k === 'WorkerInLane') return 'Warning';
  if (s.zone_state === 'Warning') return 'Warning';
  if (s.zone_state === 'Approaching' && k) return 'Information';
  return 'None';
}

function stageRank(stage) {
  return Math.max(0, STAGES.indexOf(stage));
}

/** 'Live' | 'Estimated' | 'Lost'; without `position` (a core that does not send it) GNSS loss is Lost. */
function positionOf(state) {
  const s = state || {};
  if (s.position === 'Live' || s.position === 'Estimated' || s.position === 'Lost') return s.position;
  return s.gnss_ok === false ? 'Lost' : 'Live';
}

/**
 * Banner colour from the stage: red for Warning and Urgent, amber for Information. With
 * no stage, system alerts are slate ('info') and work-zone facts a neutral 'zone' style.
 */
function stageSev(stage, kindSev) {
  if (stage === 'Warning' || stage === 'Urgent') return 'red';
  if (stage === 'Information') return 'amber';
  return kindSev === 'info' ? 'info' : 'zone';
}

const ZONE_KNOWN = ['Approaching', 'Warning', 'InZone'];

/** The banner while live: the primary alert in its stage's colour, or the calm state. */
function banner(state, units) {
  const s = state || {};
  const stage = stageOf(s);
  const ctx = { units, advice: s.advice, limit_mps: s.speed_limit_mps, approx: positionOf(s) === 'Estimated' };
  if (positionOf(s) === 'Lost') {
    const zone = ZONE_KNOWN.indexOf(s.zone_state) >= 0;
    return { kind: 'PositionLost', stage, sev: stageSev(stage, 'info'), icon: 'i-sat-off',
      title: 'Position lost',
      detail: zone ? (s.zone_state === 'InZone' ? 'In work zone' : 'Work zone ahead') + ' · distance unknown'
        : 'Work-zone warnings unavailable' };
  }
  if (s.primary) {
    const d = describeAlert(s.primary, ctx);
    return Object.assign({ kind: s.primary.kind, stage }, d, { sev: stageSev(stage, d.sev) });
  }
  return Object.assign({ kind: 'none', stage }, calmBanner(s, units, stage));
}

/** The banner when the server has no primary alert (never green without a position). */
function calmBanner(state, units, stage) {
  const st = stage || stageOf(state);
  if (state && positionOf(state) === 'Lost') return banner(state, units);
  if (state && state.roadside_data === false) {
    const d = describeAlert({ kind: 'NoRoadsideData' }, { units });
    return Object.assign({}, d, { sev: stageSev(st, d.sev) });
  }
  switch (state && state.zone_state) {
    case 'InZone':
      return { sev: stageSev(st, 'zone'), icon: 'i-cone', title: 'In work zone', detail: 'Keep to the limit' };
    case 'Leaving':
      return { sev: 'calm', icon: 'i-flag', title: 'Leaving work zone', detail: '' };
    case 'Approaching':
    case 'Warning':
      return { sev: stageSev(st, 'zone'), icon: 'i-diamond', title: 'Work zone ahead',
        detail: aheadText(state.distance_m, units, positionOf(state) === 'Estimated') };
    default:
      return { sev: 'calm', icon: 'i-ok', title: 'No warnings', detail: '' };
  }
}

/** What the big distance field says; `approx` marks a dead-reckoned distance. */
function distanceView(state, units) {
  const z = state && state.zone_state;
  const d = state && state.distance_m;
  const pos = positionOf(state);
  const none = { value: '', unit: '', approx: false };
  if (state && state.roadside_data === false) return Object.assign({ mode: 'unknown', label: 'No roadside data' }, none);
  if (pos === 'Lost') {
    return Object.assign({ mode: 'unknown', label: 'Position lost' }, none);
  }
  const approx = pos === 'Estimated';
  if (z === 'InZone' || (finite(d) && d <= 0 && z !== 'Leaving' && z !== 'None' && z !== undefined)) {
    return { mode: 'inzone', label: approx ? 'Work zone · estimated' : 'Work zone', value: 'IN ZONE', unit: '', approx: false };
  }
  if (z === 'Leaving') return Object.assign({ mode: 'leaving', label: 'Leaving work zone' }, none);
  if (z === 'Approaching' || z === 'Warning') {
    const p = distanceParts(d, units);
    return { mode: z === 'Warning' ? 'warning' : 'approach', label: approx ? 'to work zone · estimated' : 'to work zone',
      value: p ? p.value : '—', unit: p ? p.unit : '', approx: approx && !!p };
  }
  return Object.assign({ mode: 'none', label: 'No work zone ahead' }, none);
}

/**
 * The tone the stage asks for: 'urgent' (repeats every 2 s), 'warning' (one group when
 * entered from a lower stage) or 'none'. Only while live.
 */
function toneFor(state, live) {
  if (!live || !state) return 'none';
  const st = stageOf(state);
  return st === 'Urgent' ? 'urgent' : st === 'Warning' ? 'warning' : 'none';
}

/** The lower limit ahead: { value, where } ("in 100 m" / "in 350 ft"); null when none. */
function limitAhead(state, units) {
  const s = state || {};
  if (!finite(s.limit_ahead_mps)) return null;
  if (!finite(s.limit_ahead_m)) return { value: speedText(s.limit_ahead_mps, units), where: 'ahead' };
  const d = Math.max(0, s.limit_ahead_m);
  const ft = d * M_TO_FT;
  const p = unitsOf(units) === 'mph' && ft < 1000
    ? { value: String(roundTo(ft, ft >= 300 ? 50 : 10)), unit: 'ft' } : distanceParts(d, units);
  return { value: speedText(s.limit_ahead_mps, units), where: 'in ' + p.value + ' ' + p.unit };
}

/** Metres <-> the distance unit of the settings form (ft with mph). */
function formDistance(m, units) {
  return unitsOf(units) === 'mph' ? Math.round(m * M_TO_FT) : Math.round(m);
}

function metresFromForm(v, units) {
  return unitsOf(units) === 'mph' ? Math.round((v / M_TO_FT) * 10) / 10 : v;
}

/** The warning-distance range in the form's unit: the contract's metres, or the whole feet within them. */
function formDistanceRange(units) {
  const r = contract.settings.warning_distance_m;
  return unitsOf(units) === 'mph'
    ? { min: Math.ceil(r.min * M_TO_FT), max: Math.floor(r.max * M_TO_FT), unit: 'ft' }
    : { min: r.min, max: r.max, unit: r.unit };
}

const FIX_NAMES = { 0: 'no fix', 1: 'GPS', 2: 'DGPS', 3: 'PPS', 4: 'RTK', 5: 'RTK float', 6: 'dead reck.', 7: 'manual', 8: 'sim' };

function fixName(q) {
  return finite(q) ? (FIX_NAMES[q] || 'fix ' + q) : '';
}

/**
 * The roadside chip: whether there is roadside data and whether it came signed. The core
 * counts in `unverified` the maps and zones that came without a verified IEEE 1609.2
 * signature (only possible when the unit does not require signatures); they are shown,
 * marked. `trust` is 'signed', 'unverified' or 'none' (no data).
 */
function roadsideChip(state, live) {
  if (!state || !state.roadside_data) {
    return { cls: live ? 'chip-warn' : 'chip-muted', text: 'No roadside data', trust: 'none' };
  }
  if (finite(state.unverified) && state.unverified > 0) {
    return { cls: live ? 'chip-warn' : 'chip-muted', text: 'Roadside data · UNVERIFIED', trust: 'unverified' };
  }
  return { cls: live ? 'chip-ok' : 'chip-muted', text: 'Roadside data · signed', trust: 'signed' };
}

/** Seconds with one decimal below 10 s, else whole. */
function ageText(ms) {
  if (!finite(ms)) return '';
  const s = ms / 1000;
  return (s < 10 ? s.toFixed(1) : Math.round(s)) + ' s';
}

export { contract, KINDS, STAGES, MPS_TO, M_TO_FT, speedValue, speedText, speedUnitLabel, distanceParts,
  distanceText, aheadText, describeAlert, calmBanner, banner, distanceView, stageOf, stageRank, stageSev,
  positionOf, toneFor, limitAhead, formDistance, metresFromForm, formDistanceRange,
  fixName, ageText, finite, roadsideChip };
