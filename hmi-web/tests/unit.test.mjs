// Unit tests of the page's pure parts (format.js, lanes.js model), run in node: no browser, no server.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { createSound } from '../sound.js';

// The app fetches its contract beside itself; node's fetch does not read files, so the
// modules' file: URLs are read from the disk here (anything else goes to node's fetch).
const netFetch = globalThis.fetch;
globalThis.fetch = async (url, opts) => (String(url).startsWith('file:')
  ? { ok: true, json: async () => JSON.parse(fs.readFileSync(new URL(String(url)), 'utf8')) }
  : netFetch(url, opts));
const F = await import('../format.js');
const L = await import('../lanes.js');

test('speed in km/h and mph, rounded, never negative', () => {
  assert.equal(F.speedText(11.1111, 'kmh'), '40');
  assert.equal(F.speedText(11.176, 'mph'), '25');
  assert.equal(F.speedText(-0.1, 'kmh'), '0');
  assert.equal(F.speedText(null, 'kmh'), '--');
  assert.equal(F.speedText(undefined, 'mph'), '--');
  assert.equal(F.speedUnitLabel('mph'), 'mph');
  assert.equal(F.speedUnitLabel('kmh'), 'km/h');
  assert.equal(F.speedUnitLabel('bogus'), 'km/h');
});

test('distances: m/km and ft/mi, coarse when far', () => {
  assert.deepEqual(F.distanceParts(37.4, 'kmh'), { value: '37', unit: 'm' });
  assert.deepEqual(F.distanceParts(87.4, 'kmh'), { value: '85', unit: 'm' });
  assert.deepEqual(F.distanceParts(434, 'kmh'), { value: '430', unit: 'm' });
  assert.deepEqual(F.distanceParts(1250, 'kmh'), { value: '1.3', unit: 'km' });
  assert.deepEqual(F.distanceParts(-20, 'kmh'), { value: '20', unit: 'm' });
  assert.deepEqual(F.distanceParts(30, 'mph'), { value: '100', unit: 'ft' });
  assert.deepEqual(F.distanceParts(120, 'mph'), { value: '400', unit: 'ft' });
  assert.deepEqual(F.distanceParts(1609.344, 'mph'), { value: '1.0', unit: 'mi' });
  assert.equal(F.distanceParts(null, 'kmh'), null);
  assert.equal(F.distanceParts(NaN, 'kmh'), null);
});

test('distance field: countdown, in zone, leaving, unknown', () => {
  assert.equal(F.distanceView({ zone_state: 'Warning', distance_m: 88, gnss_ok: true, roadside_data: true }, 'kmh').value, '90');
  assert.equal(F.distanceView({ zone_state: 'InZone', distance_m: -12 }, 'kmh').value, 'IN ZONE');
  assert.equal(F.distanceView({ zone_state: 'Leaving', distance_m: -130 }, 'kmh').mode, 'leaving');
  assert.equal(F.distanceView({ zone_state: 'None', distance_m: null }, 'kmh').label, 'No work zone ahead');
  assert.equal(F.distanceView({ zone_state: 'None', gnss_ok: false }, 'kmh').label, 'Position lost');
  assert.equal(F.distanceView({ zone_state: 'Approaching', distance_m: null }, 'kmh').value, '—');
});

test('the app knows every alert kind and stage of the core\'s contract', () => {
  const contract = JSON.parse(fs.readFileSync(new URL('../contract.json', import.meta.url), 'utf8'));
  assert.equal(contract.alert_kinds[0], 'WorkerInLane', 'a person in the path first');
  for (const kind of contract.alert_kinds) {
    const d = F.describeAlert({ kind, distance_m: 80, limit_mps: 11.11 }, { units: 'kmh', advice: 'None' });
    assert.notEqual(d.title, kind, `${kind} has its own wording, not the unknown kind's fallback`);
  }
  // What each stage looks and sounds like: a stage the core adds fails here until the app
  // (and this table) give it its colour and tone.
  const looks = { None: ['zone', 'none'], Information: ['amber', 'none'], Warning: ['red', 'warning'], Urgent: ['red', 'urgent'] };
  assert.deepEqual(Object.keys(looks), contract.stages);
  for (const stage of contract.stages) {
    const state = { stage, primary: { kind: 'ReducedSpeedAhead' } };
    assert.deepEqual([F.stageSev(stage, 'amber'), F.toneFor(state, true)], looks[stage], stage);
  }
  // The form's feet: the whole feet within the contract's metres.
  const metres = contract.settings.warning_distance_m;
  const feet = F.formDistanceRange('mph');
  assert.ok(F.metresFromForm(feet.min, 'mph') >= metres.min && F.metresFromForm(feet.max, 'mph') <= metres.max, JSON.stringify(feet));
  assert.ok(F.metresFromForm(feet.min - 1, 'mph') < metres.min && F.metresFromForm(feet.max + 1, 'mph') > metres.max, 'whole feet');
});

test('every alert kind has a colour, an icon and short text', () => {
  for (const kind of F.KINDS) {
    const d = F.describeAlert({ kind, distance_m: 80, limit_mps: 11.11 }, { units: 'kmh', advice: 'None' });
    assert.ok(['red', 'amber', 'orange', 'info'].includes(d.sev), kind);
    assert.match(d.icon, /^i-/);
    assert.ok(d.title.length > 0 && d.title.length <= 22, `${kind}: "${d.title}" is short`);
  }
  const own = (advice) => F.describeAlert({ kind: 'LaneClosedOwn', distance_m: 80 }, { units: 'kmh', advice });
  assert.equal(own('MoveLeft').title, 'Change lane left');
  assert.equal(own('MoveRight').title, 'Change lane right');
  assert.equal(own('None').title, 'Your lane is closed');
  assert.equal(own('MoveLeft').sev, 'red');
  const r = F.describeAlert({ kind: 'ReducedSpeedAhead', distance_m: 120, limit_mps: 11.176 }, { units: 'mph' });
  assert.equal(r.detail, '25 mph in 400 ft');
  assert.equal(F.describeAlert({ kind: 'Overspeed', limit_mps: null }, { units: 'kmh', limit_mps: 11.1111 }).detail, 'Limit 40 km/h');
  assert.equal(F.describeAlert({ kind: 'SomethingNew' }, {}).title, 'SomethingNew');
});

test('stage: from the server, or from the old rules without it; colour follows the stage only', () => {
  assert.equal(F.stageOf({ stage: 'Urgent' }), 'Urgent');
  assert.equal(F.stageOf({ stage: 'bogus', zone_state: 'Warning' }), 'Warning');
  assert.equal(F.stageOf({ zone_state: 'InZone', primary: { kind: 'Overspeed' } }), 'Urgent');
  assert.equal(F.stageOf({ zone_state: 'Approaching', primary: { kind: 'ReducedSpeedAhead' } }), 'Information');
  assert.equal(F.stageOf(null), 'None');
  assert.equal(F.stageSev('Warning', 'amber'), 'red');
  assert.equal(F.stageSev('Urgent', 'info'), 'red');
  assert.equal(F.stageSev('Information', 'red'), 'amber');
  assert.equal(F.stageSev('None', 'red'), 'zone', 'a red kind without a stage is not red');
  assert.equal(F.stageSev('None', 'info'), 'info');
  const b = (st, kind) => F.banner({ stage: st, zone_state: 'Warning', distance_m: 60, position: 'Live', primary: { kind, distance_m: 60 } }, 'kmh');
  assert.equal(b('Information', 'Overspeed').sev, 'amber');
  assert.equal(b('Warning', 'ReducedSpeedAhead').sev, 'red');
});

test('tone: urgent, warning or none, only while live', () => {
  assert.equal(F.toneFor({ stage: 'Urgent' }, true), 'urgent');
  assert.equal(F.toneFor({ stage: 'Warning' }, true), 'warning');
  assert.equal(F.toneFor({ stage: 'Information' }, true), 'none');
  assert.equal(F.toneFor({ stage: 'Urgent' }, false), 'none');
  assert.equal(F.toneFor(null, true), 'none');
});

test('position: estimated keeps the countdown marked, lost never shows green', () => {
  const est = { stage: 'Warning', zone_state: 'Warning', distance_m: 84, position: 'Estimated', gnss_ok: false, roadside_data: true };
  const v = F.distanceView(est, 'kmh');
  assert.equal(v.value, '85');
  assert.equal(v.approx, true);
  assert.match(v.label, /estimated/);
  assert.equal(F.banner({ ...est, primary: { kind: 'ReducedSpeedAhead', distance_m: 84, limit_mps: 11.12 } }, 'kmh').detail, '40 km/h in ≈ 85 m');
  const lost = { stage: 'None', zone_state: 'Approaching', distance_m: null, position: 'Lost', gnss_ok: false, roadside_data: true, primary: null };
  const b = F.banner(lost, 'kmh');
  assert.equal(b.title, 'Position lost');
  assert.notEqual(b.sev, 'calm');
  assert.match(b.detail, /Work zone ahead/);
  assert.equal(F.distanceView(lost, 'kmh').label, 'Position lost');
  assert.notEqual(F.calmBanner({ zone_state: 'None', position: 'Lost', gnss_ok: false }, 'kmh').sev, 'calm');
  assert.equal(F.positionOf({ gnss_ok: false }), 'Lost', 'an older core without position');
  assert.equal(F.positionOf({ gnss_ok: true }), 'Live');
  assert.equal(F.banner({ zone_state: 'None', position: 'Live', roadside_data: true }, 'kmh').sev, 'calm');
});

test('limit ahead plate, and the warning distance in ft with mph', () => {
  assert.deepEqual(F.limitAhead({ limit_ahead_mps: 11.12, limit_ahead_m: 100 }, 'kmh'), { value: '40', where: 'in 100 m' });
  assert.deepEqual(F.limitAhead({ limit_ahead_mps: 11.176, limit_ahead_m: 100 }, 'mph'), { value: '25', where: 'in 350 ft' });
  assert.equal(F.limitAhead({ limit_ahead_mps: null, limit_ahead_m: 100 }, 'kmh'), null);
  assert.equal(F.limitAhead({ limit_ahead_mps: 11.12, limit_ahead_m: null }, 'kmh').where, 'ahead');
  assert.equal(F.formDistance(150, 'mph'), 492);
  assert.equal(F.metresFromForm(492, 'mph'), 150);
  assert.equal(F.formDistance(150, 'kmh'), 150);
  const r = F.formDistanceRange('mph');
  assert.ok(F.metresFromForm(r.min, 'mph') >= 20 && F.metresFromForm(r.max, 'mph') <= 2000, 'the ft range stays within 20-2000 m');
});

const base = { zone_state: 'Warning', distance_m: 80, gnss_ok: true, roadside_data: true, lane_confidence: 90, advice: 'None' };

test('lanes from road_lanes: order, closed lanes, own lane, advice', () => {
  const m = L.model({ ...base, road_lanes: [4, 5, 6], closed_lanes: [6], lane: { map: 1, lane: 6 }, advice: 'MoveLeft' }, {});
  assert.deepEqual(m.lanes.map((l) => l.id), [4, 5, 6]);
  assert.deepEqual(m.lanes.map((l) => l.closed), [false, false, true]);
  assert.equal(m.carIndex, 2);
  assert.equal(m.advice, 'MoveLeft');
  assert.equal(m.approximate, false);
  assert.equal(m.carUncertain, false);
  assert.ok(m.span && m.span.to > m.span.from);
});

test('lanes without road_lanes: drawn from closed_lanes and lane, marked approximate', () => {
  const m = L.model({ ...base, road_lanes: [], closed_lanes: [3], lane: { map: 1, lane: 3 }, advice: 'MoveLeft' }, {});
  assert.deepEqual(m.lanes.map((l) => l.id), [null, 3], 'an open lane is added where the advice points');
  assert.equal(m.carIndex, 1);
  assert.equal(m.approximate, true);
  const r = L.model({ ...base, closed_lanes: [1, 2], lane: { map: 1, lane: 4 } }, {});
  assert.deepEqual(r.lanes.map((l) => l.id), [1, 2, 4]);
  const none = L.model({ ...base, closed_lanes: [], lane: null }, {});
  assert.equal(none.lanes.length, 0);
  assert.equal(none.message, 'No lane data');
});

test('the car is never claimed without a lane; low confidence is a guess', () => {
  const unknown = L.model({ ...base, road_lanes: [1, 2], closed_lanes: [2], lane: null }, {});
  assert.equal(unknown.carIndex, null);
  assert.equal(unknown.message, 'Lane unknown');
  const guess = L.model({ ...base, road_lanes: [1, 2], lane: { map: 1, lane: 1 }, lane_confidence: 30 }, {});
  assert.equal(guess.carUncertain, true);
  const nognss = L.model({ ...base, gnss_ok: false, road_lanes: [1, 2], lane: null }, {});
  assert.equal(nognss.message, 'No GNSS');
  const lost = L.model({ ...base, gnss_ok: false, position: 'Lost', road_lanes: [1, 2], lane: null }, {});
  assert.equal(lost.message, 'Position lost');
  const est = L.model({ ...base, gnss_ok: false, position: 'Estimated', road_lanes: [1, 2], lane: { map: 1, lane: 1 } }, {});
  assert.equal(est.message, '');
  assert.equal(est.carUncertain, true, 'a dead-reckoned car is drawn as a guess');
});

test('closure moves toward the car as the distance shrinks; spans it in the zone', () => {
  const at = (d, z = 'Warning') => L.model({ ...base, zone_state: z, distance_m: d, speed_mps: 11, road_lanes: [1, 2], closed_lanes: [2], lane: { map: 1, lane: 1 } }, { warning_distance_m: 100, lead_time_s: 9 }).span;
  assert.ok(at(250, 'Approaching').to < at(100).to);
  assert.ok(at(100).to < at(20).to);
  assert.equal(at(-10, 'InZone').to, 320);
  assert.equal(at(-150, 'Leaving').faded, true);
});

test('roadside chip: signed, unverified (marked), none', () => {
  assert.deepEqual(F.roadsideChip({ roadside_data: true, zones: 1, unverified: 0 }, true),
    { cls: 'chip-ok', text: 'Roadside data · signed', trust: 'signed' });
  const u = F.roadsideChip({ roadside_data: true, zones: 2, unverified: 1 }, true);
  assert.equal(u.trust, 'unverified');
  assert.equal(u.cls, 'chip-warn');
  assert.match(u.text, /UNVERIFIED/);
  assert.equal(F.roadsideChip({ roadside_data: false }, true).trust, 'none');
  assert.equal(F.roadsideChip(null, false).cls, 'chip-muted');
  assert.equal(F.roadsideChip({ roadside_data: true, unverified: 3 }, false).cls, 'chip-muted');
});

// ---- sound.js: the stage rules, with a fake AudioContext whose clock the test moves ----

function soundUnderTest() {
  const oscillators = [];
  const node = () => ({ connect(n) { return n; } });
  let audio = null;
  class FakeContext {
    constructor() { this.state = 'running'; this.currentTime = 0; this.destination = node(); audio = this; }
    resume() { return Promise.resolve(); }
    createOscillator() {
      const o = { ...node(), frequency: { value: 0 }, stopped: false, start() {}, stop() { o.stopped = true; } };
      oscillators.push(o);
      return o;
    }
    createBiquadFilter() { return { ...node(), frequency: { value: 0 } }; }
    createGain() { return { ...node(), gain: { setValueAtTime() {}, linearRampToValueAtTime() {} } }; }
  }
  const window = {
    AudioContext: FakeContext, localStorage: null, addEventListener() {}, setInterval() { return 0; },
    document: { addEventListener() {}, hidden: false },
  };
  const S = createSound(window);
  S.init({ allowed: true });
  return {
    S, oscillators,
    /** Feeds `tone` at 10 Hz for `s` seconds of audio time (as the app does on each state). */
    run(tone, s, live = true) {
      for (let t = 0; t < s - 1e-9; t += 0.1) {
        S.update(tone, live);
        audio.currentTime += 0.1;
      }
    },
  };
}

test('sound: Warning plays one group when entered from a lower stage, never repeats', () => {
  const { S, run } = soundUnderTest();
  run('none', 1);
  assert.equal(S.tonesScheduled(), 0);
  run('warning', 6);
  assert.equal(S.tonesScheduled(), 1, 'one group for entering Warning, none in 6 s');
  run('none', 0.5);
  run('warning', 1);
  assert.equal(S.tonesScheduled(), 2, 'entered again from a lower stage: one more');
});

test('sound: Urgent repeats every 2 s, stops at once when the stage drops or the link is lost', () => {
  const { S, oscillators, run } = soundUnderTest();
  run('urgent', 0.1);
  assert.equal(S.tonesScheduled(), 1, 'a group at once');
  run('urgent', 4.1);
  assert.equal(S.tonesScheduled(), 3, 'then every 2 s');
  run('warning', 3);
  assert.equal(S.tonesScheduled(), 3, 'Urgent -> Warning: no new group');
  assert.ok(oscillators.every((o) => o.stopped), 'the scheduled beeps are cut');
  run('urgent', 0.1);
  const n = S.tonesScheduled();
  assert.equal(n, 4);
  run('urgent', 3, false);
  assert.equal(S.tonesScheduled(), n, 'no tone while the link is lost');
  assert.ok(oscillators.every((o) => o.stopped));
  run('urgent', 0.1);
  assert.equal(S.tonesScheduled(), n + 1, 'the link is back in Urgent: it repeats again');
});

test('sound: a reconnect in the same Warning does not beep again; muted plays nothing', () => {
  const { S, run } = soundUnderTest();
  run('warning', 1);
  run('warning', 2, false);
  run('warning', 2);
  assert.equal(S.tonesScheduled(), 1);
  S.setAllowed(false);
  run('none', 0.2);
  run('urgent', 3);
  assert.equal(S.tonesScheduled(), 1, 'muted in the settings');
});

test('workers: the in-lane alert is red and named, the near-road one informs', () => {
  const inLane = F.describeAlert({ kind: 'WorkerInLane', stage: 'Warning', distance_m: 82 }, { units: 'kmh' });
  assert.equal(inLane.sev, 'red');
  assert.equal(inLane.title, 'WORKER IN LANE AHEAD');
  assert.equal(inLane.detail, 'A worker in your lane in 80 m');
  const near = F.describeAlert({ kind: 'WorkersNearRoad', distance_m: 140 }, { units: 'kmh' });
  assert.equal(near.sev, 'orange');
  assert.equal(near.title, 'Workers near the road');
  assert.equal(F.stageOf({ primary: { kind: 'WorkerInLane' } }), 'Warning');
});

test('workers on the lane diagram: at their distance and offset, the one in the path marked', () => {
  const state = {
    road_lanes: [1, 2, 3], lane: { lane: 2 }, lane_confidence: 90, position: 'Live', roadside_data: true,
    speed_mps: 10, zone_state: 'None',
    workers: [
      { id: 7, distance_m: 0, lateral_m: 0, in_own_lane_path: true },
      { id: 8, distance_m: 150, lateral_m: 3.5, in_own_lane_path: false },
      { id: 9, distance_m: -5, lateral_m: 0, in_own_lane_path: true },     // behind: not drawn
      { id: 10, distance_m: 1e6, lateral_m: 0, in_own_lane_path: false },  // beyond the range
      { id: 11, distance_m: NaN, lateral_m: 0 },                           // malformed
    ],
  };
  const m = L.model(state, { warning_distance_m: 100, lead_time_s: 9 });
  // Range 3 x 100 m; the car's lane (index 1) is centred at 16 + 100 + 50 = 166.
  assert.deepEqual(m.workers.map((w) => w.id), [7, 8]);
  assert.equal(m.workers[0].x, 166);
  assert.equal(m.workers[1].x, 266);
  assert.ok(m.workers[0].inPath && !m.workers[1].inPath);
  assert.ok(m.workers[1].y < m.workers[0].y, 'farther is higher up');
  assert.match(L.describe(m), /2 workers ahead, 1 in your lane$/);
  // No position: no workers drawn.
  assert.deepEqual(L.model(Object.assign({}, state, { position: 'Lost' }), {}).workers, []);
});
