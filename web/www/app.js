// threadcut thread planner: the page around the wasm module. No framework, no network: every
// result comes from the threadcut library compiled to WebAssembly (pkg/, built by web/build.sh).
import init, * as tc from './pkg/threadcut_web.js';

const $ = (id) => document.getElementById(id);
const call = (f, arg) => JSON.parse(arg === undefined ? f() : f(typeof arg === 'string' ? arg : JSON.stringify(arg)));

let controllers = [];
let mode = 'plan';
let values = {};
let lastGcode = '';
let lastPlanned = '';

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

function fill() {
  const c = current();
  if (!c.form) return;
  const r = call(tc.fill, { controller: c.name, thread: $('thread').value, internal: $('internal').checked });
  if (!r.ok) {
    $('thread-info').innerHTML = `<span class="error">${esc(r.error)}</span>` + (r.hint ? ` <span class="muted">${esc(r.hint)}</span>` : '');
    return;
  }
  values = r.values;
  describeThread(r.thread);
  renderForm();
  plan();
}

function describeThread(name) {
  const t = call(tc.thread, name);
  if (!t.ok) return;
  const th = t.thread;
  const mm = (v) => (Math.round(v * 1000) / 1000).toString();
  const side = $('internal').checked ? t.internal : t.external;
  const taper = th.taper
    ? ` Taper 1:16: diameters at the gauge plane, ${mm(th.taper.gauge_length)} mm from the small end; ` +
      'a form without a taper word cuts it parallel (threadcut thread NAME --controller C gives the word).'
    : '';
  $('thread-info').textContent =
    `${th.name}: ${th.profile.angle_deg}° form, pitch ${mm(th.pitch)} mm, major ${mm(th.basic.major)} mm, minor ${mm(th.basic.minor)} mm, ` +
    `thread height ${mm($('internal').checked ? th.internal_depth : th.external_depth)} mm (${side.class}).` + taper;
}

function plan() {
  const c = current();
  if (!c.form) return;
  const r = call(tc.plan, { controller: c.name, values });
  lastPlanned = r.program || '';
  show(r);
}

function analyse() {
  show(call(tc.analyse, { controller: current().name, program: $('source').value }));
}

let timer = null;
function schedule(f) {
  clearTimeout(timer);
  timer = setTimeout(f, 120);
}

// ---- results ----

function show(r) {
  document.body.dataset.state = r.ok ? 'ok' : 'error';
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
  for (const d of diags) {
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

  // What the check assumed (the blank, the tool), as `threadcut check` states it.
  const notes = $('notes');
  notes.innerHTML = '';
  for (const n of r.notes || []) {
    const li = document.createElement('li');
    li.innerHTML = `${n.line ? `<span class="muted">line ${n.line}</span> ` : ''}${esc(n.message)}`;
    notes.append(li);
  }

  // The program with each diagnostic's span marked.
  $('listing').innerHTML = listing(r.program || '', diags);

  // Pass tables.
  const passes = $('passes');
  passes.innerHTML = '';
  for (const cycle of r.cycles || []) {
    const units = cycle.units === 'inch' ? 'in' : 'mm';
    const d = units === 'in' ? 4 : 3;
    const n = (v) => v.toFixed(d);
    const rows = cycle.passes.map((p) =>
      `<tr class="${p.kind}"><td>${p.n}</td><td>${p.kind}</td><td>${n(p.depth)}</td><td>${n(p.increment)}</td>` +
      `<td>${n(p.x)}</td><td>${n(p.z)}</td><td>${p.area.toFixed(d + 2)}</td><td>${(p.share * 100).toFixed(1)}%</td>` +
      (p.sim_area !== undefined ? `<td>${p.cutting_flank}</td>` : '') + '</tr>').join('');
    const flank = cycle.passes.length && cycle.passes[0].sim_area !== undefined ? '<th>cutting flank</th>' : '';
    const what = cycle.source === 'moves'
      ? `${cycle.passes.length} synchronised passes as one thread`
      : `${esc(cycle.controller)} cycle, ${cycle.passes.length} passes`;
    const from = cycle.depth_from === 'first_pass' ? '; depths from the first pass: the crest is not known' : '';
    passes.insertAdjacentHTML('beforeend',
      `<p>Line ${cycle.line}: ${what} (${units}; depth radial, X as programmed${from})</p>` +
      `<table><thead><tr><th>pass</th><th>kind</th><th>depth</th><th>increment</th><th>x</th><th>z</th><th>area (${units}²)</th><th>share</th>${flank}</tr></thead>` +
      `<tbody>${rows}</tbody></table>`);
  }
  if (!(r.cycles || []).length) passes.innerHTML = '<p class="muted">No thread: no threading cycle and no synchronised move.</p>';

  // Plots (the library's own SVG).
  $('plot').innerHTML = r.svg || `<p class="muted">No plot${r.plot_error ? ': ' + esc(r.plot_error) : ''}.</p>`;

  // Expanded G-code.
  lastGcode = r.gcode || '';
  $('gcode').textContent = lastGcode || '(no output: the program has errors)';
  $('copy').disabled = $('download').disabled = !lastGcode;
}

function listing(text, diags) {
  const lines = text.split('\n');
  if (lines.length && lines[lines.length - 1] === '') lines.pop();
  const width = String(lines.length).length;
  return lines.map((line, i) => {
    const marks = diags.filter((d) => d.line === i + 1);
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
    return `<span${cls}><span class="ln">${String(i + 1).padStart(width)}</span> ${html}</span>`;
  }).join('\n');
}

// ---- wiring ----

function setMode(m) {
  mode = m;
  $('tab-plan').classList.toggle('active', m === 'plan');
  $('tab-paste').classList.toggle('active', m === 'paste');
  $('tab-plan').setAttribute('aria-selected', m === 'plan');
  $('tab-paste').setAttribute('aria-selected', m === 'paste');
  $('plan-pane').hidden = m !== 'plan';
  $('paste-pane').hidden = m !== 'paste';
  if (m === 'plan') plan();
  else {
    // Start from the planned program, so that it can be edited as a whole.
    if (!$('source').value.trim()) $('source').value = lastPlanned;
    analyse();
  }
}

function controllerChanged() {
  const c = current();
  $('controller-info').textContent = `${c.description} (${c.units}, X on ${c.diameter_x ? 'diameter' : 'radius'} at power-on)`;
  if (mode === 'plan') {
    values = {};
    renderForm();
    fill();
    if (!c.form) show({ ok: true, program: '', cycles: [], diagnostics: [] });
  } else analyse();
}

async function main() {
  await init();
  const r = call(tc.controllers);
  controllers = r.controllers;
  for (const c of controllers) {
    const o = document.createElement('option');
    o.value = c.name;
    o.textContent = c.name + (c.form ? ` — ${c.form.cycle}` : '');
    $('controller').append(o);
  }
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
  $('analyse').addEventListener('click', analyse);
  $('source').addEventListener('input', () => schedule(analyse));
  $('copy').addEventListener('click', async () => {
    try {
      await navigator.clipboard.writeText(lastGcode);
      $('copied').textContent = 'copied';
    } catch {
      // Clipboard refused (no permission): select the text for a manual copy.
      const sel = window.getSelection();
      sel.selectAllChildren($('gcode'));
      $('copied').textContent = 'selected: press Ctrl+C';
    }
    setTimeout(() => { $('copied').textContent = ''; }, 2000);
  });
  $('download').addEventListener('click', () => {
    const blob = new Blob([lastGcode], { type: 'text/plain' });
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = `threadcut-${current().name}.nc`;
    a.click();
    URL.revokeObjectURL(a.href);
  });
  controllerChanged();
  document.body.dataset.ready = 'true';
}

main().catch((e) => {
  document.body.dataset.ready = 'failed';
  $('diagnostics').innerHTML = `<li class="error">The threadcut module did not load: ${esc(e)}. Build it with web/build.sh and serve this folder over http.</li>`;
});
