/* Pairing: the unit takes settings only from a tablet that has sent it the unit's PIN once
 * (POST /api/pair). Its answer sets an HttpOnly session cookie the page never sees; the
 * browser sends it with every later request. pair.ask() shows the dialog and resolves
 * true once paired, false when the driver cancels. */
const doc = document;
const $ = (id) => doc.getElementById(id);
const PIN = /^[A-Za-z0-9]{4,32}$/;

let pending = null;   // { promise, resolve } while the dialog is open
let busy = false;

function message(text, kind) {
  const m = $('pair-msg');
  m.textContent = text;
  m.dataset.kind = kind || 'error';
}

function finish(paired) {
  const dlg = $('pair-dialog');
  if (dlg.open) dlg.close();
  const p = pending;
  pending = null;
  if (p) p.resolve(paired);
}

/** Shows the dialog (once, however often it is asked for while open). */
function ask() {
  if (pending) return pending.promise;
  let resolve;
  const promise = new Promise((r) => { resolve = r; });
  pending = { promise, resolve };
  $('pair-pin').value = '';
  message('', '');
  const dlg = $('pair-dialog');
  if (typeof dlg.showModal === 'function') dlg.showModal();
  else dlg.setAttribute('open', '');
  $('pair-pin').focus();
  return promise;
}

function tries(n) {
  return n === 1 ? '1 try' : n + ' tries';
}

function submit(ev) {
  ev.preventDefault();
  if (busy) return;
  const pin = $('pair-pin').value.trim();
  if (!PIN.test(pin)) {
    message('Enter the PIN: 4 to 32 letters or digits.');
    return;
  }
  busy = true;
  $('pair-submit').disabled = true;
  message('Pairing…', 'busy');
  fetch('/api/pair', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ pin }),
  })
    .then((resp) => resp.text().then((t) => ({ resp, body: parse(t) })))
    .then(({ resp, body }) => {
      if (resp.ok) { finish(true); return; }
      $('pair-pin').select();
      if (resp.status === 403) {
        const left = body && Number.isFinite(body.tries_left) ? ' (' + tries(body.tries_left) + ' left before pairing locks)' : '';
        message('Wrong PIN' + left + '.');
      } else if (resp.status === 429) {
        const s = body && Number.isFinite(body.retry_after_s) ? body.retry_after_s : null;
        message('Too many wrong PINs: pairing is locked' + (s !== null ? ' for ' + s + ' s' : '') + '.');
      } else {
        message('Not paired: the unit said “' + ((body && body.error) || 'HTTP ' + resp.status) + '”.');
      }
    })
    .catch(() => message('The unit is not reachable.'))
    .finally(() => { busy = false; $('pair-submit').disabled = false; });
}

function parse(t) {
  try { return JSON.parse(t); } catch (e) { return null; }
}

function init() {
  $('pair-form').addEventListener('submit', submit);
  $('pair-cancel').addEventListener('click', () => finish(false));
  // Escape closes a modal dialog by itself: report it as a cancel.
  $('pair-dialog').addEventListener('close', () => finish(false));
}

export const pair = { ask, isOpen: () => !!pending };
init();
