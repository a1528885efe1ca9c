// Checks of what is on screen, run in the page: layout overflow and the one-red rule, plus the
// stage scenes both the browser tests and the README screenshots go through.

/** In the page: every visible element that is cut, overflows its box or wraps a quantity. */
export function overflowReport() {
  const out = [];
  const vw = window.innerWidth;
  const vh = window.innerHeight;
  const name = (el) => el.id ? '#' + el.id : el.tagName.toLowerCase() + (typeof el.className === 'string' && el.className ? '.' + el.className.trim().split(/\s+/).join('.') : '');
  const text = (el) => (el.textContent || '').trim().slice(0, 40);
  const shown = (el, cs) => cs.display !== 'none' && cs.visibility !== 'hidden';
  const clipped = (cs) => cs.overflowX !== 'visible' || cs.overflowY !== 'visible';
  for (const el of document.querySelectorAll('body *')) {
    if (el.closest('defs, symbol, script, style, template')) continue;
    if (el instanceof SVGElement && el.tagName.toLowerCase() !== 'svg') continue;
    const cs = getComputedStyle(el);
    if (!shown(el, cs)) continue;
    let hiddenAncestor = false;
    for (let a = el.parentElement; a; a = a.parentElement) {
      const acs = getComputedStyle(a);
      if (acs.display === 'none') { hiddenAncestor = true; break; }
    }
    if (hiddenAncestor) continue;
    const r = el.getBoundingClientRect();
    if (r.width <= 1 || r.height <= 1) continue; // nothing drawn (or a screen-reader-only text)
    const inScroller = !!el.parentElement && !!el.parentElement.closest('.page');
    if (r.left < -0.5 || r.right > vw + 0.5 || (!inScroller && (r.top < -0.5 || r.bottom > vh + 0.5))) {
      out.push(`${name(el)} "${text(el)}" outside the viewport: ${JSON.stringify(r.toJSON())}`);
    }
    for (let a = el.parentElement; a && a !== document.documentElement; a = a.parentElement) {
      const acs = getComputedStyle(a);
      if (!clipped(acs)) continue;
      const ar = a.getBoundingClientRect();
      // a vertically scrolling page is not a cut below its fold
      const scrollsY = acs.overflowY === 'auto' || acs.overflowY === 'scroll';
      const outY = !scrollsY && (r.top < ar.top - 0.5 || r.bottom > ar.bottom + 0.5);
      if (r.left < ar.left - 0.5 || r.right > ar.right + 0.5 || outY) {
        out.push(`${name(el)} "${text(el)}" cut by ${name(a)}: ${Math.round(r.left)}..${Math.round(r.right)} x ${Math.round(r.top)}..${Math.round(r.bottom)} in ${Math.round(ar.left)}..${Math.round(ar.right)} x ${Math.round(ar.top)}..${Math.round(ar.bottom)}`);
      }
      break;
    }
    const ownText = [...el.childNodes].some((n) => n.nodeType === 3 && n.textContent.trim());
    if (ownText && cs.display !== 'inline' && (el.scrollWidth > el.clientWidth + 1 || (clipped(cs) && el.scrollHeight > el.clientHeight + 1))) {
      out.push(`${name(el)} "${text(el)}" text overflows: ${el.scrollWidth}x${el.scrollHeight} in ${el.clientWidth}x${el.clientHeight}`);
    }
  }
  // a number and its unit, a chip, a sign value: on one line
  for (const el of document.querySelectorAll('.qty, .chip, .other, .speed, .limit-value, .ahead-where, .pos-marker, .sound-label, .btn')) {
    const r = el.getBoundingClientRect();
    if (r.width <= 1 || !el.checkVisibility()) continue;
    // the text's line boxes: two that do not overlap vertically are two lines
    const rects = [];
    const walker = document.createTreeWalker(el, NodeFilter.SHOW_TEXT);
    for (let n = walker.nextNode(); n; n = walker.nextNode()) {
      if (!n.textContent.trim()) continue;
      const range = document.createRange();
      range.selectNodeContents(n);
      rects.push(...[...range.getClientRects()].filter((q) => q.width > 0));
    }
    const wrapped = rects.some((a) => rects.some((b) => b.top >= a.bottom - 1));
    if (wrapped) out.push(`${name(el)} "${text(el)}" wraps over several lines`);
  }
  return out;
}

const live = (s) => s.position === 'Live' && s.time_status !== 'Unverified';
const reset = [['gnss_back', null], ['time_ok', null]];

/**
 * The stage scenes: driver steps (each a scene or switch, and the state to wait for before
 * the next step), then what the server must send for the stage.
 */
export const STAGES = [
  { name: 'information', steps: [...reset, ['approach', null]], pred: (s) => live(s) && s.stage === 'Information' && s.zone_state === 'Approaching' },
  { name: 'warning', steps: [...reset, ['warning', null]], pred: (s) => live(s) && s.stage === 'Warning' },
  { name: 'urgent', steps: [...reset, ['urgent', null]], pred: (s) => live(s) && s.stage === 'Urgent' },
  { name: 'in_zone', steps: [...reset, ['in_zone', null]], pred: (s) => live(s) && s.zone_state === 'InZone' && s.stage !== 'Urgent' },
  { name: 'estimated', steps: [...reset, ['warning', (s) => live(s) && s.stage === 'Warning'], ['gnss_lost', null]],
    pred: (s) => s.position === 'Estimated' && s.zone_state !== 'None' && s.distance_m !== null },
  { name: 'lost', steps: [...reset, ['approach', (s) => live(s) && s.zone_state === 'Approaching'], ['gnss_lost', null]],
    pred: (s) => s.position === 'Lost', timeout: 15000 },
  { name: 'time_unverified', steps: [...reset, ['approach', (s) => live(s) && s.zone_state === 'Approaching'], ['time_fault', null]],
    pred: (s) => s.time_status === 'Unverified' && s.position === 'Live' },
];

export const VIEWPORTS = [
  { name: 'phone', width: 390, height: 844 },
  { name: 'tablet', width: 1280, height: 800 },
];

/** Every layout the checks run at: the phone widths 360-430 px and the tablet. */
export const LAYOUTS = [
  { name: 'phone360', width: 360, height: 740 },
  ...VIEWPORTS.slice(0, 1),
  { name: 'phone430', width: 430, height: 932 },
  ...VIEWPORTS.slice(1),
];
