// threadcut's engine off the page's thread: the wasm module runs here, so that analysing a long
// program never freezes the page. Messages: {id, fn, arg} in (fn one of the module's JSON
// functions, arg its JSON text); {id, result, ms} out (result the function's JSON text, ms the
// time it took).
import init, * as tc from './pkg/threadcut_web.js';

const ready = init();
// Warming (`warm`, the page's analysis request without its program): the browser compiles the
// module's functions as they first run, and optimises the busy ones after a while, so the first
// analysis of a long paste ran at about half the speed of the next one (docs/performance.md).
// The page asks once for each controller it selects; the worker then analyses a hundred
// M20x2.5 cycles written for that controller (Fanuc's G76, converted by the engine itself),
// after whatever it was asked before, and drops the result. OmniTurn's G33 starts its passes
// from the tool's position, which a G76 cannot be converted to: its program is the seed's
// external thread (inch) in its own words.
const WARM_FANUC = 'G21\nG97 S500 M03\n' +
  'G00 X22. Z7.5\nG76 P020060 Q100 R0.05\nG76 X16.932 Z-30. P1534 Q470 F2.5\n'.repeat(100) + 'M30\n';
const WARM_OWN = { omniturn: 'T4F200\n' + 'X0Z.2\nX.237\nG33X.212Z-.5I.012K.05PC\n'.repeat(100) };

function warm(arg) {
  const request = JSON.parse(arg);
  let program = WARM_OWN[request.controller] || WARM_FANUC;
  if (program === WARM_FANUC && request.controller !== 'fanuc') {
    const converted = JSON.parse(tc.convert(JSON.stringify({ from: 'fanuc', to: request.controller, program })));
    if (!converted.ok) return JSON.stringify({ ok: false, error: converted.error });
    program = converted.program;
  }
  const analysed = JSON.parse(tc.analyse(JSON.stringify({ ...request, program })));
  return JSON.stringify({ ok: analysed.ok === true, error: analysed.ok ? undefined : 'the warm-up program did not analyse' });
}

const functions = { controllers: tc.controllers, thread: tc.thread, fill: tc.fill, plan: tc.plan, analyse: tc.analyse, expand: tc.expand, convert: tc.convert, warm };

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
