/*
 * Audible warning: WebAudio beeps in the 1-5 kHz band, following the alert stage.
 *   Warning: ONE beep group when the stage is entered from a lower stage.
 *   Urgent: a beep group at once, then every 2 s while the stage stays Urgent.
 * The tone stops at once when the stage drops (the driver complied) or the link is lost.
 *
 * createSound(root) makes the player over `root`'s WebAudio, storage, events and timers: the
 * page passes `window`, the node unit tests a fake one.
 */
const PERIOD_S = 2.0;
const LOOKAHEAD_S = 0.25;
const KEY = 'hmi.sound.unlocked';
const RANK = { none: 0, warning: 1, urgent: 2 };
// warning: two 2 kHz beeps; urgent: three alternating 2.0/2.6 kHz beeps
const PATTERNS = {
  warning: [{ f: 2000, at: 0, len: 0.16 }, { f: 2000, at: 0.26, len: 0.16 }],
  urgent: [{ f: 2000, at: 0, len: 0.12 }, { f: 2600, at: 0.18, len: 0.12 }, { f: 2000, at: 0.36, len: 0.12 }],
  confirm: [{ f: 1500, at: 0, len: 0.08 }, { f: 2000, at: 0.11, len: 0.1 }],
};

/** A tone player over `root` (a window: AudioContext, localStorage, events, setInterval). */
export function createSound(root) {
  function storage() {
    try { return root.localStorage; } catch (e) { return null; }
  }

  const S = {
    ctx: null,
    allowed: true,
    tone: 'none',      // what the last live state asked for
    live: false,
    nextAt: 0,         // when the next urgent group is due (AudioContext time), 0: none
    tones: 0,          // beep groups scheduled (for the tests)
    playing: [],
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
    S.playing.push(osc);
    osc.onended = () => { S.playing = S.playing.filter((o) => o !== osc); };
  }

  function play(pattern, t0, vol) {
    pattern.forEach((b) => beep(S.ctx, b.f, t0 + b.at, b.len, vol));
  }

  function running() {
    return S.allowed && S.ctx && S.ctx.state === 'running';
  }

  /** One beep group now (counted); false when the audio is not running. */
  function group(pattern) {
    if (!running()) return false;
    const t0 = S.ctx.currentTime + 0.02;
    play(PATTERNS[pattern], t0, 0.5);
    S.tones += 1;
    return t0;
  }

  /** Schedules the next urgent group when it falls inside the look-ahead window. */
  function pump() {
    if (!S.live || S.tone !== 'urgent' || !running()) return;
    const now = S.ctx.currentTime;
    if (S.nextAt && now + LOOKAHEAD_S < S.nextAt) return;
    const t0 = Math.max(now + 0.02, S.nextAt || 0);
    play(PATTERNS.urgent, t0, 0.5);
    S.tones += 1;
    S.nextAt = t0 + PERIOD_S;
  }

  function silence() {
    S.playing.forEach((o) => { try { o.stop(); } catch (e) { /* already stopped */ } });
    S.playing = [];
    S.nextAt = 0;
  }

  /**
   * The tone the latest state asks for ('none' | 'warning' | 'urgent') and whether the link
   * is live. Without the link everything stops, and the last stage is kept, so a reconnect
   * in the same Warning does not beep again.
   */
  function update(tone, live) {
    const want = RANK[tone] !== undefined ? tone : 'none';
    if (!live) {
      if (S.live) silence();
      S.live = false;
      return;
    }
    S.live = true;
    const prev = S.tone;
    S.tone = want;
    if (!S.allowed) return;
    if (RANK[want] < RANK[prev]) silence();            // the stage dropped: stop at once
    if (want === 'warning' && prev === 'none') group('warning');
    if (want === 'urgent' && prev !== 'urgent') silence();    // urgent starts over at once
    pump();
  }

  function setAllowed(on) {
    S.allowed = !!on;
    if (!S.allowed) silence();
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

  return {
    init, unlock, update, setAllowed, state,
    tonesScheduled: () => S.tones,
    allowed: () => S.allowed,
    tone: () => S.tone,
    PERIOD_S,
  };
}
