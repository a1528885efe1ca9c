#!/usr/bin/env python3
"""DEVELOPMENT STAND-IN for the OBU daemon's HMI server. Not the product, not used by CI.

It serves the hmi-web files and the HTTP contract of the real daemon (GET /events as
Server-Sent Events, GET/PUT /api/settings persisted to a file, pairing with POST/GET
/api/pair, GET /api/status, GET /healthz) with made-up states, so the page can be developed and its browser tests run before the daemon
exists. Python 3 standard library only.

  python3 dev_server.py serve [--port N] [--host H] [--state-dir D] [--mode script|manual] [--scene S]
      Prints its URL on the first line of stdout. --mode script (default) loops through
      cruise -> approach -> warning -> lane closed -> overspeed -> in zone -> leaving -> GNSS
      dropout -> no roadside data -> restart (stream closed, 503 for 3 s, seq from 0);
      --mode manual holds one scene until told otherwise.
      Defaults come from the environment: HMI_PORT, HMI_STATE_DIR, HMI_PIN (the pairing
      PIN; made at random and printed on stderr when unset). A settings write needs the
      session cookie POST /api/pair gives for the PIN (401 without; 5 wrong PINs: 429).

  python3 dev_server.py drive SCENE      (HMI_URL=http://host:port in the environment)
      Switches the running stand-in to SCENE and holds it (this is the stand-in's
      HMI_DRIVER_CMD). Scenes: see SCENES below; `gnss_lost`/`gnss_back` toggle a GNSS dropout
      on top of the current scene (Estimated for 5 s, then Lost), `time_fault`/`time_ok` mark the
      time unverified and back; `silent` keeps the stream open with heartbeats only.
"""

import argparse
import hmac
import json
import mimetypes
import os
import secrets
import signal
import sys
import tempfile
import threading
import time
import urllib.request
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

WEB_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..'))
KMH = 1 / 3.6
LANE_LIMIT = 80 * KMH       # the road's limit
ZONE_LIMIT = 40 * KMH       # the work zone's reduced limit
ROAD = [1, 2, 3]            # lane ids left to right; lane 3 (right) is closed in the zone
CLOSED = [3]

DEFAULT_SETTINGS = {'warning_distance_m': 100, 'lead_time_s': 9, 'sound': True, 'units': 'kmh', 'theme': 'auto'}


def alert(kind, distance=None, limit=None, stage='None'):
    return {'kind': kind, 'distance_m': distance, 'limit_mps': limit, 'stage': stage}


def base(t_ms):
    return {
        'time_ms': t_ms, 'speed_mps': 22.0, 'speed_limit_mps': LANE_LIMIT, 'reduced_limit': False,
        'limit_ahead_mps': None, 'limit_ahead_m': None, 'decel_needed_mps2': None, 'speed_alarm': False,
        'stage': 'None', 'position': 'Live', 'time_status': 'Trusted',
        'zone_state': 'None', 'distance_m': None, 'primary': None, 'others': [],
        'lane': {'map': 1, 'lane': 2}, 'lane_confidence': 92, 'closed_lanes': [], 'advice': 'None',
        'road_lanes': list(ROAD), 'gnss_ok': True, 'roadside_data': True, 'maps': 1, 'zones': 1, 'unverified': 0,
        'counters': {'fixes': t_ms // 100, 'off_map': 0, 'lane_switches': 1, 'maps_updated': 1,
                     'maps_rejected': 0, 'zones_updated': 1, 'zones_rejected': 0,
                     'zones_cancelled': 0, 'expired': 0},
    }


def ramp(t, start, rate, floor):
    """A countdown from `start` at `rate` per second, held at `floor`."""
    return max(floor, start - rate * t)


def scene_cruise(s, t):
    s['speed_mps'] = 22.0 + 0.3 * ((t * 10) % 3)


def scene_speeding(s, t):
    """97 km/h on the 80 km/h road: the speed alarm, no alert."""
    s.update(speed_mps=27.0, speed_alarm=True)


def zone_ahead(s, d, stage):
    """A zone ahead at d metres: the 40 km/h limit starts there (the road's limit is in force)."""
    s.update(zone_state='Warning' if stage in ('Warning', 'Urgent') else 'Approaching', distance_m=d,
             closed_lanes=list(CLOSED), stage=stage, limit_ahead_mps=ZONE_LIMIT, limit_ahead_m=d)


def scene_approach(s, t):
    d = ramp(t, 560, 22, 210)
    zone_ahead(s, d, 'Information')
    s['primary'] = alert('ReducedSpeedAhead', d, ZONE_LIMIT, 'Information')
    s['others'] = [alert('LaneClosedOther', d, ZONE_LIMIT, 'Information')]


def scene_warning(s, t):
    """A complying driver at the warning distance: below the zone limit, in an open lane."""
    d = ramp(t, 95, 8, 60)
    zone_ahead(s, d, 'Warning')
    s.update(speed_mps=10.5)
    s['primary'] = alert('ReducedSpeedAhead', d, ZONE_LIMIT, 'Warning')
    s['others'] = [alert('LaneClosedOther', d, ZONE_LIMIT, 'Information')]


def scene_lane_closed(s, t):
    d = ramp(t, 90, 11, 55)
    zone_ahead(s, d, 'Warning')
    s.update(speed_mps=10.5, lane={'map': 1, 'lane': 3}, advice='MoveLeft')
    s['primary'] = alert('LaneClosedOwn', d, ZONE_LIMIT, 'Warning')
    s['others'] = [alert('ReducedSpeedAhead', d, ZONE_LIMIT, 'Warning')]


def scene_urgent(s, t):
    """Still in the closed lane 10-40 m before the zone: a lane change no longer fits."""
    d = 40 - (10.5 * t) % 30
    zone_ahead(s, d, 'Urgent')
    s.update(speed_mps=10.5, lane={'map': 1, 'lane': 3}, advice='MoveLeft', lane_confidence=88)
    s['primary'] = alert('LaneClosedOwn', d, ZONE_LIMIT, 'Urgent')
    s['others'] = [alert('ReducedSpeedAhead', d, ZONE_LIMIT, 'Warning'), alert('LaneClosedOther', d, ZONE_LIMIT, 'Information')]


def scene_lane_closed_fallback(s, t):
    """Same as lane_closed but without road_lanes: the page must draw from closed_lanes + lane."""
    scene_lane_closed(s, t)
    s['road_lanes'] = []


def scene_overspeed(s, t):
    d = ramp(t, 70, 16, 20)
    zone_ahead(s, d, 'Urgent')
    s.update(speed_mps=16.5, speed_alarm=True, decel_needed_mps2=round((16.5 ** 2 - ZONE_LIMIT ** 2) / (2 * d), 2))
    s['primary'] = alert('Overspeed', d, ZONE_LIMIT, 'Urgent')
    s['others'] = [alert('ReducedSpeedAhead', d, ZONE_LIMIT, 'Warning'), alert('LaneClosedOther', d, ZONE_LIMIT, 'Information')]


def scene_in_zone(s, t):
    d = -min(95, 10 + 10.5 * t)
    s.update(zone_state='InZone', distance_m=d, speed_mps=10.5, speed_limit_mps=ZONE_LIMIT,
             reduced_limit=True, closed_lanes=list(CLOSED), stage='Information')
    s['primary'] = alert('LaneClosedOther', d, ZONE_LIMIT, 'Information')


def scene_leaving(s, t):
    d = -min(150, 110 + 14 * t)
    s.update(zone_state='Leaving', distance_m=d, speed_mps=min(22, 13 + 2 * t), closed_lanes=list(CLOSED))


def scene_no_roadside(s, t):
    s.update(roadside_data=False, maps=0, zones=0, speed_limit_mps=None, road_lanes=[], lane=None,
             lane_confidence=0)
    s['primary'] = alert('NoRoadsideData')


SCENES = {
    'cruise': scene_cruise,
    'speeding': scene_speeding,
    'approach': scene_approach,
    'warning': scene_warning,
    'lane_closed': scene_lane_closed,
    'lane_closed_fallback': scene_lane_closed_fallback,
    'overspeed': scene_overspeed,
    'urgent': scene_urgent,
    'in_zone': scene_in_zone,
    'leaving': scene_leaving,
    'no_roadside': scene_no_roadside,
}
# pseudo-scenes handled by World.set_scene: gnss_lost, gnss_back, time_fault, time_ok, silent
SCRIPT = [('cruise', 5), ('approach', 6), ('warning', 5), ('lane_closed', 5), ('overspeed', 4),
          ('in_zone', 6), ('leaving', 4), ('gnss_lost', 4), ('cruise', 3), ('no_roadside', 3),
          ('restart', 3)]


DEAD_RECKONING_S = 5.0


def apply_gnss_loss(s, lost_for):
    """What the daemon does without fixes: for DEAD_RECKONING_S the position is estimated
    (zone, countdown and lane still given), then it is lost: the zone ahead is kept, the
    distance and the lane are not, the speed's source is stale."""
    s['gnss_ok'] = False
    if lost_for < DEAD_RECKONING_S:
        s['position'] = 'Estimated'
        s['lane_confidence'] = min(s['lane_confidence'], 60)
        s['others'] = s['others'] + [alert('GnssStale')]
        return 1000 + int(lost_for * 1000)
    s.update(position='Lost', lane=None, lane_confidence=0, distance_m=None, advice='None', speed_mps=None,
             speed_alarm=False, decel_needed_mps2=None, limit_ahead_m=None)
    if s['zone_state'] in ('Leaving',):
        s['zone_state'] = 'None'
    keep = [a for a in [s['primary']] + s['others'] if a and a['kind'] in ('MapMissing', 'NoRoadsideData')]
    s['primary'] = alert('GnssStale')
    if s['stage'] in ('Warning', 'Urgent'):
        s['stage'] = 'Information'
    s['primary']['stage'] = s['stage']
    s['others'] = keep
    return 1000 + int(lost_for * 1000)


class World:
    """Produces one state every 100 ms; SSE handlers wait on `cond` for the next one."""

    def __init__(self, mode, scene):
        self.cond = threading.Condition()
        self.mode = mode
        self.scene = scene
        self.scene_at = time.monotonic()
        self.gnss_lost_at = None
        self.time_fault = False
        self.silent = False
        self.seq = 0
        self.started = time.monotonic()
        self.down_until = 0.0
        self.generation = 0      # bumped on a simulated restart: open streams close
        self.latest = None
        self.counts = {'map': 0, 'tim': 0, 'nmea_gga': 0, 'nmea_rmc': 0}

    def set_scene(self, name):
        with self.cond:
            if name == 'gnss_lost':
                self.gnss_lost_at = self.gnss_lost_at or time.monotonic()
            elif name == 'gnss_back':
                self.gnss_lost_at = None
            elif name == 'time_fault':
                self.time_fault = True
            elif name == 'time_ok':
                self.time_fault = False
            elif name == 'silent':
                self.silent = True
            elif name == 'restart':
                self.restart(3.0)
            elif name in SCENES:
                self.silent = False
                self.scene, self.scene_at = name, time.monotonic()
            else:
                raise KeyError(name)

    def restart(self, down_s):
        self.generation += 1
        self.down_until = time.monotonic() + down_s
        self.seq = 0
        self.started = self.down_until
        self.cond.notify_all()

    def script_step(self, now):
        total = sum(d for _, d in SCRIPT)
        t = (now - self.script_t0) % total
        for name, dur in SCRIPT:
            if t < dur:
                break
            t -= dur
        if name == 'restart':
            if now >= self.down_until and self.last_script != 'restart':
                self.restart(dur)
        elif name == 'gnss_lost':
            if self.gnss_lost_at is None:
                self.gnss_lost_at = now
        else:
            self.gnss_lost_at = None
            if name != self.scene:
                self.scene, self.scene_at = name, now
        self.last_script = name

    def tick(self):
        now = time.monotonic()
        if self.mode == 'script':
            self.script_step(now)
        if now < self.down_until or self.silent:
            return
        t_ms = int((now - self.started) * 1000)
        s = base(t_ms)
        SCENES[self.scene](s, now - self.scene_at)
        age = 80
        if self.gnss_lost_at is not None:
            age = apply_gnss_loss(s, now - self.gnss_lost_at)
        if self.time_fault:
            s['time_status'] = 'Unverified' 
        self.seq += 1
        self.counts['nmea_gga'] += 0 if self.gnss_lost_at else 1
        self.counts['nmea_rmc'] += 0 if self.gnss_lost_at else 1
        self.counts['map'] += 1 if s['roadside_data'] else 0
        self.counts['tim'] += 1 if s['roadside_data'] else 0
        self.latest = {'seq': self.seq, 'state': s, 'gnss_age_ms': age,
                       'fix_quality': 0 if self.gnss_lost_at else 4}
        self.cond.notify_all()

    def run(self):
        self.script_t0 = time.monotonic()
        self.last_script = None
        while True:
            with self.cond:
                self.tick()
            time.sleep(0.1)

    def status(self):
        latest = self.latest or {}
        s = latest.get('state') or {}
        return {
            'uptime_s': round(time.monotonic() - self.started, 1),
            'stand_in': 'hmi-web/tests/dev_server.py (development only)',
            'scene': self.scene,
            'counters': dict(self.counts),
            'decode_errors': {'bad_envelope': 0, 'uper': 1, 'capacity': 0, 'unknown_psid': 2},
            'gnss': {'age_ms': latest.get('gnss_age_ms'), 'fix_quality': latest.get('fix_quality')},
            'maps': s.get('maps'), 'zones': s.get('zones'),
        }


class Settings:
    def __init__(self, path):
        self.path = path
        self.lock = threading.Lock()

    def get(self):
        with self.lock:
            try:
                with open(self.path) as f:
                    return json.load(f)
            except (OSError, ValueError):
                return dict(DEFAULT_SETTINGS)

    def put(self, body):
        err = validate(body)
        if err:
            return None, err
        with self.lock:
            tmp = self.path + '.tmp'
            with open(tmp, 'w') as f:
                json.dump(body, f)
            os.replace(tmp, self.path)
        return body, None


class Pairing:
    """The daemon's pairing, simplified: sessions persisted in the state dir, 5 wrong PINs in a
    row lock pairing for 30 s."""

    def __init__(self, pin, path):
        self.pin = pin
        self.path = path
        self.lock = threading.Lock()
        self.wrong = 0
        self.locked_until = 0.0
        try:
            with open(path) as f:
                self.sessions = [t for t in json.load(f) if isinstance(t, str)]
        except (OSError, ValueError, TypeError):
            self.sessions = []

    def attempt(self, pin):
        """(status, body, token or None)."""
        with self.lock:
            now = time.monotonic()
            if now < self.locked_until:
                return 429, {'error': 'too many wrong PINs: pairing is locked',
                             'retry_after_s': int(self.locked_until - now) + 1}, None
            if not isinstance(pin, str) or not hmac.compare_digest(pin.encode(), self.pin.encode()):
                self.wrong += 1
                if self.wrong >= 5:
                    self.locked_until = now + 30
                    return 429, {'error': 'too many wrong PINs: pairing is locked', 'retry_after_s': 30}, None
                return 403, {'error': 'wrong PIN', 'tries_left': 5 - self.wrong}, None
            self.wrong = 0
            token = secrets.token_hex(32)
            self.sessions = (self.sessions + [token])[-16:]
            with open(self.path, 'w') as f:
                json.dump(self.sessions, f)
            return 200, {'paired': True}, token

    def authorised(self, cookie_header):
        for part in (cookie_header or '').split(';'):
            name, _, value = part.strip().partition('=')
            if name == 'obu_session':
                with self.lock:
                    return any(hmac.compare_digest(value, t) for t in self.sessions)
        return False


def is_num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and v == v


def validate(b):
    if not isinstance(b, dict):
        return 'body: expected a JSON object'
    for k in b:
        if k not in DEFAULT_SETTINGS:
            return f'{k}: unknown field'
    for k in DEFAULT_SETTINGS:
        if k not in b:
            return f'{k}: missing'
    if not is_num(b['warning_distance_m']) or not 20 <= b['warning_distance_m'] <= 2000:
        return 'warning_distance_m: must be a number from 20 to 2000'
    if not is_num(b['lead_time_s']) or not 2 <= b['lead_time_s'] <= 30:
        return 'lead_time_s: must be a number from 2 to 30'
    if not isinstance(b['sound'], bool):
        return 'sound: must be true or false'
    if b['units'] not in ('kmh', 'mph'):
        return 'units: must be "kmh" or "mph"'
    if b['theme'] not in ('day', 'night', 'auto'):
        return 'theme: must be "day", "night" or "auto"'
    return None


class Handler(BaseHTTPRequestHandler):
    server_version = 'hmi-dev-stand-in/1'
    world = None
    settings = None
    pairing = None

    def log_message(self, fmt, *args):
        pass

    def send_json(self, code, obj):
        data = json.dumps(obj).encode()
        self.send_response(code)
        self.send_header('Content-Type', 'application/json')
        self.send_header('Content-Length', str(len(data)))
        self.send_header('Cache-Control', 'no-store')
        self.end_headers()
        self.wfile.write(data)

    def send_text(self, code, text, ctype='text/plain; charset=utf-8'):
        data = text.encode()
        self.send_response(code)
        self.send_header('Content-Type', ctype)
        self.send_header('Content-Length', str(len(data)))
        self.end_headers()
        self.wfile.write(data)

    def do_GET(self):
        path = self.path.split('?', 1)[0]
        if path == '/events':
            return self.events()
        if path == '/healthz':
            return self.send_text(200, 'ok')
        if path == '/api/settings':
            return self.send_json(200, self.settings.get())
        if path == '/api/status':
            return self.send_json(200, self.world.status())
        if path == '/api/pair':
            return self.send_json(200, {'paired': self.pairing.authorised(self.headers.get('Cookie')),
                                        'locked_for_s': 0})
        if path == '/__dev/scene':
            return self.send_json(200, {'scene': self.world.scene, 'scenes': sorted(SCENES) + ['gnss_lost', 'gnss_back', 'time_fault', 'time_ok', 'silent', 'restart']})
        return self.static(path)

    def do_PUT(self):
        if self.path != '/api/settings':
            return self.send_json(404, {'error': 'not found'})
        if not self.pairing.authorised(self.headers.get('Cookie')):
            self.rfile.read(int(self.headers.get('Content-Length') or 0))
            return self.send_json(401, {'error': "pairing required: send the unit's PIN to POST /api/pair"})
        try:
            body = json.loads(self.rfile.read(int(self.headers.get('Content-Length') or 0)) or b'null')
        except ValueError:
            return self.send_json(400, {'error': 'body: not JSON'})
        stored, err = self.settings.put(body)
        if err:
            return self.send_json(400, {'error': err})
        return self.send_json(200, stored)

    def do_POST(self):
        if self.path == '/api/pair':
            return self.pair()
        if self.path != '/__dev/scene':
            return self.send_json(404, {'error': 'not found'})
        try:
            body = json.loads(self.rfile.read(int(self.headers.get('Content-Length') or 0)))
            self.world.set_scene(body['scene'])
        except (ValueError, KeyError, TypeError) as e:
            return self.send_json(400, {'error': f'scene: {e}'})
        return self.send_json(200, {'scene': body['scene']})

    def pair(self):
        try:
            body = json.loads(self.rfile.read(int(self.headers.get('Content-Length') or 0)))
            pin = body['pin']
        except (ValueError, KeyError, TypeError):
            return self.send_json(400, {'error': 'expected {"pin": "..."}'})
        status, answer, token = self.pairing.attempt(pin)
        data = json.dumps(answer).encode()
        self.send_response(status)
        self.send_header('Content-Type', 'application/json')
        self.send_header('Content-Length', str(len(data)))
        if token:
            self.send_header('Set-Cookie', f'obu_session={token}; HttpOnly; SameSite=Strict; Path=/; Max-Age=31536000')
        self.end_headers()
        self.wfile.write(data)

    def static(self, path):
        if path == '/':
            path = '/index.html'
        rel = os.path.normpath(path.lstrip('/'))
        full = os.path.join(WEB_ROOT, rel)
        if rel.startswith('..') or rel.startswith('tests') or not os.path.isfile(full):
            return self.send_text(404, 'not found')
        with open(full, 'rb') as f:
            data = f.read()
        if rel == 'sw.js':
            data = data.replace(b'@HMI_SHELL_VERSION@', shell_version().encode())
        ctype = MIME.get(os.path.splitext(full)[1]) or mimetypes.guess_type(full)[0] or 'application/octet-stream'
        if ctype.startswith('text/') or ctype.endswith('javascript'):
            ctype += '; charset=utf-8'
        self.send_response(200)
        self.send_header('Content-Type', ctype)
        self.send_header('Content-Length', str(len(data)))
        self.send_header('Cache-Control', 'no-cache')
        self.end_headers()
        self.wfile.write(data)

    def events(self):
        w = self.world
        if time.monotonic() < w.down_until:
            return self.send_text(503, 'restarting')
        self.send_response(200)
        self.send_header('Content-Type', 'text/event-stream')
        self.send_header('Cache-Control', 'no-cache')
        self.send_header('X-Accel-Buffering', 'no')
        self.end_headers()
        gen = w.generation
        last_seq = None
        last_write = time.monotonic()
        try:
            self.wfile.write(b'retry: 1000\n\n')
            self.wfile.flush()
            while True:
                with w.cond:
                    w.cond.wait(timeout=0.25)
                    msg = w.latest
                    if w.generation != gen:
                        return
                now = time.monotonic()
                if msg and msg['seq'] != last_seq and not w.silent:
                    last_seq = msg['seq']
                    out = f"event: state\nid: {msg['seq']}\ndata: {json.dumps(msg)}\n\n"
                    self.wfile.write(out.encode())
                    self.wfile.flush()
                    last_write = now
                elif now - last_write >= 1.0:
                    self.wfile.write(b': hb\n\n')
                    self.wfile.flush()
                    last_write = now
        except (BrokenPipeError, ConnectionResetError, OSError):
            return


MIME = {'.webmanifest': 'application/manifest+json', '.js': 'text/javascript', '.svg': 'image/svg+xml'}


def shell_version():
    """A hash of the app files (as the daemon stamps it into sw.js): new files, new cache."""
    import hashlib
    h = hashlib.sha256()
    for name in sorted(os.listdir(WEB_ROOT)):
        full = os.path.join(WEB_ROOT, name)
        if os.path.isfile(full) and name not in ('sw.js', 'README.md', 'screenshot.png'):
            h.update(name.encode() + b'\0')
            with open(full, 'rb') as f:
                h.update(f.read())
    return h.hexdigest()[:16]


class Server(ThreadingHTTPServer):
    daemon_threads = True
    allow_reuse_address = True


def serve(args):
    state_dir = args.state_dir or os.environ.get('HMI_STATE_DIR') or tempfile.mkdtemp(prefix='hmi-dev-')
    os.makedirs(state_dir, exist_ok=True)
    port = args.port if args.port is not None else int(os.environ.get('HMI_PORT') or 0)
    world = World(args.mode, args.scene)
    Handler.world = world
    Handler.settings = Settings(os.path.join(state_dir, 'settings.json'))
    pin = os.environ.get('HMI_PIN') or f'{secrets.randbelow(1000000):06d}'
    Handler.pairing = Pairing(pin, os.path.join(state_dir, 'sessions.json'))
    httpd = Server((args.host, port), Handler)
    threading.Thread(target=world.run, daemon=True).start()
    signal.signal(signal.SIGTERM, lambda *_: os._exit(0))
    print(f'http://{args.host}:{httpd.server_address[1]}', flush=True)
    print(f'dev stand-in: mode={args.mode} state_dir={state_dir} web_root={WEB_ROOT} pairing PIN {pin}', file=sys.stderr, flush=True)
    try:
        httpd.serve_forever(poll_interval=0.2)
    except KeyboardInterrupt:
        pass


def drive(args):
    url = os.environ.get('HMI_URL')
    if not url:
        sys.exit('drive: set HMI_URL')
    req = urllib.request.Request(url.rstrip('/') + '/__dev/scene', data=json.dumps({'scene': args.scene}).encode(),
                                 headers={'Content-Type': 'application/json'}, method='POST')
    with urllib.request.urlopen(req, timeout=5) as r:
        r.read()


def main():
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    sub = p.add_subparsers(dest='cmd', required=True)
    s = sub.add_parser('serve')
    s.add_argument('--host', default='127.0.0.1')
    s.add_argument('--port', type=int, default=None)
    s.add_argument('--state-dir', default=None)
    s.add_argument('--mode', choices=['script', 'manual'], default='script')
    s.add_argument('--scene', choices=sorted(SCENES), default='cruise')
    d = sub.add_parser('drive')
    d.add_argument('scene')
    args = p.parse_args()
    serve(args) if args.cmd == 'serve' else drive(args)


if __name__ == '__main__':
    main()
