/* Pure formatting and alert wording. No DOM: also loaded by the node unit tests. */
(function (root) {
  'use strict';

  const MPS_TO = { kmh: 3.6, mph: 2.23694 };
  const M_TO_FT = 3.28084;
  const FT_PER_MILE = 5280;

  /** Alert kinds, highest priority first (the server already picks `primary`). */
  const KINDS = ['Overspeed', 'LaneClosedOwn', 'ReducedSpeedAhead', 'LaneClosedOther',
    'WorkZoneAhead', 'GnssStale', 'MapMissing', 'NoRoadsideData'];

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

  /** "in 120 m" / "here" / "" for an alert distance. */
  function aheadText(m, units) {
    if (!finite(m)) return '';
    if (m <= 0) return 'here';
    return 'in ' + distanceText(m, units);
  }

  /**
   * Wording, colour and icon of one alert.
   * sev: red (act now), amber (prepare), orange (work zone info), info (system).
   */
  function describeAlert(alert, ctx) {
    const units = ctx && ctx.units;
    const advice = (ctx && ctx.advice) || 'None';
    const a = alert || {};
    const ahead = aheadText(a.distance_m, units);
    const limit = finite(a.limit_mps) ? a.limit_mps : (ctx && ctx.limit_mps);
    switch (a.kind) {
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

  /** The banner when the server has no primary alert. */
  function calmBanner(state, units) {
    if (state && state.gnss_ok === false) return describeAlert({ kind: 'GnssStale' }, { units });
    if (state && state.roadside_data === false) return describeAlert({ kind: 'NoRoadsideData' }, { units });
    switch (state && state.zone_state) {
      case 'InZone':
        return { sev: 'orange', icon: 'i-cone', title: 'In work zone', detail: 'Keep to the limit' };
      case 'Leaving':
        return { sev: 'calm', icon: 'i-flag', title: 'Leaving work zone', detail: '' };
      case 'Approaching':
      case 'Warning':
        return { sev: 'orange', icon: 'i-diamond', title: 'Work zone ahead', detail: aheadText(state.distance_m, units) };
      default:
        return { sev: 'calm', icon: 'i-ok', title: 'No warnings', detail: '' };
    }
  }

  /** What the big distance field says. */
  function distanceView(state, units) {
    const z = state && state.zone_state;
    const d = state && state.distance_m;
    if (state && state.gnss_ok === false) return { mode: 'unknown', label: 'Position unknown', value: '', unit: '' };
    if (state && state.roadside_data === false) return { mode: 'unknown', label: 'No roadside data', value: '', unit: '' };
    if (z === 'InZone' || (finite(d) && d <= 0 && z !== 'Leaving' && z !== 'None' && z !== undefined)) {
      return { mode: 'inzone', label: 'Work zone', value: 'IN ZONE', unit: '' };
    }
    if (z === 'Leaving') return { mode: 'leaving', label: 'Leaving work zone', value: '', unit: '' };
    if (z === 'Approaching' || z === 'Warning') {
      const p = distanceParts(d, units);
      return { mode: z === 'Warning' ? 'warning' : 'approach', label: 'to work zone',
        value: p ? p.value : '—', unit: p ? p.unit : '' };
    }
    return { mode: 'none', label: 'No work zone ahead', value: '', unit: '' };
  }

  /** True while the audible warning must repeat. */
  function toneWanted(state) {
    if (!state) return false;
    const k = state.primary && state.primary.kind;
    return state.zone_state === 'Warning' || k === 'Overspeed' || k === 'LaneClosedOwn';
  }

  /** Urgency of the tone: 'high' for act-now alerts, 'normal' for the zone warning. */
  function toneLevel(state) {
    const k = state && state.primary && state.primary.kind;
    return k === 'Overspeed' || k === 'LaneClosedOwn' ? 'high' : 'normal';
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
      return { cls: live ? 'chip-bad' : 'chip-muted', text: 'No roadside data', trust: 'none' };
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

  const api = { KINDS, MPS_TO, M_TO_FT, speedValue, speedText, speedUnitLabel, distanceParts,
    distanceText, aheadText, describeAlert, calmBanner, distanceView, toneWanted, toneLevel,
    fixName, ageText, finite, roadsideChip };
  root.HmiFormat = api;
  if (typeof module === 'object' && module.exports) module.exports = api;
})(typeof window !== 'undefined' ? window : globalThis);
