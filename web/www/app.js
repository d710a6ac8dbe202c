// threadcut thread planner: the page around the wasm module. No framework, no network: every
// result comes from the threadcut library compiled to WebAssembly (pkg/, built by web/build.sh),
// which runs in a Web Worker (worker.js): the page stays responsive while a long program is
// analysed, and an analysis starts once typing pauses.

const $ = (id) => document.getElementById(id);

// How long typing must pause before an analysis starts (ms): a pasted program is analysed at once
// after the paste; a program being typed, after the last keystroke.
const PAUSE_MS = 150;

/** The worker and its calls: each call a promise of the function's parsed JSON. */
class Engine {
  constructor() {
    this.next = 0;
    this.spawn();
  }

  spawn() {
    this.worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });
    this.waiting = new Map();
    this.warmed = new Set();
    this.worker.onmessage = (e) => {
      const w = this.waiting.get(e.data.id);
      if (!w) return;
      this.waiting.delete(e.data.id);
      if (w.fn === 'warm') return w.resolve(JSON.parse(e.data.result));
      this.lastMs = e.data.ms;
      performance.mark('threadcut:result');
      w.resolve(JSON.parse(e.data.result));
    };
    this.worker.onerror = (e) => {
      for (const w of this.waiting.values()) w.resolve({ ok: false, error: `the threadcut module failed: ${e.message}` });
      this.waiting.clear();
    };
  }

  call(fn, arg) {
    const id = ++this.next;
    const text = arg === undefined || typeof arg === 'string' ? arg : JSON.stringify(arg);
    return new Promise((resolve) => {
      this.waiting.set(id, { fn, text, resolve });
      this.worker.postMessage({ id, fn, arg: text });
    });
  }

  /** Has the worker analyse a short program for this controller once, after what it was asked
   * before (the page asks after an analysis is shown): the first analysis of a long paste then
   * runs compiled code (worker.js). A new worker is warmed again. */
  warm(request) {
    if (this.warmed.has(request.controller)) return;
    this.warmed.add(request.controller);
    this.call('warm', request);
  }

  /** Stops an analysis that a newer one replaces: a new worker, the other calls sent again. */
  restart() {
    const waiting = this.waiting;
    this.worker.terminate();
    this.spawn();
    for (const w of waiting.values()) {
      // A warm-up is not sent again ahead of the analysis that replaces the stopped one.
      if (w.fn === 'plan' || w.fn === 'analyse' || w.fn === 'warm') w.resolve(null);
      else this.call(w.fn, w.text).then(w.resolve);
    }
  }
}

const engine = new Engine();

let controllers = [];
let mode = 'plan';
let values = {};
let lastGcode = '';
// The expanded program's lines in all, and the request that gives it whole when the analysis
// gave only its first lines (a long paste: `expand` on demand, for Copy and Download).
let lastGcodeTotal = 0;
let lastExpand = null;
let lastPlanned = '';
let lastConverted = '';
// The analysis being run (a number; 0: none) and the time of the edit it answers.
let running = 0;
let requested = 0;
let editedAt = 0;

function esc(s) {
  return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]));
}

function current() {
  return controllers.find((c) => c.name === $('controller').value);
}

// ---- the cycle form: the program's lines with an input for every word the user may edit ----

function renderForm() {
  const c = current();
  const form = $('form');
  form.innerHTML = '';
  if (!c.form) {
    $('cycle-name').textContent = '';
    form.innerHTML = '<p class="muted">No cycle form for this controller yet: paste a program in “Analyse a program”.</p>';
    return;
  }
  $('cycle-name').textContent = c.form.cycle;
  for (const line of c.form.lines) {
    const div = document.createElement('div');
    div.className = 'line';
    for (const piece of line) {
      if (piece.text !== undefined) {
        div.append(piece.text);
        continue;
      }
      const f = piece.field;
      const span = document.createElement('span');
      span.className = 'word' + (f.optional ? ' optional' : '');
      if (f.letter) span.append(f.letter);
      const input = document.createElement('input');
      input.dataset.field = f.id;
      input.title = f.label;
      input.value = values[f.id] ?? '';
      input.spellcheck = false;
      input.setAttribute('aria-label', f.label);
      size(input, f);
      input.addEventListener('input', () => {
        values[f.id] = input.value;
        size(input, f);
        schedule(plan);
      });
      span.append(input);
      div.append(span);
    }
    form.append(div);
  }
  // What each word means, next to the form (the inputs carry the same text as their tooltip).
  const legend = document.createElement('ul');
  legend.id = 'legend';
  for (const line of c.form.lines) {
    for (const piece of line) {
      if (!piece.field) continue;
      const li = document.createElement('li');
      li.dataset.legend = piece.field.id;
      li.textContent = piece.field.label;
      legend.append(li);
    }
  }
  form.append(legend);
}

function size(input, f) {
  input.style.width = `calc(${Math.max(f.kind === 'digits2' ? 2 : 3, input.value.length)}ch + 0.6rem)`;
}

async function fill() {
  const c = current();
  if (!c.form) return;
  const name = $('thread').value;
  const r = await engine.call('fill', { controller: c.name, thread: name, internal: $('internal').checked });
  if (!r.ok) {
    unknownThread(name, r);
    return;
  }
  values = r.values;
  await describeThread(r.thread);
  renderForm();
  plan();
}

/** A thread name the standards do not have: the old plan goes, and the page says why. */
function unknownThread(name, r) {
  // An analysis still running for the old plan must not bring it back.
  requested++;
  running = 0;
  status('');
  values = {};
  lastPlanned = '';
  $('form').innerHTML = '';
  $('cycle-name').textContent = '';
  const near = (r.hint || '').replace(/^nearest known threads: /, '');
  $('thread-info').innerHTML = `<span class="error">No plan: “${esc(name.trim())}” is not a standard thread this planner knows (${esc(r.error.replace(/: `[^`]*`$/, ''))}).</span>` +
    (near ? ` <span class="muted">Nearest: ${esc(near)}. The Thread field’s list shows every thread it knows.</span>` : '');
  show({
    ok: false,
    error: `No standard thread “${name.trim()}”: pick one from the Thread field’s list${near ? ` (nearest: ${near})` : ''}.`,
    program: '',
    cycles: [],
    diagnostics: [],
  });
}

/** A number with at most `d` decimals, no trailing zeros. */
function fmt(v, d) {
  return String(Math.round(v * 10 ** d) / 10 ** d);
}

async function describeThread(name) {
  const t = await engine.call('thread', name);
  if (!t.ok) return;
  const th = t.thread;
  const side = $('internal').checked ? t.internal : t.external;
  const height = $('internal').checked ? th.internal_depth : th.external_depth;
  // Inch threads in inches and threads per inch, as their standards give them; metric in mm.
  const inch = th.tpi != null;
  const len = inch ? (mm) => `${fmt(mm / 25.4, 4)} in` : (mm) => `${fmt(mm, 3)} mm`;
  const pitch = inch ? `${fmt(th.tpi, 3)} TPI (pitch ${fmt(th.pitch / 25.4, 5)} in)` : `pitch ${fmt(th.pitch, 3)} mm`;
  const taper = th.taper
    ? ` Taper 1:16: diameters at the gauge plane, ${len(th.taper.gauge_length)} from the small end; ` +
      'a cycle with a taper word (Allen-Bradley’s I) cuts the taper, the others cut it parallel.'
    : '';
  $('thread-info').textContent =
    `${th.name}: ${th.profile.angle_deg}° form, ${pitch}, major ${len(th.basic.major)}, minor ${len(th.basic.minor)}, ` +
    `thread height ${len(height)} (${side.class}).` + taper + wiresText(t.wires, len) + gaugesText(t, len);
}

/** The three-wire measurement of the external thread (the library's `wires`, mm). */
function wiresText(w, len) {
  if (!w) return '';
  const m = (o) => len(o.corrected);
  const lim = w.limits ? `; ${w.class} allows M ${m(w.limits[0])}–${m(w.limits[1])}` : '';
  return ` Three wires: best wire ${len(w.best)} (${len(w.min)}–${len(w.max)} touch the flanks), ` +
    `M over it ${m(w.basic)} at the basic pitch diameter${lim} (with the lead angle, NBS H28).`;
}

/** The GO / NOT GO gauges of the side shown (ISO 1502 / ASME B1.2 arrangement, at the limits). */
function gaugesText(t, len) {
  const g = t.gauges && ($('internal').checked ? t.gauges.internal : t.gauges.external);
  if (!g || !g.length) return '';
  const each = g.map((p) => `${p.gauge} (${p.diameter}) GO ${len(p.go)}, NOT GO ${len(p.not_go)}`);
  return ` Gauges: ${each.join('; ')} (gauge tolerances not applied).`;
}

function plan() {
  const c = current();
  if (!c.form) return;
  run('plan', { controller: c.name, values }, (r) => { lastPlanned = r.program || ''; });
}

/**
 * The Convert tab's named tools, `THREAD_EXT_60=T0101, GROOVE=T0202`, as the request's `tools`
 * object (`threadcut convert --tool`); an entry without `=` is passed with an empty number, so
 * that the library's message names it.
 */
function namedTools(text) {
  const tools = {};
  for (const entry of text.split(',')) {
    if (!entry.trim()) continue;
    const at = entry.indexOf('=');
    const name = (at < 0 ? entry : entry.slice(0, at)).trim();
    tools[name] = at < 0 ? '' : entry.slice(at + 1).trim();
  }
  return tools;
}

/**
 * Converts the Convert tab's program for the target with the library's conversion, then analyses
 * the converted program on the target (the right-hand side shows that analysis).
 */
async function convert() {
  const from = current().name;
  const to = $('target').value;
  const id = ++requested;
  if (running) engine.restart();
  running = 0;
  status('converting…');
  const r = await engine.call('convert', { from, to, program: $('convert-source').value, tools: namedTools($('convert-tools').value) });
  if (id !== requested) return;
  showConversion(r);
  if (r.ok) {
    run('analyse', { controller: to, program: r.program, ...shownOnly() });
  } else {
    show({ ok: false, program: $('convert-source').value, cycles: [], diagnostics: r.diagnostics || [], error: r.diagnostics ? undefined : r.error });
    status('');
  }
}

function showConversion(r) {
  const list = $('convert-status');
  list.innerHTML = '';
  document.body.dataset.converted = String(Number(document.body.dataset.converted || '0') + 1);
  lastConverted = r.ok ? r.program : '';
  $('copy-converted').disabled = $('download-converted').disabled = !r.ok;
  if (!r.ok) {
    for (const d of r.diagnostics || [{ message: r.error, line: 0 }]) {
      const where = d.line ? `line ${d.line}, column ${d.column}: ` : '';
      list.insertAdjacentHTML('beforeend', `<li class="error"><b>not converted</b> ${esc(where)}${esc(d.message)}` +
        (d.hint ? `<div class="hint">hint: ${esc(d.hint)}</div>` : '') + '</li>');
    }
    $('converted').textContent = '(no output: the program cannot be converted)';
    return;
  }
  const cycles = r.native + r.plain.length;
  list.insertAdjacentHTML('beforeend', `<li class="ok">Converted from ${esc(r.from)} to ${esc(r.to)}: ` +
    (cycles ? `${r.native} of ${cycles} threading cycle${cycles === 1 ? '' : 's'} as ${esc(r.to)}’s own cycle.` : 'no threading cycle.') + '</li>');
  for (const p of r.plain) {
    list.insertAdjacentHTML('beforeend', `<li class="plain">line ${p.line}: plain moves, not the native cycle: ${esc(p.reason)}</li>`);
  }
  $('converted').textContent = head(r.program, SHOWN_LINES, 'Copy and Download give the whole program');
}

/** The stock the form gives (`check --stock-*`): a number for each field filled in. */
function stock() {
  const out = {};
  for (const [id, key] of [['stock-diameter', 'stock_diameter'], ['stock-start', 'stock_start'],
    ['stock-length', 'stock_length'], ['stock-bore', 'stock_bore']]) {
    const v = $(id).value.trim();
    if (v !== '' && Number.isFinite(Number(v))) out[key] = Number(v);
  }
  return out;
}

/** What an analysis gives the page: no motion list and no blanks (the page shows neither), the
 * first pass tables, lines and rows. */
function shownOnly() {
  return { motions: false, blanks: false, max_cycles: SHOWN_CYCLES, gcode_lines: SHOWN_LINES, max_passes: SHOWN_PASSES };
}

function analyse() {
  run('analyse', { controller: current().name, program: $('source').value, ...shownOnly(), ...stock() });
}

/** Runs an analysis in the worker and shows it, unless a newer one has been asked for since. */
async function run(fn, request, then) {
  const id = ++requested;
  if (running) engine.restart();
  running = id;
  const asked = editedAt || performance.now();
  status('analysing…');
  const r = await engine.call(fn, request);
  if (r === null || id !== requested) return;
  running = 0;
  if (then) then(r);
  const shown = performance.now();
  lastExpand = fn === 'analyse' ? { controller: request.controller, program: request.program, start: request.start } : null;
  show(r);
  performance.mark('threadcut:shown');
  if (request.controller) engine.warm({ controller: request.controller, ...shownOnly() });
  const ms = performance.now() - asked;
  document.body.dataset.engineMs = String(Math.round(engine.lastMs));
  document.body.dataset.showMs = String(Math.round(performance.now() - shown));
  const lines = r.lines ? `${r.lines.toLocaleString('en')} lines ` : '';
  status(`analysed ${lines}in ${Math.round(ms)} ms`);
  document.body.dataset.analysedMs = String(Math.round(ms));
  // The length of the program this analysis read (a test waits for the one it typed).
  document.body.dataset.analysedLength = String((request.program || '').length);
}

/** The number of lines of `text` (a last line without its end counts). */
function lineCount(text) {
  return text ? text.split('\n').length - (text.endsWith('\n') ? 1 : 0) : 0;
}

/** Whether the analysis gave only the expanded program's first lines. */
function gcodePartial() {
  return lastGcodeTotal > lineCount(lastGcode);
}

/** The whole expanded program: the analysis's, or from the engine when it gave only the first lines. */
async function wholeGcode() {
  if (!gcodePartial() || !lastExpand) return lastGcode;
  const r = await engine.call('expand', lastExpand);
  if (!r || !r.ok) throw new Error(r ? r.error : 'the expansion was replaced');
  return r.gcode;
}

function status(text) {
  $('status').textContent = text;
}

let timer = null;
/** Runs `f` once typing has paused for PAUSE_MS. */
function schedule(f) {
  editedAt = performance.now();
  performance.mark('threadcut:edit');
  clearTimeout(timer);
  timer = setTimeout(f, PAUSE_MS);
}

// ---- results ----

let shownCount = 0;

function show(r) {
  document.body.dataset.state = r.ok ? 'ok' : 'error';
  document.body.dataset.analysed = String(++shownCount);
  const diags = r.diagnostics || [];
  if (r.error) diags.unshift({ severity: 'error', code: null, message: r.error, line: 0, column: 0, len: 0 });

  // Diagnostics, and the field each points into.
  for (const el of document.querySelectorAll('#form input, #legend li')) {
    el.classList.remove('bad', 'warn');
    el.removeAttribute('aria-invalid');
  }
  const list = $('diagnostics');
  list.innerHTML = '';
  if (diags.length === 0) list.innerHTML = '<li class="ok">No errors or warnings.</li>';
  for (const d of diags.slice(0, SHOWN_FINDINGS)) {
    const li = document.createElement('li');
    li.className = d.severity;
    const where = d.line ? `line ${d.line}, column ${d.column}` : '';
    li.innerHTML = `<b>${esc(d.severity)}${d.code ? `[${esc(d.code)}]` : ''}</b> ${where ? `<span class="muted">${where}</span> ` : ''}` +
      esc(d.message) + (d.hint ? `<div class="hint">hint: ${esc(d.hint)}</div>` : '');
    if (d.field) {
      const input = document.querySelector(`#form input[data-field="${d.field}"]`);
      if (input) {
        input.classList.add(d.severity === 'error' ? 'bad' : 'warn');
        input.setAttribute('aria-invalid', 'true');
        const entry = document.querySelector(`#legend li[data-legend="${d.field}"]`);
        if (entry) entry.classList.add(d.severity === 'error' ? 'bad' : 'warn');
        li.querySelector('b').insertAdjacentHTML('afterend', ` <span class="field">${esc(input.getAttribute('aria-label').split(':')[0])}</span>`);
      }
    }
    list.append(li);
  }
  if (diags.length > SHOWN_FINDINGS) {
    list.insertAdjacentHTML('beforeend', `<li class="more">… ${(diags.length - SHOWN_FINDINGS).toLocaleString('en')} more findings (the first ${SHOWN_FINDINGS} are listed and marked)</li>`);
  }

  // What the check assumed (the blank, the tool), as `threadcut check` states it.
  const notes = $('notes');
  notes.innerHTML = '';
  for (const n of r.notes || []) {
    const li = document.createElement('li');
    li.innerHTML = `${n.line ? `<span class="muted">line ${n.line}</span> ` : ''}${esc(n.message)}`;
    notes.append(li);
  }

  // The program with each diagnostic's span marked.
  $('listing').innerHTML = listing(r.program || '', diags.slice(0, SHOWN_FINDINGS));

  // Pass tables.
  const passes = $('passes');
  passes.innerHTML = '';
  for (const cycle of r.cycles || []) {
    const units = cycle.units === 'inch' ? 'in' : 'mm';
    const d = units === 'in' ? 4 : 3;
    const n = (v) => v.toFixed(d);
    const rows = cycle.passes.map((p) =>
      `<tr class="${p.kind}"><td>${p.n}</td><td>${p.kind}</td><td>${n(p.depth)}</td><td>${n(p.increment)}</td>` +
      `<td>${n(p.x)}</td><td>${p.z === null ? '?' : n(p.z)}</td><td>${p.area.toFixed(d + 2)}</td><td>${(p.share * 100).toFixed(1)}%</td>` +
      (p.sim_area !== undefined ? `<td>${p.cutting_flank}</td>` : '') + '</tr>').join('');
    const flank = cycle.passes.length && cycle.passes[0].sim_area !== undefined ? '<th>cutting flank</th>' : '';
    const total = cycle.passes_total ?? cycle.passes.length;
    const what = cycle.source === 'moves'
      ? `${total.toLocaleString('en')} synchronised passes as one thread`
      : `${esc(cycle.controller)} cycle, ${total.toLocaleString('en')} passes`;
    const rest = total > cycle.passes.length
      ? `<p class="muted">… ${(total - cycle.passes.length).toLocaleString('en')} more passes: the first ${cycle.passes.length.toLocaleString('en')} are listed.</p>` : '';
    const from = cycle.depth_from === 'first_pass' ? '; depths from the first pass: the crest is not known' : '';
    passes.insertAdjacentHTML('beforeend',
      `<p>Line ${cycle.line}: ${what} (${units}; depth radial, X as programmed${from})</p>` +
      (cycle.start_unknown ? `<p class="muted">Note: ${esc(cycle.start_unknown.note)}</p>` : '') +
      `<table><thead><tr><th>pass</th><th>kind</th><th>depth</th><th>increment</th><th>x</th><th>z</th><th>area (${units}²)</th><th>share</th>${flank}</tr></thead>` +
      `<tbody>${rows}</tbody></table>${rest}`);
  }
  if (!(r.cycles || []).length) passes.innerHTML = '<p class="muted">No thread: no threading cycle and no synchronised move.</p>';
  else if (r.cycles_total > r.cycles.length) {
    passes.insertAdjacentHTML('beforeend', `<p class="muted">… ${(r.cycles_total - r.cycles.length).toLocaleString('en')} more threads: the pass tables of the first ${r.cycles.length} are shown.</p>`);
  }

  // Plots (the library's own SVG).
  $('plot').innerHTML = r.svg || `<p class="muted">No plot${r.plot_error ? ': ' + esc(r.plot_error) : ''}.</p>`;

  // Expanded G-code.
  lastGcode = r.gcode || '';
  const given = lineCount(lastGcode);
  lastGcodeTotal = r.gcode_total ?? given;
  const rest = 'Copy and Download give the whole program';
  $('gcode').textContent = !lastGcode ? '(no output: the program has errors)'
    : lastGcodeTotal > given ? `${lastGcode}… ${(lastGcodeTotal - given).toLocaleString('en')} more lines (${rest})\n`
      : head(lastGcode, SHOWN_LINES, rest);
  $('copy').disabled = $('download').disabled = !lastGcode;
}

// A long program is shown in part: the page would spend seconds laying out 30,000 lines. The
// listing shows its first SHOWN_LINES lines and every line with a finding (with a line around it).
const SHOWN_LINES = 1000;
// At most this many findings are listed and marked, and this many threads get a pass table.
const SHOWN_FINDINGS = 200;
const SHOWN_CYCLES = 20;
// And each pass table lists at most this many passes (a thread written as thousands of moves).
const SHOWN_PASSES = 500;

/** The first `n` lines of `text`, and a line saying how many more there are. */
function head(text, n, rest) {
  let end = 0;
  for (let i = 0; i < n; i++) {
    end = text.indexOf('\n', end) + 1;
    if (end === 0) return text;
  }
  if (end >= text.length) return text;
  let more = 0;
  for (let i = end; i < text.length; i++) if (text.charCodeAt(i) === 10) more++;
  if (!text.endsWith('\n')) more++;
  return `${text.slice(0, end)}… ${more.toLocaleString('en')} more lines (${rest})\n`;
}

function listing(text, diags) {
  const lines = text.split('\n');
  if (lines.length && lines[lines.length - 1] === '') lines.pop();
  const width = String(lines.length).length;
  const marked = new Map();
  for (const d of diags) {
    if (!d.line) continue;
    if (!marked.has(d.line)) marked.set(d.line, []);
    marked.get(d.line).push(d);
  }
  // The lines shown: the first SHOWN_LINES, and each marked line with one line either side.
  const shown = new Set();
  for (let i = 1; i <= Math.min(lines.length, SHOWN_LINES); i++) shown.add(i);
  for (const l of marked.keys()) for (const k of [l - 1, l, l + 1]) if (k >= 1 && k <= lines.length) shown.add(k);
  const numbers = [...shown].sort((a, b) => a - b);
  const out = [];
  let last = 0;
  for (const n of numbers) {
    if (n > last + 1) out.push(`<span class="gap">${' '.repeat(width)} … ${(n - last - 1).toLocaleString('en')} lines</span>`);
    out.push(listed(lines[n - 1], n, width, marked.get(n) || []));
    last = n;
  }
  if (last < lines.length) out.push(`<span class="gap">${' '.repeat(width)} … ${(lines.length - last).toLocaleString('en')} more lines</span>`);
  return out.join('\n');
}

/** One line of the listing, with the span of its first finding that has a column marked. */
function listed(line, number, width, marks) {
  let html;
  const d = marks.find((m) => m.column > 0);
  if (d) {
    // Columns count bytes; programs are ASCII in practice, and a UTF-8 line is mapped by bytes.
    const bytes = new TextEncoder().encode(line);
    const dec = new TextDecoder();
    const a = Math.min(d.column - 1, bytes.length);
    const b = Math.min(a + Math.max(d.len, 1), bytes.length);
    html = esc(dec.decode(bytes.slice(0, a))) +
      `<mark class="${d.severity === 'error' ? 'err' : 'warn'}" title="${esc(d.message)}">${esc(dec.decode(bytes.slice(a, b))) || ' '}</mark>` +
      esc(dec.decode(bytes.slice(b)));
  } else {
    html = esc(line);
  }
  const cls = marks.length ? ` class="${marks.some((m) => m.severity === 'error') ? 'err' : 'warn'}"` : '';
  return `<span${cls}><span class="ln">${String(number).padStart(width)}</span> ${html}</span>`;
}

// ---- wiring ----

function setMode(m) {
  mode = m;
  for (const [tab, pane, name] of [['tab-plan', 'plan-pane', 'plan'], ['tab-paste', 'paste-pane', 'paste'], ['tab-convert', 'convert-pane', 'convert']]) {
    $(tab).classList.toggle('active', m === name);
    $(tab).setAttribute('aria-selected', m === name);
    $(pane).hidden = m !== name;
  }
  if (m === 'plan') plan();
  else if (m === 'paste') {
    // Start from the planned program, so that it can be edited as a whole.
    if (!$('source').value.trim()) $('source').value = lastPlanned;
    analyse();
  } else {
    // Start from the program last analysed or planned.
    if (!$('convert-source').value.trim()) $('convert-source').value = $('source').value.trim() ? $('source').value : lastPlanned;
    convert();
  }
}

async function controllerChanged() {
  const c = current();
  $('controller-info').textContent = `${c.description} (${c.units}, X on ${c.diameter_x ? 'diameter' : 'radius'} at power-on)`;
  if (mode === 'plan') {
    values = {};
    renderForm();
    await fill();
    if (!c.form) show({ ok: true, program: '', cycles: [], diagnostics: [] });
  } else if (mode === 'paste') analyse();
  else convert();
}

async function main() {
  const r = await engine.call('controllers');
  if (!r.ok) throw new Error(r.error);
  controllers = r.controllers;
  for (const c of controllers) {
    const o = document.createElement('option');
    o.value = c.name;
    o.textContent = c.name + (c.form ? ` — ${c.form.cycle}` : '');
    $('controller').append(o);
  }
  for (const c of controllers) {
    const o = document.createElement('option');
    o.value = c.name;
    o.textContent = c.name;
    $('target').append(o);
  }
  $('target').value = 'linuxcnc';
  for (const name of r.threads || []) {
    const o = document.createElement('option');
    o.value = name;
    $('threads').append(o);
  }
  $('controller').value = 'gsk980';
  $('controller').addEventListener('change', controllerChanged);
  $('fill').addEventListener('click', fill);
  $('thread').addEventListener('change', fill);
  $('thread').addEventListener('keydown', (e) => { if (e.key === 'Enter') fill(); });
  $('internal').addEventListener('change', fill);
  $('tab-plan').addEventListener('click', () => setMode('plan'));
  $('tab-paste').addEventListener('click', () => setMode('paste'));
  $('tab-convert').addEventListener('click', () => setMode('convert'));
  $('convert').addEventListener('click', () => { editedAt = 0; convert(); });
  $('target').addEventListener('change', () => { editedAt = 0; convert(); });
  $('convert-source').addEventListener('input', () => schedule(convert));
  $('convert-tools').addEventListener('input', () => schedule(convert));
  $('copy-converted').addEventListener('click', async () => {
    try {
      await navigator.clipboard.writeText(lastConverted);
      $('copied-converted').textContent = 'copied';
    } catch {
      window.getSelection().selectAllChildren($('converted'));
      $('copied-converted').textContent = 'selected: press Ctrl+C';
    }
    setTimeout(() => { $('copied-converted').textContent = ''; }, 2000);
  });
  $('download-converted').addEventListener('click', () => {
    const blob = new Blob([lastConverted], { type: 'text/plain' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `threadcut-${current().name}-to-${$('target').value}.nc`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 0);
  });
  $('analyse').addEventListener('click', () => { editedAt = 0; analyse(); });
  $('source').addEventListener('input', () => schedule(analyse));
  for (const input of document.querySelectorAll('input.stock')) input.addEventListener('input', () => schedule(analyse));
  $('copy').addEventListener('click', async () => {
    const partial = gcodePartial();
    try {
      if (partial && typeof ClipboardItem !== 'undefined') {
        // The whole program comes from the engine: the clipboard takes the promise within the
        // click, so a browser that allows a write only there still takes it.
        const text = wholeGcode().then((t) => new Blob([t], { type: 'text/plain' }));
        await navigator.clipboard.write([new ClipboardItem({ 'text/plain': text })]);
      } else {
        await navigator.clipboard.writeText(await wholeGcode());
      }
      $('copied').textContent = 'copied';
    } catch (e) {
      if (partial) {
        // Never offer the lines shown as the whole program.
        $('copied').textContent = `not copied (${e.message || e}): Download gives the whole program`;
      } else {
        // Clipboard refused (no permission): select the text for a manual copy.
        const sel = window.getSelection();
        sel.selectAllChildren($('gcode'));
        $('copied').textContent = 'selected: press Ctrl+C';
      }
    }
    setTimeout(() => { $('copied').textContent = ''; }, 4000);
  });
  $('download').addEventListener('click', async () => {
    let text;
    try {
      text = await wholeGcode();
    } catch (e) {
      $('copied').textContent = `not downloaded: ${e.message || e}`;
      setTimeout(() => { $('copied').textContent = ''; }, 4000);
      return;
    }
    const blob = new Blob([text], { type: 'text/plain' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `threadcut-${current().name}.nc`;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 0);
  });
  await controllerChanged();
  document.body.dataset.ready = 'true';
}

main().catch((e) => {
  document.body.dataset.ready = 'failed';
  $('diagnostics').innerHTML = `<li class="error">The threadcut module did not load: ${esc(e)}. Build it with web/build.sh and serve this folder over http.</li>`;
});
