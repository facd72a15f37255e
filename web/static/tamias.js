// The hand-written glue between the page and the engine's wasm module
// (web/src/exports.rs holds the other side and its conventions).
//
// The module imports nothing and exports C-ABI functions: numbers in,
// numbers out, text through one out buffer in wasm memory, input text
// through an in buffer. A negative result is an error whose message is in
// the out buffer; this glue turns it into a thrown Error.
//
// Works in the browser (`Tamias.load(url)`) and in Node (`Tamias.load(bytes)`).

const decoder = new TextDecoder();
const encoder = new TextEncoder();

/** A module of one function that uses a 128-bit SIMD instruction
 * (`i32.const 0; i8x16.splat; i8x16.popcnt`): it validates only where
 * the engine has `simd128`. */
const SIMD_PROBE = new Uint8Array([
  0, 97, 115, 109, 1, 0, 0, 0, 1, 5, 1, 96, 0, 1, 123, 3, 2, 1, 0,
  10, 10, 1, 8, 0, 65, 0, 253, 15, 253, 98, 11,
]);

/** The two builds of the engine: the same bits, different speed. */
/** The playground's solvers, in the order of `tamias_play_solver`'s modes. */
const SOLVERS = ['sequential', 'soft', 'narrow'];

export const MODULES = {
  simd128: 'tamias2d_web_simd128.wasm',
  scalar: 'tamias2d_web.wasm',
};

export class Tamias {
  /** True when this WebAssembly engine runs 128-bit SIMD. */
  static hasSimd128() { return WebAssembly.validate(SIMD_PROBE); }

  /** Which build to load: `simd128` where the engine has it, else
   * `scalar`; `?wasm=scalar` (or `simd128`) in `search` forces one. */
  static moduleKind(search = '') {
    const asked = new URLSearchParams(search).get('wasm');
    if (asked in MODULES) return asked;
    return Tamias.hasSimd128() ? 'simd128' : 'scalar';
  }

  /** Instantiates the module from a URL (fetched) or its bytes. */
  static async load(source) {
    const bytes = typeof source === 'string'
      ? await (await fetch(source)).arrayBuffer()
      : source;
    const { instance } = await WebAssembly.instantiate(bytes, {});
    return new Tamias(instance.exports);
  }

  constructor(exports) {
    this.x = exports;
  }

  // --- buffers -----------------------------------------------------------

  /** The out buffer as text. */
  text() {
    const ptr = this.x.tamias_out_ptr();
    const len = this.x.tamias_out_len();
    return decoder.decode(new Uint8Array(this.x.memory.buffer, ptr, len));
  }

  /** `r` if it is not an error, else throws the module's message. */
  ok(r) {
    if (r < 0) throw new Error(this.text());
    return r;
  }

  /** The out buffer as JSON, after a call that returned `r`. */
  json(r) {
    this.ok(r);
    return JSON.parse(this.text());
  }

  /** The draw list the last draw call filled (a view: read it before the next call). */
  drawList(r) {
    const n = this.ok(r);
    return new Float32Array(this.x.memory.buffer, this.x.tamias_draw_ptr(), n);
  }

  // --- the playground ----------------------------------------------------

  /** `[{name, section, about, bodies}]`, in registry order. */
  catalog() { return this.json(this.x.tamias_scene_catalog()); }
  playBuiltin(index) { this.ok(this.x.tamias_play_builtin(index)); }
  playJson(text) {
    const bytes = encoder.encode(text);
    const ptr = this.x.tamias_in_reserve(bytes.length);
    new Uint8Array(this.x.memory.buffer, ptr, bytes.length).set(bytes);
    this.ok(this.x.tamias_play_json());
  }
  step(n = 1) { this.ok(this.x.tamias_play_step(n)); }
  /** The playground's solver: `'sequential'`, `'soft'` (the soft step) or
   * `'narrow'` (the soft step on the narrow contact kernels). */
  setSolver(name) { this.ok(this.x.tamias_play_solver(SOLVERS.indexOf(name))); }
  /** `{name, steps, bodies, checksum, dragging}`. */
  status() { return this.json(this.x.tamias_play_status()); }
  drawPlay(contacts) { return this.drawList(this.x.tamias_play_draw(contacts ? 1 : 0)); }
  /** Every body's `x, y, cos θ, sin θ` (4 floats per body, slot order), for sprites. */
  bodyTransforms() { return this.drawList(this.x.tamias_play_transforms()); }
  /** True if a body was grabbed. */
  dragBegin(x, y, reach) { return this.ok(this.x.tamias_drag_begin(x, y, reach)) === 1; }
  dragMove(x, y) { this.ok(this.x.tamias_drag_move(x, y)); }
  dragEnd() { this.ok(this.x.tamias_drag_end()); }
  drop(kind, x, y) { this.ok(this.x.tamias_drop(kind === 'box' ? 1 : 0, x, y)); }
  /** Saves a frame snapshot; returns its size in bytes. */
  save() { return this.ok(this.x.tamias_save()); }
  load() { this.ok(this.x.tamias_load()); }

  // --- same bits -----------------------------------------------------------

  goldenCount() { return this.x.tamias_golden_count(); }
  /** `{name, steps, computed, golden}` (checksums as hex strings). */
  goldenRun(index) { return this.json(this.x.tamias_golden_run(index)); }

  // --- lockstep ------------------------------------------------------------

  lockstepNew(index, delay) { this.ok(this.x.tamias_lockstep_new(index, delay)); }
  /** Peer A's frame, with an optional input `[x, y]` (drop a ball there). */
  lockstepA(input) {
    const [has, x, y] = input ? [1, input[0], input[1]] : [0, 0, 0];
    this.ok(this.x.tamias_lockstep_a(has, x, y));
  }
  /** Peer B's frame; the frames it replayed (0: no rollback). */
  lockstepB() { return this.ok(this.x.tamias_lockstep_b()); }
  lockstepStatus() { return this.json(this.x.tamias_lockstep_status()); }
  drawPeer(b, contacts) { return this.drawList(this.x.tamias_lockstep_draw(b ? 1 : 0, contacts ? 1 : 0)); }
}
