// The demo page: a playground, the "same bits" panel and the lockstep view.
// `?check` runs the browser test first (every golden check, frame times,
// a lockstep run) and posts the results to the server's /report
// (`tamias web --check` reads them), then plays as usual. The page loads
// the engine's `simd128` build where the browser has 128-bit SIMD, the
// scalar build elsewhere (`?wasm=scalar` forces it); the check runs the
// goldens and the frame times on the other build too.
import { Tamias, MODULES } from './tamias.js';

const params = new URLSearchParams(location.search);
const CHECK = params.has('check');
const $ = (id) => document.getElementById(id);
const color = (c) => '#' + (c >>> 0).toString(16).padStart(6, '0');
// A zero time is no measurement (headless Chromium's virtual time, which
// screenshots use, stands still while a script runs): shown as a dash.
const ms = (t) => (!(t > 0) ? '–' : t < 0.1 ? `${(t * 1000).toFixed(0)} µs` : `${t.toFixed(2)} ms`);
const median = (xs) => { const s = [...xs].sort((a, b) => a - b); return s[s.length >> 1]; };

// ---------------------------------------------------------------- drawing --

/** Walks a draw list (layout in web/src/draw.rs). */
function walk(list, on) {
  let i = 0;
  while (i < list.length) {
    const kind = list[i];
    if (kind === 0) { on.circle(list[i + 1], list[i + 2], list[i + 3], list[i + 4], list[i + 5], list[i + 6]); i += 7; }
    else if (kind === 1) { on.segment(list[i + 1], list[i + 2], list[i + 3], list[i + 4], list[i + 5], list[i + 6]); i += 7; }
    else if (kind === 2) { const n = list[i + 1]; on.polygon(list.subarray(i + 4, i + 4 + 2 * n), list[i + 2], list[i + 3]); i += 4 + 2 * n; }
    else if (kind === 3) { on.dot(list[i + 1], list[i + 2], list[i + 3], list[i + 4]); i += 5; }
    else break;
  }
}

/** A canvas showing world space (y up), fitted to a scene's extent. */
class View {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d');
    this.scale = 1; this.ox = 0; this.oy = 0;
  }

  fit(list) {
    let [l, b, r, t] = [Infinity, Infinity, -Infinity, -Infinity];
    const grow = (x, y, pad = 0) => { l = Math.min(l, x - pad); r = Math.max(r, x + pad); b = Math.min(b, y - pad); t = Math.max(t, y + pad); };
    walk(list, {
      circle: (x, y, rad) => grow(x, y, rad),
      segment: (ax, ay, bx, by, rad) => { grow(ax, ay, rad); grow(bx, by, rad); },
      polygon: (v) => { for (let k = 0; k < v.length; k += 2) grow(v[k], v[k + 1]); },
      dot: () => {},
    });
    if (!(r > l && t > b)) { l = -10; r = 10; b = -10; t = 10; }
    const { width: w, height: h } = this.canvas;
    this.scale = 0.92 * Math.min(w / (r - l), h / (t - b));
    this.ox = w / 2 - this.scale * (l + r) / 2;
    this.oy = h / 2 + this.scale * (b + t) / 2;
    this.world = { l, b, r, t };
  }

  toWorld(event) {
    const rect = this.canvas.getBoundingClientRect();
    const px = (event.clientX - rect.left) * this.canvas.width / rect.width;
    const py = (event.clientY - rect.top) * this.canvas.height / rect.height;
    return [(px - this.ox) / this.scale, (this.oy - py) / this.scale];
  }

  draw(list) {
    const { ctx, scale: s, ox, oy } = this;
    const X = (x) => ox + s * x, Y = (y) => oy - s * y;
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    ctx.lineJoin = 'round'; ctx.lineCap = 'round';
    walk(list, {
      circle(x, y, rad, c, sn, fill) {
        ctx.beginPath(); ctx.arc(X(x), Y(y), Math.max(s * rad, 1), 0, 2 * Math.PI);
        ctx.fillStyle = color(fill); ctx.fill();
        ctx.strokeStyle = 'rgba(0,0,0,0.45)'; ctx.lineWidth = 1; ctx.stroke();
        ctx.beginPath(); ctx.moveTo(X(x), Y(y)); ctx.lineTo(X(x + c * rad), Y(y + sn * rad)); ctx.stroke();
      },
      segment(ax, ay, bx, by, rad, fill) {
        ctx.beginPath(); ctx.moveTo(X(ax), Y(ay)); ctx.lineTo(X(bx), Y(by));
        ctx.strokeStyle = color(fill); ctx.lineWidth = Math.max(2 * s * rad, 2); ctx.stroke();
      },
      polygon(v, rad, fill) {
        ctx.beginPath(); ctx.moveTo(X(v[0]), Y(v[1]));
        for (let k = 2; k < v.length; k += 2) ctx.lineTo(X(v[k]), Y(v[k + 1]));
        ctx.closePath(); ctx.fillStyle = color(fill); ctx.fill();
        ctx.strokeStyle = rad > 0 ? color(fill) : 'rgba(0,0,0,0.45)';
        ctx.lineWidth = rad > 0 ? Math.max(2 * s * rad, 1) : 1; ctx.stroke();
      },
      dot(x, y, size, c) {
        ctx.fillStyle = color(c); ctx.fillRect(X(x) - size / 2, Y(y) - size / 2, size, size);
      },
    });
  }
}

// ------------------------------------------------------------- the page ---

const KIND = Tamias.moduleKind(location.search);
const engine = await Tamias.load(MODULES[KIND]);
// The check also runs the build the page did not choose (the scalar one,
// where the browser has SIMD): both must give the native bits.
const OTHER = KIND === 'simd128' ? 'scalar' : 'simd128';
const other = CHECK && (OTHER === 'scalar' || Tamias.hasSimd128())
  ? await Tamias.load(MODULES[OTHER]) : null;
$('wasmkind').textContent = KIND === 'simd128' ? 'wasm simd128' : 'wasm scalar (no simd128 here)';
const catalog = engine.catalog();
const indexOf = (name) => catalog.findIndex((s) => s.name === name);
const status = (text) => { $('status').textContent = text; };

// Playground.
const view = new View($('view'));
const play = { index: indexOf('pyramid_20'), running: true, dragging: false, times: [] };
for (const [i, s] of catalog.entries()) {
  const o = document.createElement('option');
  o.value = i; o.textContent = `${s.section} · ${s.name}`; o.title = s.about;
  $('scene').append(o);
}

function loadScene(index) {
  play.index = index; play.times = [];
  engine.playBuiltin(index);
  engine.setSolver($('solver').value);
  $('scene').value = index;
  view.fit(engine.drawPlay(false));
  $('load').disabled = true; $('snapshot').textContent = '–';
  status(`${catalog[index].name}: ${catalog[index].about}`);
}

function stepPlay() {
  const t0 = performance.now();
  engine.step(1);
  play.times.push(performance.now() - t0);
  if (play.times.length > 60) play.times.shift();
}

function showPlay() {
  view.draw(engine.drawPlay($('contacts').checked));
  const st = engine.status();
  $('steps').textContent = st.steps;
  $('bodies').textContent = st.bodies;
  $('checksum').textContent = st.checksum;
  if (play.times.length) $('steptime').textContent = ms(median(play.times));
}

/** Runs `f`; an engine error is shown in the status line, not thrown. */
const guard = (f) => (...args) => {
  try { return f(...args); } catch (e) { status(`error: ${e.message}`); return undefined; }
};

$('scene').onchange = (e) => loadScene(Number(e.target.value));
$('solver').onchange = guard((e) => engine.setSolver(e.target.value));
$('scenefile').onchange = guard(async (e) => {
  const file = e.target.files[0];
  if (!file) return;
  const text = await file.text();
  try {
    engine.playJson(text);
  } catch (err) {
    status(`${file.name}: ${err.message}`);
    return;
  }
  play.times = [];
  view.fit(engine.drawPlay(false));
  $('load').disabled = true; $('snapshot').textContent = '–';
  status(`${file.name}: ${engine.status().name}`);
});
$('pause').onclick = () => { play.running = !play.running; $('pause').textContent = play.running ? 'Pause' : 'Play'; };
$('stepone').onclick = () => { stepPlay(); showPlay(); };
$('reset').onclick = () => loadScene(play.index);
$('save').onclick = guard(() => { const n = engine.save(); $('snapshot').textContent = `${n} B saved`; $('load').disabled = false; });
$('load').onclick = guard(() => { engine.load(); showPlay(); $('snapshot').textContent += ', loaded'; });
$('view').addEventListener('pointerdown', guard((e) => {
  const [x, y] = view.toWorld(e);
  const reach = 6 / view.scale;
  if (engine.dragBegin(x, y, reach)) {
    play.dragging = true; $('view').setPointerCapture(e.pointerId);
  } else {
    engine.drop($('dropkind').value, x, y);
  }
}));
$('view').addEventListener('pointermove', guard((e) => { if (play.dragging) engine.dragMove(...view.toWorld(e)); }));
const endDrag = guard(() => { if (play.dragging) { play.dragging = false; engine.dragEnd(); } });
$('view').addEventListener('pointerup', endDrag);
$('view').addEventListener('pointercancel', endDrag);

// Same bits.
function runGolden(i) {
  return showGolden(engine.goldenRun(i));
}

function showGolden(o) {
  const same = o.computed === o.golden;
  const row = document.createElement('tr');
  row.dataset.scene = o.name; row.dataset.computed = o.computed;
  row.innerHTML = `<td>${o.name}</td><td>${o.steps}</td><td class="mono">${o.computed}</td>` +
    `<td class="mono">${o.golden}</td><td class="${same ? 'ok' : 'bad'}">${same ? '✅' : '❌'}</td>`;
  $('same-rows').append(row);
  return o;
}

function summarise(outcomes, total) {
  const k = outcomes.filter((o) => o.computed === o.golden).length;
  const done = outcomes.length === total;
  $('same-summary').textContent = `same bits: ${k}/${total}` + (done ? (k === total ? ' ✅' : ' ❌') : ' …');
  $('same-summary').className = 'summary ' + (done ? (k === total ? 'ok' : 'bad') : '');
}

// Lockstep.
const DELAY = 6, AUTO_EVERY = 60, INPUTS_PER_GAME = 40;
const lock = { index: indexOf('bowl_boxes_100'), views: [new View($('peerA')), new View($('peerB'))],
  pending: null, inputs: 0, frames: 0, agreed: 0, confirmed: 0, rollbacks: 0, lastMs: null, maxMs: 0, lastFrames: 0 };
$('delay').textContent = DELAY;

function newGame() {
  engine.lockstepNew(lock.index, DELAY);
  for (const [i, v] of lock.views.entries()) v.fit(engine.drawPeer(i === 1, false));
  lock.inputs = 0;
}

/** The automatic input of frame `f`: a ball over one of five columns. */
function autoInput(f) {
  if (f % AUTO_EVERY !== AUTO_EVERY - 1) return null;
  const w = lock.views[0].world;
  const col = Math.floor(f / AUTO_EVERY) % 5;
  return [w.l + (w.r - w.l) * (0.3 + 0.1 * col), w.t - 0.1 * (w.t - w.b)];
}

function frameLockstep() {
  const game = engine.lockstepStatus();
  const input = lock.pending ?? autoInput(game.frame);
  lock.pending = null;
  engine.lockstepA(input);
  const t0 = performance.now();
  const replayed = engine.lockstepB();
  const took = performance.now() - t0;
  if (replayed > 0) { lock.lastMs = took; lock.maxMs = Math.max(lock.maxMs, took); lock.lastFrames = replayed; lock.rollbacks++; }
  const st = engine.lockstepStatus();
  if (st.confirmed_frame !== null) {
    lock.confirmed++;
    if (st.confirmed_a === st.confirmed_b) lock.agreed++;
  }
  lock.frames++;
  if (input && ++lock.inputs >= INPUTS_PER_GAME) newGame();
  return st;
}

function showLockstep(st) {
  for (const [i, v] of lock.views.entries()) v.draw(engine.drawPeer(i === 1, false));
  $('ls-frame').textContent = st.frame;
  $('ls-confirmed').textContent = st.confirmed_frame ?? '–';
  $('ls-sums').textContent = st.confirmed_a ? `${st.confirmed_a} / ${st.confirmed_b}` : '–';
  const all = lock.agreed === lock.confirmed;
  $('ls-agree').textContent = `${lock.agreed}/${lock.confirmed} frames ${all ? '✅' : '❌'}`;
  $('ls-agree').className = all ? 'ok' : 'bad';
  $('ls-rollbacks').textContent = lock.rollbacks;
  if (lock.lastMs !== null) $('ls-last').textContent = `${lock.lastFrames} frames replayed` + (lock.lastMs > 0 ? ` in ${ms(lock.lastMs)} (slowest ${ms(lock.maxMs)})` : '');
}

for (const c of ['peerA', 'peerB']) {
  $(c).addEventListener('pointerdown', (e) => { lock.pending = lock.views[c === 'peerA' ? 0 : 1].toWorld(e); });
}

// ------------------------------------------------------- the browser test --

/** Mean ms per step of a built-in scene over its first 300 steps from the
 * build (5 s of play: falling, piling, settling), on `solver` (as
 * `setSolver` takes it), as `tamias web --check` measures natively. */
function frameTime(eng, name, solver) {
  eng.playBuiltin(indexOf(name));
  eng.setSolver(solver);
  const t0 = performance.now();
  eng.step(300);
  return (performance.now() - t0) / 300;
}

/** The frame times of one build:
 * `{"pyramid_20": ms, "pyramid_20 soft": ms, "pyramid_20 soft narrow": ms, …}`. */
function frameTimes(eng) {
  const timings = {};
  for (const name of ['pyramid_20', 'bowl_boxes_500']) {
    timings[name] = frameTime(eng, name, 'sequential');
    timings[`${name} soft`] = frameTime(eng, name, 'soft');
    timings[`${name} soft narrow`] = frameTime(eng, name, 'narrow');
  }
  return timings;
}

/** The page's own wiring, through real pointer events on the playground:
 * a press on the top box of pyramid_20 grabs it (a drag starts), the
 * release ends the drag, a press on empty space drops a body. */
function checkPointer() {
  loadScene(indexOf('pyramid_20'));
  let top = null;
  walk(engine.drawPlay(false), {
    circle() {}, segment() {}, dot() {},
    polygon(v) {
      let [x, y] = [0, 0];
      for (let k = 0; k < v.length; k += 2) { x += v[k]; y += v[k + 1]; }
      const c = [2 * x / v.length, 2 * y / v.length];
      if (!top || c[1] > top[1]) top = c;
    },
  });
  const canvas = $('view');
  const rect = canvas.getBoundingClientRect();
  const client = ([x, y]) => ({
    clientX: rect.left + (view.ox + view.scale * x) * rect.width / canvas.width,
    clientY: rect.top + (view.oy - view.scale * y) * rect.height / canvas.height,
  });
  const fire = (type, at) => canvas.dispatchEvent(new PointerEvent(type, { bubbles: true, pointerId: 1, ...client(at) }));
  fire('pointerdown', top);
  const grabbed = engine.status().dragging;
  fire('pointermove', [top[0], top[1] + 1]);
  fire('pointerup', top);
  const released = !engine.status().dragging;
  const before = engine.status().bodies;
  fire('pointerdown', [top[0], top[1] + 0.3 * (view.world.t - view.world.b)]);
  fire('pointerup', top);
  const dropped = engine.status().bodies === before + 1;
  return { grabbed, released, dropped };
}

/** The browser test, synchronous from start to end (so a screenshot taken
 * after it sees the finished page); the report is posted to /report. */
function check() {
  const total = engine.goldenCount();
  const goldens = [];
  for (let i = 0; i < total; i++) goldens.push(runGolden(i));
  summarise(goldens, total);
  const timings = frameTimes(engine);
  let fallback = null;
  if (other) {
    const outcomes = [];
    for (let i = 0; i < other.goldenCount(); i++) outcomes.push(other.goldenRun(i));
    fallback = { module: OTHER, goldens: outcomes, timings: frameTimes(other) };
  }
  newGame();
  let st;
  for (let f = 0; f < 300; f++) st = frameLockstep();
  const report = {
    module: KIND, goldens, timings, fallback, userAgent: navigator.userAgent,
    lockstep: { frames: st.frame, confirmed: lock.confirmed, agreed: lock.agreed, rollbacks: lock.rollbacks },
  };
  report.ui = checkPointer();
  fetch('/report', { method: 'POST', body: JSON.stringify(report) })
    .then(() => { document.title = 'tamias: check done'; });
  const same = `browser test done: same bits ${goldens.filter((o) => o.computed === o.golden).length}/${total}`;
  return timings.pyramid_20 > 0
    ? `${same}; pyramid_20 ${ms(timings.pyramid_20)} per step, bowl_boxes_500 ${ms(timings.bowl_boxes_500)} per step (first 300 steps)`
    : same;
}

// ----------------------------------------------------------------- start --

if (CHECK) {
  const done = check();
  // A lively playground for a screenshot: three balls dropped on the pyramid.
  loadScene(indexOf('pyramid_20'));
  const w = view.world;
  for (const [k, dx] of [[0, -0.06], [1, 0.05], [2, 0.0]]) {
    engine.drop('ball', (w.l + w.r) / 2 + dx * (w.r - w.l), w.t + (0.1 + 0.25 * k) * (w.t - w.b));
  }
  view.fit(engine.drawPlay(false));
  for (let k = 0; k < 100; k++) stepPlay();
  status(done);
} else {
  loadScene(play.index);
  newGame();
  // The goldens run in a worker, so the page keeps drawing meanwhile.
  const total = engine.goldenCount(); const goldens = [];
  const worker = new Worker(`golden-worker.js?wasm=${KIND}`, { type: 'module' });
  worker.onmessage = ({ data }) => {
    if (data.outcome) { goldens.push(showGolden(data.outcome)); summarise(goldens, total); }
    if (data.error) status(`same bits: ${data.error}`);
  };
}

function animate() {
  try {
    if (play.running) stepPlay();
    showPlay();
    showLockstep(frameLockstep());
  } catch (e) {
    // An engine error stops the animation with its message, not silently.
    status(`stopped: ${e.message}`);
    return;
  }
  requestAnimationFrame(animate);
}
requestAnimationFrame(animate);
