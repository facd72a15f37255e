// Runs every golden scene in a worker of its own (its own instance of the
// module), so the page keeps drawing at 60 Hz meanwhile. Posts one outcome
// per scene ({name, steps, computed, golden}), then {done: true}.
// The page names the build in the worker's query (`?wasm=simd128`).
import { Tamias, MODULES } from './tamias.js';

const engine = await Tamias.load(MODULES[Tamias.moduleKind(self.location.search)]);
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
