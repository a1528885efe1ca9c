/* Audible warning: WebAudio beeps in the 1-5 kHz band, repeated every 2 s while wanted. */
(function (root) {
  'use strict';

  const PERIOD_S = 2.0;
  const LOOKAHEAD_S = 0.25;
  const KEY = 'hmi.sound.unlocked';
  // normal: two 2 kHz beeps; high (overspeed, own lane closed): three alternating 2.0/2.6 kHz beeps
  const PATTERNS = {
    normal: [{ f: 2000, at: 0, len: 0.16 }, { f: 2000, at: 0.26, len: 0.16 }],
    high: [{ f: 2000, at: 0, len: 0.12 }, { f: 2600, at: 0.18, len: 0.12 }, { f: 2000, at: 0.36, len: 0.12 }],
    confirm: [{ f: 1500, at: 0, len: 0.08 }, { f: 2000, at: 0.11, len: 0.1 }],
  };

  function storage() {
    try { return root.localStorage; } catch (e) { return null; }
  }

  const S = {
    ctx: null,
    allowed: true,
    wanted: false,
    level: 'normal',
    nextAt: 0,
    tones: 0,
    live: [],
    timer: null,
    onChange: () => {},
  };

  function Ctor() {
    return root.AudioContext || root.webkitAudioContext || null;
  }

  function ensureContext() {
    if (S.ctx || !S.allowed) return S.ctx;
    const C = Ctor();
    if (!C) return null;
    try {
      S.ctx = new C({ latencyHint: 'interactive' });
    } catch (e) {
      return null;
    }
    S.ctx.onstatechange = () => { S.onChange(state()); pump(); };
    return S.ctx;
  }

  function state() {
    if (!Ctor()) return 'unsupported';
    return S.ctx ? S.ctx.state : 'none';
  }

  /** Called from a user gesture (or any tap): create and resume the context. */
  function unlock(confirm) {
    const ctx = ensureContext();
    if (!ctx) return Promise.resolve(state());
    const st = storage();
    return ctx.resume().then(() => {
      if (st) st.setItem(KEY, '1');
      if (confirm && ctx.state === 'running') play(PATTERNS.confirm, ctx.currentTime + 0.02, 0.35);
      S.onChange(state());
      pump();
      return state();
    }, () => state());
  }

  function remembered() {
    const st = storage();
    return !!(st && st.getItem(KEY) === '1');
  }

  function beep(ctx, f, t, len, vol) {
    const osc = ctx.createOscillator();
    const lp = ctx.createBiquadFilter();
    const g = ctx.createGain();
    osc.type = 'square';
    osc.frequency.value = f;
    lp.type = 'lowpass';
    lp.frequency.value = 6000;
    g.gain.setValueAtTime(0, t);
    g.gain.linearRampToValueAtTime(vol, t + 0.008);
    g.gain.setValueAtTime(vol, t + len - 0.02);
    g.gain.linearRampToValueAtTime(0, t + len);
    osc.connect(lp).connect(g).connect(ctx.destination);
    osc.start(t);
    osc.stop(t + len + 0.01);
    S.live.push(osc);
    osc.onended = () => { S.live = S.live.filter((o) => o !== osc); };
  }

  function play(pattern, t0, vol) {
    pattern.forEach((b) => beep(S.ctx, b.f, t0 + b.at, b.len, vol));
  }

  /** Schedule the next beep group when it falls inside the look-ahead window. */
  function pump() {
    const ctx = S.ctx;
    if (!S.wanted || !S.allowed || !ctx || ctx.state !== 'running') return;
    const now = ctx.currentTime;
    if (S.nextAt && now + LOOKAHEAD_S < S.nextAt) return;
    const t0 = Math.max(now + 0.02, S.nextAt || 0);
    play(PATTERNS[S.level] || PATTERNS.normal, t0, 0.5);
    S.tones += 1;
    S.nextAt = t0 + PERIOD_S;
  }

  function silence() {
    S.live.forEach((o) => { try { o.stop(); } catch (e) { /* already stopped */ } });
    S.live = [];
    S.nextAt = 0;
  }

  /**
   * Desired tone from the latest state: starts at once, repeats every PERIOD_S, stops when it
   * clears. An escalation (normal -> high) restarts the pattern unless one just started.
   */
  function update(wanted, level) {
    const w = !!wanted && S.allowed;
    const lv = level === 'high' ? 'high' : 'normal';
    if (!w) {
      if (S.wanted) silence();
      S.wanted = false;
      return;
    }
    const ctx = S.ctx;
    const escalates = S.wanted && lv === 'high' && S.level !== 'high';
    if (escalates && ctx && ctx.currentTime - (S.nextAt - PERIOD_S) > 0.6) silence();
    S.level = lv;
    S.wanted = true;
    pump();
  }

  function setAllowed(on) {
    S.allowed = !!on;
    if (!S.allowed) { silence(); S.wanted = false; }
    else ensureContext();
    S.onChange(state());
  }

  function init(opts) {
    S.onChange = (opts && opts.onChange) || S.onChange;
    S.allowed = !(opts && opts.allowed === false);
    ensureContext();
    if (remembered() && S.ctx && S.ctx.state !== 'running') S.ctx.resume().catch(() => {});
    // Any tap on the page counts as the gesture the browser wants.
    const resume = () => { if (S.allowed && state() !== 'running') unlock(false); };
    root.addEventListener('pointerdown', resume, true);
    root.addEventListener('keydown', resume, true);
    root.document.addEventListener('visibilitychange', () => {
      if (!root.document.hidden && S.ctx && S.ctx.state === 'suspended' && remembered()) S.ctx.resume().catch(() => {});
    });
    S.timer = root.setInterval(pump, 100);
    S.onChange(state());
  }

  root.HmiSound = {
    init, unlock, update, setAllowed, state,
    tonesScheduled: () => S.tones,
    allowed: () => S.allowed,
    wanted: () => S.wanted,
  };
})(window);
