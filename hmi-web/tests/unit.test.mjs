// Unit tests of the page's pure parts (format.js, lanes.js model), run in node: no browser, no server.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const F = require('../format.js');
const L = require('../lanes.js');

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
  assert.equal(F.distanceView({ zone_state: 'None', gnss_ok: false }, 'kmh').label, 'Position unknown');
  assert.equal(F.distanceView({ zone_state: 'Approaching', distance_m: null }, 'kmh').value, '—');
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

test('tone while Warning, Overspeed or own lane closed; urgency', () => {
  assert.equal(F.toneWanted({ zone_state: 'Warning', primary: null }), true);
  assert.equal(F.toneWanted({ zone_state: 'InZone', primary: { kind: 'Overspeed' } }), true);
  assert.equal(F.toneWanted({ zone_state: 'Approaching', primary: { kind: 'LaneClosedOwn' } }), true);
  assert.equal(F.toneWanted({ zone_state: 'Approaching', primary: { kind: 'ReducedSpeedAhead' } }), false);
  assert.equal(F.toneWanted({ zone_state: 'InZone', primary: null }), false);
  assert.equal(F.toneWanted(null), false);
  assert.equal(F.toneLevel({ primary: { kind: 'Overspeed' } }), 'high');
  assert.equal(F.toneLevel({ zone_state: 'Warning', primary: { kind: 'ReducedSpeedAhead' } }), 'normal');
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
