/* The live state stream (Server-Sent Events) and the connection watchdog. */
const STALE_MS = 1500;      // no `state` event for longer: the display is not live
const FORCE_MS = 6000;      // open but silent for longer (half-open Wi-Fi link): reconnect ourselves
const RETRY_CLOSED_MS = 1500; // EventSource gave up (non-200 answer): try again after this

const S = {
  url: '/events',
  es: null,
  open: false,
  conn: 'disconnected',
  lastAt: 0,
  openedAt: 0,
  last: null,
  seq: null,
  received: 0,
  parseErrors: 0,
  errors: 0,
  connects: 0,
  rate: 0,
  rateCount: 0,
  rateAt: 0,
  retryTimer: null,
  onState: () => {},
  onConn: () => {},
};

function now() {
  return performance.now();
}

function connect() {
  if (S.es) { S.es.close(); S.es = null; }
  S.open = false;
  S.openedAt = now();
  clearTimeout(S.retryTimer);
  S.retryTimer = null;
  const es = new EventSource(S.url);
  S.es = es;
  es.onopen = () => {
    if (es !== S.es) return;
    S.open = true;
    S.openedAt = now();
    S.connects += 1;
    evaluate();
  };
  es.onerror = () => {
    if (es !== S.es) return;
    S.open = false;
    S.errors += 1;
    if (es.readyState === EventSource.CLOSED) scheduleRetry();
    evaluate();
  };
  es.addEventListener('state', (e) => onMessage(es, e));
}

function scheduleRetry() {
  if (S.retryTimer) return;
  S.retryTimer = setTimeout(connect, RETRY_CLOSED_MS);
}

function onMessage(es, e) {
  if (es !== S.es) return;
  let msg;
  try {
    msg = JSON.parse(e.data);
  } catch (err) {
    S.parseErrors += 1;
    return;
  }
  if (!msg || typeof msg !== 'object' || !msg.state || typeof msg.state !== 'object') {
    S.parseErrors += 1;
    return;
  }
  S.open = true;
  S.lastAt = now();
  S.last = msg;
  S.seq = msg.seq;
  S.received += 1;
  S.rateCount += 1;
  evaluate();
  S.onState(msg);
}

function evaluate() {
  const t = now();
  let conn;
  if (!S.open) conn = 'disconnected';
  else if (S.lastAt && t - S.lastAt <= STALE_MS) conn = 'live';
  else conn = 'stale';
  if (S.open && t - Math.max(S.lastAt, S.openedAt) > FORCE_MS) {
    connect();
    conn = 'disconnected';
  }
  if (t - S.rateAt >= 1000) {
    S.rate = S.rateAt ? (S.rateCount * 1000) / (t - S.rateAt) : 0;
    S.rateAt = t;
    S.rateCount = 0;
  }
  if (conn !== S.conn) {
    S.conn = conn;
    S.onConn(conn);
  }
}

function start(opts) {
  S.url = opts.url || S.url;
  S.onState = opts.onState || S.onState;
  S.onConn = opts.onConn || S.onConn;
  connect();
  setInterval(evaluate, 200);
}

export const stream = {
  start,
  connection: () => S.conn,
  last: () => S.last,
  stats: () => ({
    connection: S.conn,
    event_source: S.es ? ['connecting', 'open', 'closed'][S.es.readyState] : 'none',
    last_seq: S.seq,
    since_last_ms: S.lastAt ? Math.round(now() - S.lastAt) : null,
    states_received: S.received,
    states_per_s: Math.round(S.rate * 10) / 10,
    connects: S.connects,
    stream_errors: S.errors,
    parse_errors: S.parseErrors,
  }),
  STALE_MS,
};
