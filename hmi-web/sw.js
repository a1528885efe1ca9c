/* Service worker of the driver display: it keeps the app shell (every app file) so that a
 * reload while the vehicle unit is unreachable opens this app and its own "Disconnected"
 * screen, not the browser's error page; the app then reconnects by itself.
 *
 * - Shell files: network first (a reachable unit always gives its current files), the
 *   cache when the network fails or takes longer than NETWORK_MS.
 * - /events, /api/*, /healthz and anything not GET never touch the cache.
 * - The daemon stamps VERSION with a hash of the app files it embeds: a daemon with other
 *   files serves another sw.js, the browser installs it, and the old cache is deleted.
 */
'use strict';

const VERSION = '@HMI_SHELL_VERSION@';
const PREFIX = 'hmi-shell-';
const CACHE = PREFIX + VERSION;
const NETWORK_MS = 2500;
const SHELL = ['/index.html', '/style.css', '/contract.json', '/format.js', '/lanes.js', '/sound.js', '/stream.js',
  '/pair.js', '/views.js', '/app.js', '/manifest.webmanifest', '/icon.svg', '/icon-maskable.svg'];

self.addEventListener('install', (event) => {
  event.waitUntil(caches.open(CACHE)
    .then((cache) => cache.addAll(SHELL.map((path) => new Request(path, { cache: 'no-store' }))))
    .then(() => self.skipWaiting()));
});

self.addEventListener('activate', (event) => {
  event.waitUntil(caches.keys()
    .then((keys) => Promise.all(keys.filter((k) => k.startsWith(PREFIX) && k !== CACHE).map((k) => caches.delete(k))))
    .then(() => self.clients.claim()));
});

/** Requests that are live data: never answered from the cache. */
function live(url) {
  const p = url.pathname;
  return p === '/events' || p.startsWith('/api/') || p === '/healthz' || p === '/sw.js';
}

self.addEventListener('fetch', (event) => {
  const req = event.request;
  if (req.method !== 'GET') return;
  const url = new URL(req.url);
  if (url.origin !== self.location.origin || live(url)) return;
  event.respondWith(shell(req, url));
});

function cacheKey(url) {
  return url.pathname === '/' ? '/index.html' : url.pathname;
}

function timeout(ms) {
  return new Promise((resolve, reject) => setTimeout(() => reject(new Error('network timeout')), ms));
}

async function shell(req, url) {
  const key = cacheKey(url);
  const cache = await caches.open(CACHE);
  try {
    const resp = await Promise.race([fetch(req), timeout(NETWORK_MS)]);
    if (resp.ok && SHELL.indexOf(key) >= 0) await cache.put(key, resp.clone());
    return resp;
  } catch (err) {
    const hit = (await cache.match(key, { ignoreSearch: true })) ||
      (req.mode === 'navigate' ? await cache.match('/index.html') : undefined);
    if (hit) return hit;
    throw err;
  }
}
