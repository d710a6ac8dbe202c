// threadcut's engine off the page's thread: the wasm module runs here, so that analysing a long
// program never freezes the page. Messages: {id, fn, arg} in (fn one of the module's JSON
// functions, arg its JSON text); {id, result, ms} out (result the function's JSON text, ms the
// time it took).
import init, * as tc from './pkg/threadcut_web.js';

const ready = init();
const functions = { controllers: tc.controllers, thread: tc.thread, fill: tc.fill, plan: tc.plan, analyse: tc.analyse, expand: tc.expand, convert: tc.convert };

self.onmessage = async (e) => {
  const { id, fn, arg } = e.data;
  let result;
  const start = performance.now();
  try {
    await ready;
    const f = functions[fn];
    result = f ? (arg === undefined ? f() : f(arg)) : JSON.stringify({ ok: false, error: `no function ${fn}` });
  } catch (err) {
    result = JSON.stringify({ ok: false, error: `the threadcut module failed: ${err}` });
  }
  self.postMessage({ id, result, ms: performance.now() - start });
};
