// Runs every golden scene in a worker of its own (its own instance of the
// module), so the page keeps drawing at 60 Hz meanwhile. Posts one outcome
// per scene ({name, steps, computed, golden}), then {done: true}.
import { Tamias } from './tamias.js';

const engine = await Tamias.load('tamias2d_web.wasm');
const total = engine.goldenCount();
postMessage({ total });
for (let i = 0; i < total; i++) {
  try {
    postMessage({ outcome: engine.goldenRun(i) });
  } catch (e) {
    postMessage({ error: e.message });
  }
}
postMessage({ done: true });
