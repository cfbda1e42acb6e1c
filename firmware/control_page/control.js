// SPDX-License-Identifier: MIT
// vpe's control page: MQTT v5 over WebSockets (mqtt.js, fetched by the build) to the show's
// broker. Reads every node's status (vpe/<show>/status/<node>), the show's light and blackout,
// and the install steps' progress and images (vpe/<show>/install/<node>/...); publishes the
// light, presets and drift as the controller role does (proto/BUS.md), the blackout switch, and
// the install commands (vpe/<show>/command/<node>: a scan or a radiometric capture). What a login may do is the broker's ACL's to decide: a refused publish is
// shown, and the controls are then disabled.
'use strict';

const STALE_MS = 3000;       // a status older than this: the node's card turns red
const PUBLISH_MS = 50;       // at most 20 light states a second while dragging
const PAGE_QUIET_US = 10e6;  // with drift on, the drift takes over 10 s after the last move
const $ = (id) => document.getElementById(id);

const state = {
  client: null, user: '', show: '', nodes: new Map(), light: null, blackout: false,
  clockOffsetMs: 0, seq: 0, lastTimeUs: 0, drift: false, lastSent: 0, timer: 0,
  target: null, confirmed: null,
};

// The nodes' clock (chrony keeps them together) as seen from here: a phone's clock may be off.
function showNowUs() {
  const us = Math.round((Date.now() + state.clockOffsetMs) * 1000);
  state.lastTimeUs = Math.max(us, state.lastTimeUs + 1);
  return state.lastTimeUs;
}

function clientId() {
  return 'vpe-page-' + Math.random().toString(16).slice(2, 10);
}

// ---- Log in ----------------------------------------------------------------------------------

$('broker').value = (location.protocol === 'https:' ? 'wss://' : 'ws://') +
    (location.host || '127.0.0.1:8080');

$('login').addEventListener('submit', (event) => {
  event.preventDefault();
  connect($('broker').value.trim(), $('user').value.trim(), $('password').value);
});
$('logout').addEventListener('click', () => location.reload());

function refusalText(error, user) {
  const code = error && error.code;
  if (code === 134 || code === 135 || code === 4 || code === 5 ||
      /not authori[sz]ed|bad user/i.test(String(error && error.message))) {
    return 'Wrong user name or password for "' + user + '": the broker refused the login.';
  }
  return 'Cannot reach the broker at ' + $('broker').value + ' (' +
      ((error && error.message) || 'no answer') + ').';
}

function connect(url, user, password) {
  $('login-error').textContent = 'Connecting…';
  const id = clientId();
  const client = mqtt.connect(url, {
    clientId: id, username: user, password, protocolVersion: 5, clean: true,
    reconnectPeriod: 0, connectTimeout: 5000, keepalive: 10,
  });
  let accepted = false;
  client.on('connect', () => {
    if (!accepted) {
      accepted = true;
      client.options.reconnectPeriod = 1000;  // after a first success, ride out outages
      started(client, user, id);
    }
    setConnection('connected as ' + user);
  });
  client.on('error', (error) => {
    if (!accepted) {
      $('login-error').textContent = refusalText(error, user);
      client.end(true);
    } else {
      setConnection('broker: ' + error.message);
    }
  });
  client.on('close', () => {
    if (!accepted && $('login-error').textContent === 'Connecting…') {
      $('login-error').textContent = refusalText(null, user);
    }
    if (accepted) setConnection('reconnecting…');
  });
  client.on('message', received);
}

function setConnection(text) {
  $('connection').textContent = text;
}

function started(client, user, id) {
  state.client = client;
  state.user = user;
  state.id = id;
  $('login').hidden = true;
  $('app').hidden = false;
  $('logout').hidden = false;
  if (user === 'vpe-viewer') document.body.classList.add('viewer');  // it may only watch
  client.subscribe(['vpe/+/status/+', 'vpe/+/light', 'vpe/+/blackout', 'vpe/+/install/+/+'],
                   { qos: 0 });
  setInterval(renderCards, 250);
}

// ---- What arrives ----------------------------------------------------------------------------

function parse(payload) {
  try {
    const value = JSON.parse(new TextDecoder().decode(payload));
    return value && typeof value === 'object' && value.format === 1 ? value : null;
  } catch (error) {
    return null;
  }
}

function received(topic, payload, packet) {
  const parts = topic.split('/');
  if (parts.length === 5 && parts[0] === 'vpe' && parts[2] === 'install' &&
      (!state.show || parts[1] === state.show)) {
    installReceived(parts[3], parts[4], payload);
    return;
  }
  const message = parse(payload);
  if (parts.length < 3 || parts[0] !== 'vpe' || !message) return;
  if (!state.show) {
    state.show = parts[1];
    $('show-name').textContent = 'show "' + state.show + '"';
  }
  if (parts[1] !== state.show) return;
  if (parts[2] === 'status' && parts.length === 4 && typeof message.time_us === 'number') {
    const nowMs = Date.now();
    if (!packet.retain) {
      // Live: it was made about now on the node's clock. Follow the nodes' clock slowly.
      const offset = message.time_us / 1000 - nowMs;
      state.clockOffsetMs = state.nodes.size === 0 && state.clockOffsetMs === 0
          ? offset : state.clockOffsetMs * 0.9 + offset * 0.1;
    }
    // Seen: when it was made, on the nodes' clock (a retained status of a dead node is old).
    const seenMs = message.time_us / 1000 - state.clockOffsetMs;
    state.nodes.set(parts[3], { status: message, seenMs: Math.min(seenMs, nowMs) });
    if (!state.target) state.target = { ...message.light };
    renderControls();
  } else if (parts[2] === 'light' && typeof message.azimuth === 'number') {
    if (!state.light || message.time_us >= state.light.time_us) {
      state.light = state.confirmed = message;
      state.target = { azimuth: message.azimuth, elevation: message.elevation,
                       distance: message.distance };
      state.drift = message.drift_us !== null && message.drift_us !== undefined;
      renderControls();
    }
  } else if (parts[2] === 'blackout' && typeof message.on === 'boolean') {
    state.blackout = message.on;
    renderControls();
  }
}

// ---- Node cards ------------------------------------------------------------------------------

function ago(ms) {
  const s = Math.max(0, ms / 1000);
  return s < 60 ? s.toFixed(0) + ' s' : s < 3600 ? (s / 60).toFixed(0) + ' min'
      : (s / 3600).toFixed(1) + ' h';
}

function field(dl, name, value) {
  const dt = document.createElement('dt');
  const dd = document.createElement('dd');
  dt.textContent = name;
  dd.textContent = value;
  dl.append(dt, dd);
}

function renderCards() {
  const cards = $('cards');
  const now = Date.now();
  const names = [...state.nodes.keys()].sort();
  $('node-count').textContent = '(' + names.length + ')';
  for (const name of names) {
    const { status: s, seenMs } = state.nodes.get(name);
    let card = cards.querySelector('[data-node="' + CSS.escape(name) + '"]');
    if (!card) {
      card = document.createElement('article');
      card.className = 'card';
      card.dataset.node = name;
      cards.append(card);
    }
    const age = now - seenMs;
    const stale = age > STALE_MS;
    card.classList.toggle('stale', stale);
    card.dataset.stale = stale ? 'true' : 'false';
    const h = document.createElement('h3');
    h.textContent = name;
    const seen = document.createElement('span');
    seen.className = 'seen';
    seen.textContent = stale ? 'not seen for ' + ago(age) : 'up';
    h.append(seen);
    const dl = document.createElement('dl');
    // A still light draws nothing new: its ticks are skipped, not lost.
    field(dl, 'frames', s.fps.toFixed(0) + ' drawn + ' + s.skipped + ' skipped /s, p99 ' +
          s.frame_p99_ms.toFixed(1) + ' ms');
    field(dl, 'SoC', s.soc_temp_c === null ? '—' : s.soc_temp_c.toFixed(1) + ' °C');
    field(dl, 'bundle', s.bundle + ' ' + s.bundle_checksum);
    field(dl, 'preset', s.preset + (s.blackout ? ' (blackout)' : ''));
    field(dl, 'input', s.input + ' (' + s.role + ')');
    field(dl, 'light', s.light.azimuth.toFixed(1) + '°, ' + s.light.elevation.toFixed(1) + '°, ' +
          s.light.distance.toFixed(2) + ' m');
    field(dl, 'uptime', ago(s.uptime_s * 1000));
    field(dl, 'watchdog', s.watchdog);
    field(dl, 'last error', s.last_error || 'none');
    card.replaceChildren(h, dl);
    installBlock(name);
  }
}

// ---- Install steps: a scan or a radiometric capture on one node ------------------------------

const ACTIONS = { scan: 'Scan', radiometry: 'Radiometric capture' };

// The node's block in the Install section, made once.
function installBlock(name) {
  let block = $('installs').querySelector('[data-node="' + CSS.escape(name) + '"]');
  if (block) return block;
  block = document.createElement('article');
  block.className = 'install';
  block.dataset.node = name;
  block.dataset.state = 'idle';
  const h = document.createElement('h3');
  h.textContent = name;
  const row = document.createElement('div');
  row.className = 'row';
  for (const [action, label] of Object.entries(ACTIONS)) {
    const button = document.createElement('button');
    button.textContent = label;
    button.dataset.action = action;
    button.addEventListener('click', () => sendInstall(name, action));
    row.append(button);
  }
  const bar = document.createElement('progress');
  bar.max = 1;
  bar.value = 0;
  bar.setAttribute('aria-label', name + ': progress');
  const text = document.createElement('p');
  text.className = 'install-state';
  text.setAttribute('aria-live', 'polite');
  text.textContent = 'No capture yet.';
  const images = document.createElement('div');
  images.className = 'images';
  for (const [kind, caption] of [['camera', 'Camera, white pattern'],
                                 ['coverage', 'Coverage: bright reads, dim lit only, black dark']]) {
    const figure = document.createElement('figure');
    figure.hidden = true;
    const picture = document.createElement('canvas');
    picture.className = kind;
    picture.setAttribute('role', 'img');
    picture.setAttribute('aria-label', name + ': ' + caption);
    const label = document.createElement('figcaption');
    label.textContent = caption;
    figure.append(picture, label);
    images.append(figure);
  }
  block.append(h, row, bar, text, images);
  const blocks = [...$('installs').children, block]
      .sort((a, b) => a.dataset.node.localeCompare(b.dataset.node));
  $('installs').replaceChildren(...blocks);
  renderInstallButtons();
  return block;
}

function renderInstallButtons() {
  const watching = document.body.classList.contains('viewer');
  for (const block of $('installs').children) {
    for (const button of block.querySelectorAll('button')) {
      button.disabled = watching || block.dataset.state === 'running';
    }
  }
}

function installReceived(node, what, payload) {
  const block = installBlock(node);
  if (what === 'progress') {
    const p = parse(payload);
    if (!p || typeof p.state !== 'string') return;
    block.dataset.state = p.state;
    const bar = block.querySelector('progress');
    bar.max = Math.max(1, p.frames_total);
    bar.value = p.state === 'done' ? bar.max : Math.min(p.frames_done, bar.max);
    const text = block.querySelector('.install-state');
    const label = ACTIONS[p.action] || p.action;
    text.classList.toggle('bad', p.state === 'failed');
    if (p.state === 'running') {
      text.textContent = label + ': ' + p.step + ', ' + p.frames_done + ' / ' + p.frames_total +
          ' images, ' + p.elapsed_s.toFixed(1) + ' s';
    } else if (p.state === 'done') {
      const share = (v) => (100 * v).toFixed(0) + ' %';
      text.textContent = label + ' done in ' + p.elapsed_s.toFixed(1) + ' s → ' + p.out +
          (p.lit_fraction === null ? '' : '; lit ' + share(p.lit_fraction)) +
          (p.decodable_fraction === null ? '' : ', decodable ' + share(p.decodable_fraction));
    } else {
      text.textContent = label + ' failed: ' + p.error;
    }
    renderInstallButtons();
  } else if (what === 'camera' || what === 'coverage') {
    const picture = block.querySelector('canvas.' + what);
    createImageBitmap(new Blob([payload], { type: 'image/png' })).then((bitmap) => {
      picture.width = bitmap.width;
      picture.height = bitmap.height;
      const g = picture.getContext('2d');
      g.drawImage(bitmap, 0, 0);
      if (what === 'coverage') {
        // Grey levels 0 (dark), 96 (lit only), 255 (reads) drawn in the page's dim amber: no
        // white slab in a dark room.
        const pixels = g.getImageData(0, 0, bitmap.width, bitmap.height);
        for (let i = 0; i < pixels.data.length; i += 4) {
          const v = pixels.data[i] / 255;
          pixels.data[i] = 176 * v;
          pixels.data[i + 1] = 138 * v;
          pixels.data[i + 2] = 74 * v;
        }
        g.putImageData(pixels, 0, 0);
      }
      picture.dataset.loaded = bitmap.width + 'x' + bitmap.height;
      picture.parentElement.hidden = false;
    }, () => {});  // not a PNG: nothing to draw
  }
}

// A command on vpe/<show>/command/<node> (proto/BUS.md, "Install steps"): not retained, so a
// node that restarts does not capture again.
function sendInstall(node, action) {
  if (!state.show) return;
  publish('vpe/' + state.show + '/command/' + node,
          { format: 1, node: state.id, time_us: showNowUs(), action }, null, false);
}

// ---- The light and the show's switches -------------------------------------------------------

// The limits every node accepts: the intersection of the boards' (they should be equal).
function limits() {
  const out = { azimuth: [-180, 180], elevation: [-90, 90], distance: [0, 1e9] };
  for (const { status } of state.nodes.values()) {
    for (const key of ['azimuth', 'elevation', 'distance']) {
      const range = status.limits[key];
      if (range) out[key] = [Math.max(out[key][0], range[0]), Math.min(out[key][1], range[1])];
    }
  }
  if (out.distance[1] > 1e8) out.distance = [0.05, 5];
  return out;
}

const clamp = (v, [lo, hi]) => Math.min(hi, Math.max(lo, v));

function presetNames() {
  const first = [...state.nodes.values()][0];
  return first ? first.status.presets : [];
}

function renderControls() {
  const lim = limits();
  const distance = $('distance');
  distance.min = lim.distance[0];
  distance.max = lim.distance[1];
  if (state.target && document.activeElement !== distance) distance.value = state.target.distance;
  const presets = $('presets');
  const names = presetNames();
  const current = state.light && state.light.preset;
  if (presets.dataset.names !== names.join('\n')) {
    presets.dataset.names = names.join('\n');
    presets.replaceChildren(...names.map((name) => {
      const button = document.createElement('button');
      button.textContent = name;
      button.dataset.preset = name;
      button.addEventListener('click', () => send({ preset: name }));
      return button;
    }));
  }
  for (const button of presets.children) {
    button.setAttribute('aria-pressed', String(button.dataset.preset === current));
  }
  $('drift').setAttribute('aria-pressed', String(state.drift));
  $('blackout').setAttribute('aria-pressed', String(state.blackout));
  $('blackout').textContent = state.blackout ? 'Blackout: on' : 'Blackout';
  drawSphere();
}

// The sphere seen from above: the centre is the zenith, the rim 10° below the horizon;
// azimuth 0 (toward the visitors) points down.
const canvas = $('sphere');
const RIM = 100;  // degrees from the zenith at the rim

function toCanvas(az, el) {
  const r = (canvas.width / 2 - 8) * (90 - el) / RIM;
  const a = az * Math.PI / 180;
  return [canvas.width / 2 + r * Math.sin(a), canvas.height / 2 + r * Math.cos(a)];
}

function fromCanvas(x, y) {
  const dx = x - canvas.width / 2, dy = y - canvas.height / 2;
  const r = Math.hypot(dx, dy) / (canvas.width / 2 - 8);
  return { azimuth: Math.atan2(dx, dy) * 180 / Math.PI, elevation: 90 - r * RIM };
}

function drawSphere() {
  const g = canvas.getContext('2d');
  const w = canvas.width, c = w / 2, R = c - 8;
  g.clearRect(0, 0, w, w);
  g.strokeStyle = '#333';
  g.lineWidth = 1;
  for (const el of [-10, 0, 30, 60]) {
    g.beginPath();
    g.arc(c, c, R * (90 - el) / RIM, 0, 2 * Math.PI);
    g.stroke();
  }
  // The boards' limits: the region the light may take.
  const lim = limits();
  g.fillStyle = 'rgba(176,138,74,0.14)';
  g.beginPath();
  const a0 = lim.azimuth[0], a1 = lim.azimuth[1];
  for (let a = a0; a <= a1; a += 2) g.lineTo(...toCanvas(a, lim.elevation[0]));
  for (let a = a1; a >= a0; a -= 2) g.lineTo(...toCanvas(a, lim.elevation[1]));
  g.closePath();
  g.fill();
  for (const { status } of state.nodes.values()) {
    g.fillStyle = '#8a8378';
    g.beginPath();
    g.arc(...toCanvas(status.light.azimuth, status.light.elevation), 4, 0, 2 * Math.PI);
    g.fill();
  }
  if (state.target) {
    g.strokeStyle = '#e0b060';
    g.lineWidth = 3;
    g.beginPath();
    g.arc(...toCanvas(state.target.azimuth, state.target.elevation), 10, 0, 2 * Math.PI);
    g.stroke();
    canvas.dataset.azimuth = state.target.azimuth.toFixed(3);
    canvas.dataset.elevation = state.target.elevation.toFixed(3);
    $('light-text').textContent = 'azimuth ' + state.target.azimuth.toFixed(1) +
        '°, elevation ' + state.target.elevation.toFixed(1) + '°, ' +
        Number(state.target.distance).toFixed(2) + ' m' + (state.drift ? ', drift on' : '');
  }
}

function moveTo(position) {
  const lim = limits();
  const base = state.target || { azimuth: 0, elevation: 30, distance: lim.distance[0] };
  state.target = {
    azimuth: clamp(position.azimuth ?? base.azimuth, lim.azimuth),
    elevation: clamp(position.elevation ?? base.elevation, lim.elevation),
    distance: clamp(position.distance ?? base.distance, lim.distance),
  };
  drawSphere();
  const wait = PUBLISH_MS - (Date.now() - state.lastSent);
  clearTimeout(state.timer);
  if (wait <= 0) send({});
  else state.timer = setTimeout(() => send({}), wait);
}

function pointerPosition(event) {
  const box = canvas.getBoundingClientRect();
  return fromCanvas((event.clientX - box.left) * canvas.width / box.width,
                    (event.clientY - box.top) * canvas.height / box.height);
}

canvas.addEventListener('pointerdown', (event) => {
  canvas.setPointerCapture(event.pointerId);
  moveTo(pointerPosition(event));
});
canvas.addEventListener('pointermove', (event) => {
  if (canvas.hasPointerCapture(event.pointerId)) moveTo(pointerPosition(event));
});
canvas.addEventListener('keydown', (event) => {
  const t = state.target;
  if (!t) return;
  const step = { ArrowLeft: [-5, 0], ArrowRight: [5, 0], ArrowUp: [0, 5], ArrowDown: [0, -5] }[event.key];
  if (step) {
    event.preventDefault();
    moveTo({ azimuth: t.azimuth + step[0], elevation: t.elevation + step[1] });
  }
});
$('distance').addEventListener('input', (event) => moveTo({ distance: Number(event.target.value) }));
$('drift').addEventListener('click', () => {
  state.drift = !state.drift;
  send({ driftNow: state.drift });
});
$('blackout').addEventListener('click', () => {
  const on = !state.blackout;
  publish('vpe/' + state.show + '/blackout',
          { format: 1, node: state.id, time_us: showNowUs(), on }, () => {
    state.blackout = on;
    renderControls();
  });
});

// One state on vpe/<show>/light (proto/BUS.md): the move starts from the last target sent, so
// the nodes glide along a drag with their own smoothing.
function send({ preset, driftNow }) {
  if (!state.show || !state.target) return;
  state.lastSent = Date.now();
  const t = showNowUs();
  const from = state.light
      ? { azimuth: state.light.azimuth, elevation: state.light.elevation,
          distance: state.light.distance }
      : state.target;
  const message = {
    format: 1, node: state.id, seq: ++state.seq, time_us: t,
    azimuth: state.target.azimuth, elevation: state.target.elevation,
    distance: state.target.distance,
    from: { time_us: t, ...from },
    drift_us: state.drift ? (driftNow ? t : t + PAGE_QUIET_US) : null,
    preset: preset ?? (state.light && state.light.preset) ?? '',
    source: 'page',
  };
  state.light = message;
  publish('vpe/' + state.show + '/light', message);
}

function publish(topic, message, done, retain = true) {
  state.client.publish(topic, JSON.stringify(message), { qos: 1, retain }, (error) => {
    if (error) {
      $('control-error').textContent = 'The broker refused this as "' + state.user +
          '" (' + error.message + '): this login may only watch.';
      document.body.classList.add('viewer');
      renderInstallButtons();
      if (topic.endsWith('/light')) {
        // Nothing moved: show the show's light again.
        state.light = state.confirmed || null;
        state.target = state.light && { azimuth: state.light.azimuth,
                                        elevation: state.light.elevation,
                                        distance: state.light.distance };
        renderControls();
      }
    } else {
      $('control-error').textContent = '';
      if (done) done();
    }
  });
}
