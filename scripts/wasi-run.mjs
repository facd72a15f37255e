// Runs a wasm32-wasip1 program (a test binary) under Node's built-in WASI,
// as a cargo runner:
//
//   CARGO_TARGET_WASM32_WASIP1_RUNNER="node --no-warnings scripts/wasi-run.mjs" \
//     cargo test --target wasm32-wasip1 --test golden
//
// Usage: node wasi-run.mjs <program.wasm> [args...]
// The program gets the arguments and the environment, and no directories:
// the golden tests read no files. Exits with the program's exit code; a trap
// (a panic under panic=abort) is reported and exits with 101.
import { readFile } from 'node:fs/promises';
import process from 'node:process';
import { WASI } from 'node:wasi';

const [wasmPath, ...args] = process.argv.slice(2);
if (!wasmPath) {
  console.error('usage: node wasi-run.mjs <program.wasm> [args...]');
  process.exit(2);
}

const wasi = new WASI({
  version: 'preview1',
  args: [wasmPath, ...args],
  env: process.env,
  preopens: {},
  returnOnExit: true,
});

let code;
try {
  const module = await WebAssembly.compile(await readFile(wasmPath));
  const instance = await WebAssembly.instantiate(module, wasi.getImportObject());
  code = wasi.start(instance);
} catch (err) {
  console.error(`wasi-run: ${wasmPath} trapped: ${err && err.stack ? err.stack : err}`);
  code = 101;
}
process.exit(code);
