/* Lane diagram of the road ahead: a pure model (unit-tested in node) and an SVG renderer. */
import { contract } from './format.js';

const LW = 100;        // lane width, SVG units
const SHOULDER = 16;
const H = 320;
const TOP = 14;        // far end of the drawn road
const CAR_H = 78;
const CAR_W = 46;
const CAR_TOP = H - CAR_H - 26;
const CAR_BOTTOM = CAR_TOP + CAR_H;
const UNCERTAIN_BELOW = 50; // lane_confidence percent under which the car is drawn as a guess
const LANE_M = 3.5;    // a lane's width on the road, metres (workers' lateral offsets)

function num(x) {
  return typeof x === 'number' && Number.isFinite(x);
}

function laneIds(list) {
  return Array.isArray(list) ? list.filter((x) => Number.isInteger(x)) : [];
}

/**
 * Lanes left to right. With `road_lanes` from the server the order is known; without it the
 * ids of the closed lanes and the own lane are sorted and a placeholder open lane is added on
 * the side the advice points to, and the model says it is approximate.
 */
function laneOrder(state) {
  const road = laneIds(state.road_lanes);
  const closed = laneIds(state.closed_lanes);
  const own = state.lane && Number.isInteger(state.lane.lane) ? state.lane.lane : null;
  if (road.length) return { ids: road, approximate: false };
  const set = new Set(closed);
  if (own !== null) set.add(own);
  const ids = Array.from(set).sort((a, b) => a - b);
  if (!ids.length) return { ids: [], approximate: true };
  const pivot = own !== null ? own : null;
  const allClosed = ids.every((id) => closed.includes(id));
  const needLeft = state.advice === 'MoveLeft' && (pivot === null ? allClosed : ids[0] === pivot);
  const needRight = state.advice === 'MoveRight' && (pivot === null ? allClosed : ids[ids.length - 1] === pivot);
  if (needLeft) ids.unshift(null);
  if (needRight) ids.push(null);
  return { ids, approximate: true };
}

/** Vertical extent of the closure on screen, or null when none is drawn. */
function closureSpan(state, rangeM) {
  const z = state.zone_state;
  const d = state.distance_m;
  if (z === 'InZone') return { from: TOP, to: H, faded: false };
  if (z === 'Leaving') return { from: CAR_BOTTOM + 12, to: H, faded: true };
  if ((z === 'Approaching' || z === 'Warning') && num(d)) {
    const f = Math.max(0, Math.min(1, d / rangeM));
    const y = Math.round(CAR_TOP - 6 - f * (CAR_TOP - 6 - TOP));
    return { from: TOP, to: Math.max(TOP, y), faded: false };
  }
  return { from: TOP, to: TOP + 60, faded: true };
}

/** Distance shown by the full height: the daemon's approach distance (3x the warning distance). */
function rangeFor(state, settings) {
  const warn = settings && num(settings.warning_distance_m) ? settings.warning_distance_m : contract.settings.warning_distance_m.default;
  const lead = settings && num(settings.lead_time_s) ? settings.lead_time_s : contract.settings.lead_time_s.default;
  const v = num(state.speed_mps) ? state.speed_mps : 0;
  return 3 * Math.max(warn, v * lead, 20);
}

function model(state, settings) {
  const s = state || {};
  const order = laneOrder(s);
  const closed = laneIds(s.closed_lanes);
  const own = s.lane && Number.isInteger(s.lane.lane) ? s.lane.lane : null;
  const lanes = order.ids.map((id) => ({ id, closed: id !== null && closed.includes(id), own: id !== null && id === own }));
  const carIndex = lanes.findIndex((l) => l.own);
  const conf = num(s.lane_confidence) ? s.lane_confidence : 0;
  const pos = s.position === 'Live' || s.position === 'Estimated' || s.position === 'Lost'
    ? s.position : (s.gnss_ok === false ? 'Lost' : 'Live');
  let message = '';
  if (pos === 'Lost') message = s.gnss_ok === false && !s.position ? 'No GNSS' : 'Position lost';
  else if (s.roadside_data === false) message = 'No roadside data';
  else if (!lanes.length) message = 'No lane data';
  else if (own === null) message = 'Lane unknown';
  else if (carIndex < 0) message = 'Off the mapped lanes';
  const hasClosure = lanes.some((l) => l.closed);
  const range = rangeFor(s, settings);
  return {
    lanes,
    approximate: order.approximate && lanes.length > 0 && !message,
    carIndex: carIndex >= 0 ? carIndex : null,
    carUncertain: carIndex >= 0 && (conf < UNCERTAIN_BELOW || pos === 'Estimated'),
    estimated: pos === 'Estimated',
    advice: carIndex >= 0 && (s.advice === 'MoveLeft' || s.advice === 'MoveRight') ? s.advice : 'None',
    span: hasClosure ? closureSpan(s, range) : null,
    workers: carIndex >= 0 && !message ? workerMarks(s, carIndex, range) : [],
    message,
  };
}

/**
 * Workers ahead on the diagram: each at its distance along the own lane (the diagram's
 * scale, the car's front at 0) and its lateral offset from the own lane's centre (3.5 m a
 * lane); those in the own lane's path are marked. Behind the car or beyond the range: not
 * drawn.
 */
function workerMarks(state, carIndex, rangeM) {
  const list = Array.isArray(state.workers) ? state.workers : [];
  return list
    .filter((w) => w && num(w.distance_m) && num(w.lateral_m) && w.distance_m >= 0 && w.distance_m <= rangeM)
    .map((w) => {
      const f = w.distance_m / rangeM;
      const y = Math.round(CAR_TOP - 6 - f * (CAR_TOP - 6 - TOP));
      const x = Math.round(laneX(carIndex) + LW / 2 + (w.lateral_m / LANE_M) * LW);
      return { id: Number.isInteger(w.id) ? w.id : null, x, y, inPath: w.in_own_lane_path === true };
    });
}

// ---- SVG ----

function defs() {
  return '<defs>' +
    '<pattern id="hatch" width="22" height="22" patternUnits="userSpaceOnUse" patternTransform="rotate(45)">' +
    '<rect width="22" height="22" class="hatch-a"/><rect width="11" height="22" class="hatch-b"/></pattern>' +
    '<linearGradient id="fade" x1="0" y1="0" x2="0" y2="1"><stop offset="0" stop-color="#000" stop-opacity=".55"/>' +
    '<stop offset=".25" stop-color="#000" stop-opacity="0"/></linearGradient>' +
    '</defs>';
}

function laneX(i) {
  return SHOULDER + i * LW;
}

function roadSvg(m, W) {
  let s = `<rect class="road" x="0" y="0" width="${W}" height="${H}"/>`;
  const dash = m.approximate ? ' stroke-dasharray="4 10"' : '';
  s += `<line class="edge" x1="${SHOULDER - 4}" y1="0" x2="${SHOULDER - 4}" y2="${H}"${dash}/>`;
  s += `<line class="edge" x1="${W - SHOULDER + 4}" y1="0" x2="${W - SHOULDER + 4}" y2="${H}"${dash}/>`;
  for (let i = 1; i < m.lanes.length; i++) {
    const x = laneX(i);
    s += `<line class="divider" x1="${x}" y1="0" x2="${x}" y2="${H}" stroke-dasharray="26 22"/>`;
  }
  return s;
}

function closureSvg(m) {
  if (!m.span) return '';
  const { from, to, faded } = m.span;
  let s = '';
  m.lanes.forEach((l, i) => {
    const x = laneX(i) + 4;
    const cls = 'lane-rect lane' + (l.closed ? ' closed' : ' open') + (l.own ? ' own' : '');
    const id = l.id === null ? '' : ` data-lane-id="${l.id}"`;
    if (!l.closed) {
      s += `<rect class="${cls}"${id} x="${x}" y="${from}" width="${LW - 8}" height="0"/>`;
      return;
    }
    s += `<g class="${cls}${faded ? ' faded' : ''}"${id}>`;
    s += `<rect x="${x}" y="${from}" width="${LW - 8}" height="${Math.max(0, to - from)}" fill="url(#hatch)" rx="3"/>`;
    s += `<rect class="closure-edge" x="${x}" y="${from}" width="${LW - 8}" height="${Math.max(0, to - from)}" rx="3"/>`;
    // cones across the start of the closure (the taper) when it lies ahead, else a row of
    // cones along the closure's edge
    const cy = to - 30;
    const ahead = to < CAR_TOP;
    if (!ahead && !faded) {
      const leftOpen = i > 0 && !m.lanes[i - 1].closed;
      const edgeX = leftOpen ? x - 18 : x + LW - 18; // centred on the boundary with an open lane
      for (let y = from + 30; y < to - 20; y += 74) {
        s += `<use href="#i-cone" class="cone" x="${edgeX}" y="${y}" width="28" height="28"/>`;
      }
    } else if (to - from > 40) {
      s += `<use href="#i-cone" class="cone" x="${x + 6}" y="${cy}" width="28" height="28"/>`;
      s += `<use href="#i-cone" class="cone" x="${x + LW / 2 - 18}" y="${cy - 4}" width="28" height="28"/>`;
      s += `<use href="#i-cone" class="cone" x="${x + LW - 8 - 34}" y="${cy - 8}" width="28" height="28"/>`;
    }
    if (ahead && to - from > 130) {
      s += `<use href="#i-cone" class="cone cone-big" x="${x + LW / 2 - 26}" y="${from + (to - from) / 2 - 44}" width="44" height="44"/>`;
    }
    s += '</g>';
  });
  return s;
}

/** Lane markers for tests and screen readers even without a closure. */
function laneMarkers(m) {
  if (m.span) return '';
  return m.lanes.map((l, i) => {
    const id = l.id === null ? '' : ` data-lane-id="${l.id}"`;
    const cls = 'lane-rect lane' + (l.closed ? ' closed' : ' open') + (l.own ? ' own' : '');
    return `<rect class="${cls}"${id} x="${laneX(i) + 4}" y="${TOP}" width="${LW - 8}" height="0"/>`;
  }).join('');
}

function carSvg(m) {
  if (m.carIndex === null) return '';
  const cx = laneX(m.carIndex) + LW / 2;
  const x = cx - CAR_W / 2;
  const cls = 'car' + (m.carUncertain ? ' uncertain' : '') + (m.lanes[m.carIndex].closed ? ' on-closed' : '');
  let s = `<g class="${cls}" data-lane-index="${m.carIndex}">`;
  s += `<rect class="car-body" x="${x}" y="${CAR_TOP}" width="${CAR_W}" height="${CAR_H}" rx="13"/>`;
  s += `<path class="car-glass" d="M${x + 7} ${CAR_TOP + 24} q${CAR_W / 2 - 7} -10 ${CAR_W - 14} 0 l-3 14 h${-(CAR_W - 20)} z"/>`;
  s += `<rect class="car-glass" x="${x + 9}" y="${CAR_TOP + CAR_H - 18}" width="${CAR_W - 18}" height="8" rx="3"/>`;
  if (m.carUncertain) s += `<text class="car-q" x="${cx}" y="${CAR_TOP + CAR_H / 2 + 16}" text-anchor="middle">?</text>`;
  s += '</g>';
  return s;
}

function workersSvg(m, W) {
  return m.workers
    .filter((w) => w.x > -20 && w.x < W + 20)
    .map((w) => {
      const cls = 'worker' + (w.inPath ? ' in-path' : '');
      const id = w.id === null ? '' : ` data-worker-id="${w.id}"`;
      return `<g class="${cls}"${id}>` + (w.inPath ? `<circle class="worker-halo" cx="${w.x}" cy="${w.y - 14}" r="24"/>` : '') +
        `<use href="#i-worker" x="${w.x - 16}" y="${w.y - 32}" width="32" height="32"/></g>`;
    }).join('');
}

function adviceSvg(m) {
  if (m.advice === 'None' || m.carIndex === null) return '';
  const dir = m.advice === 'MoveLeft' ? -1 : 1;
  const x0 = laneX(m.carIndex) + LW / 2;
  const x1 = x0 + dir * LW;
  const y0 = CAR_TOP - 8;
  const y1 = Math.max(TOP + 40, CAR_TOP - 120);
  const d = `M${x0} ${y0} C${x0} ${y0 - 50} ${x1} ${y1 + 60} ${x1} ${y1 + 22}`;
  const head = `M${x1 - 22} ${y1 + 26} L${x1} ${y1 - 6} L${x1 + 22} ${y1 + 26} Z`;
  return `<g class="advice" data-advice="${m.advice}"><path class="advice-outline" d="${d}"/><path class="advice-outline" d="${head}"/>` +
    `<path class="advice-line" d="${d}"/><path class="advice-head" d="${head}"/></g>`;
}

function messageSvg(m, W) {
  if (!m.message) return '';
  return `<g class="lanes-msg"><rect x="${W / 2 - 120}" y="${H / 2 - 26}" width="240" height="52" rx="10"/>` +
    `<text x="${W / 2}" y="${H / 2 + 10}" text-anchor="middle">${m.message}</text></g>`;
}

function render(svg, state, settings) {
  const m = model(state, settings);
  const n = Math.max(m.lanes.length, 2);
  const W = SHOULDER * 2 + n * LW;
  const padded = m.lanes.length ? m : Object.assign({}, m, { lanes: [{ id: null }, { id: null }] });
  const html = defs() + roadSvg(padded, W) + closureSvg(m) + laneMarkers(m) + workersSvg(m, W) + adviceSvg(m) + carSvg(m) +
    '<rect x="0" y="0" width="' + W + '" height="' + H + '" fill="url(#fade)" pointer-events="none"/>' + messageSvg(m, W);
  if (svg.__last !== html) {
    svg.__last = html;
    svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
    svg.innerHTML = html;
  }
  return m;
}

function describe(m) {
  if (!m.lanes.length) return m.message || 'No lanes';
  const parts = m.lanes.map((l, i) => `lane ${i + 1}${l.closed ? ' closed' : ''}${l.own ? ' (you)' : ''}`);
  const inPath = m.workers.filter((w) => w.inPath).length;
  const workers = m.workers.length ? `; ${m.workers.length} worker${m.workers.length > 1 ? 's' : ''} ahead` +
    (inPath ? `, ${inPath} in your lane` : '') : '';
  return parts.join(', ') + (m.advice !== 'None' ? '; move ' + (m.advice === 'MoveLeft' ? 'left' : 'right') : '') + workers;
}

export { model, laneOrder, render, describe, UNCERTAIN_BELOW };
