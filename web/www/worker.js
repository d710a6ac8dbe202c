// threadcut's engine off the page's thread: the wasm module runs here, so that analysing a long
// program never freezes the page. Messages: {id, fn, arg} in (fn one of the module's JSON
// functions, arg its JSON text); {id, result, ms} out (result the function's JSON text, ms the
// time it took).
import init, * as tc from './pkg/threadcut_web.js';

const ready = init();
// Warming (`warm`, the page's analysis request without its program): the browser compiles the
// module's functions as they first run, and optimises the busy ones after a while, so the first
// analysis of a long paste ran at about half the speed of the next one (docs/performance.md).
// After an analysis the page asks the worker, once, to analyse a hundred M20x2.5 cycles in the
// controller's own words (its threading cycle, read, planned, checked and expanded as a pasted
// one is; GSK's and Fanuc system B's are Fanuc's G76 converted by the engine), and drops the
// result.
const hundred = (head, cycle) => head + cycle.repeat(100) + 'M30\n';
const WARM_FANUC = hundred('G21\nG97 S500 M03\n', 'G00 X22. Z7.5\nG76 P020060 Q100 R0.05\nG76 X16.932 Z-30. P1534 Q470 F2.5\n');
const WARM = {
  fanuc: WARM_FANUC,
  fanuc15: hundred('G21 G99\nG97 S500 M03\n', 'G00 X22. Z7.5\nG76 X16.932 Z-30. K1.534 D0.4 F2.5 A60 P1\n'),
  haas: hundred('G21\nG97 S500 M03\n', 'G00 X22. Z5.\nG76 X16.933 Z-30. K1.534 D0.4 F2.5 A60\n'),
  ab9: hundred('G21\nG97 S500 M03\n', 'G90 G00 X22. Z7.5\nG78 X16.932 Z-30. K1.534 D0.47 F2.5 A60 P1\n'),
  linuxcnc: hundred('G7 G21 G18\nS500 M3\n', 'G0 X22 Z5\nG76 P2.5 Z-30 I-1 J0.2 K1.534 Q29.5 L2 E1\n'),
  sinumerik: hundred('G18 G90 DIAMON\nS500 M3\n', 'G0 X22 Z5\nCYCLE97(2.5,,0,-30,20,20,3,3,1.534,0.05,30,0,5,2,3,1)\n'),
  // The seed's external thread (inch): G33 starts its passes from the tool's position.
  omniturn: hundred('T4F200\nM3 S500\n', 'X0Z.2\nX.237\nG33X.212Z-.5I.012K.05PC\n'),
};

function warm(arg) {
  const request = JSON.parse(arg);
  let program = WARM[request.controller];
  if (!program) {
    const converted = JSON.parse(tc.convert(JSON.stringify({ from: 'fanuc', to: request.controller, program: WARM_FANUC })));
    if (!converted.ok) return JSON.stringify({ ok: false, error: converted.error });
    program = converted.program;
  }
  const analysed = JSON.parse(tc.analyse(JSON.stringify({ ...request, program })));
  return JSON.stringify({ ok: analysed.ok === true, threads: analysed.cycles_total, diagnostics: analysed.diagnostics.length });
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
