// End-to-end test of the thread planner page: serves web/www on 127.0.0.1, drives it in headless
// Debian Chromium (playwright-core, no downloaded browser), plans an M20x2.5 thread on GSK G78,
// copies and downloads its program, edits a word into an alarm, pastes a bad program, plans an
// inch thread, asks for a thread that does not exist, pastes a 30,000-line program and times its
// analysis (docs/performance.md), and saves screenshots next to this file.
//
//   web/build.sh && (cd web/e2e && npm ci && node test.mjs)
//
// CHROMIUM=/path/to/chromium overrides /usr/bin/chromium.
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { readFileSync } from 'node:fs';
import { existsSync } from 'node:fs';
import { join, extname, normalize, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', 'www');
if (!existsSync(join(root, 'pkg', 'threadcut_web_bg.wasm'))) {
  console.error('web/www/pkg/ is missing: run web/build.sh first');
  process.exit(1);
}

// A static file server on 127.0.0.1 (the page needs no network beyond its own files).
const types = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm' };
const server = createServer(async (req, res) => {
  const path = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname)).replace(/^(\.\.[/\\])+/, '');
  const file = join(root, path.endsWith('/') ? path + 'index.html' : path);
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': types[extname(file)] || 'application/octet-stream' });
    res.end(body);
  } catch {
    res.writeHead(404);
    res.end('not found');
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const url = `http://127.0.0.1:${server.address().port}/`;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
    '--disable-component-update', '--disable-sync'],
});
const problems = [];
let failed = false;
try {
  const context = await browser.newContext({ viewport: { width: 1400, height: 1000 }, acceptDownloads: true });
  await context.grantPermissions(['clipboard-read', 'clipboard-write'], { origin: url });
  const page = await context.newPage();
  // Runs `action` and waits until the page has shown the analysis it started.
  const analysed = async (action) => {
    const before = await page.evaluate(() => document.body.dataset.analysed || '0');
    await action();
    await page.waitForFunction((b) => (document.body.dataset.analysed || '0') !== b, before, { timeout: 20000 });
  };
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  // No request may leave 127.0.0.1.
  page.on('request', (r) => { if (!r.url().startsWith(url) && !r.url().startsWith('blob:')) problems.push(`network: ${r.url()}`); });

  await page.goto(url);
  await page.waitForSelector('body[data-ready="true"]', { timeout: 20000 });

  // 1. Plan M20x2.5 external on GSK G78.
  await page.selectOption('#controller', 'gsk980');
  await page.fill('#thread', 'M20x2.5');
  await analysed(() => page.click('#fill'));
  await page.waitForSelector('#passes tbody tr');
  const rows = await page.$$eval('#passes tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
  // Hand-computed in web/tests/api.rs: ten rough passes (first 0.470 deep, X 19.060) and two
  // finishing passes at the 1.534 thread height.
  assert.equal(rows.length, 12, `pass rows: ${JSON.stringify(rows)}`);
  assert.deepEqual(rows[0].slice(0, 5), ['1', 'rough', '0.470', '0.470', '19.060']);
  assert.deepEqual(rows[11].slice(0, 3), ['12', 'finish', '1.534']);
  assert.equal(await page.inputValue('#form input[data-field="x"]'), '16.932');
  const gcode = await page.textContent('#gcode');
  assert.equal((gcode.match(/G32/g) || []).length, 12, gcode);
  assert.ok(!gcode.includes('G78'), 'the expanded program has no G78 left');
  const plot = await page.$eval('#plot', (el) => {
    const svg = el.querySelector('svg');
    if (!svg) return null;
    const box = svg.getBoundingClientRect();
    return { shapes: svg.querySelectorAll('path, polyline, polygon, line, rect').length, w: box.width, h: box.height };
  });
  assert.ok(plot, 'the plot is an SVG');
  assert.ok(plot.shapes > 10 && plot.w > 100 && plot.h > 100, `plot: ${JSON.stringify(plot)}`);
  assert.match(await page.textContent('#diagnostics'), /No errors or warnings/);
  await page.screenshot({ path: join(here, 'screenshot.png'), fullPage: true });

  // Copy puts the whole expanded program on the clipboard; Download saves the same bytes.
  await page.click('#copy');
  await page.waitForFunction(() => document.getElementById('copied').textContent === 'copied');
  assert.equal(await page.evaluate(() => navigator.clipboard.readText()), gcode);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download')]);
  assert.equal(download.suggestedFilename(), 'threadcut-gsk980.nc');
  assert.equal(readFileSync(await download.path(), 'utf8'), gcode);

  // 2. A live edit: the infeed mode digit r = 5 is out of range; that field is highlighted.
  await page.fill('#form input[data-field="r"]', '5');
  await page.waitForSelector('#form input[data-field="r"].bad');
  assert.match(await page.textContent('#diagnostics li.error'), /E004.*P\(r\)=05/s);
  assert.equal(await page.$$eval('#form input.bad', (els) => els.length), 1);
  assert.equal(await page.$$eval('#passes tbody tr', (trs) => trs.length), 0);
  assert.match(await page.textContent('#legend li.bad'), /^P\(r\)/);
  await page.screenshot({ path: join(here, 'screenshot-field.png'), fullPage: true });
  await page.fill('#form input[data-field="r"]', '1');
  await page.waitForSelector('#passes tbody tr');
  assert.equal(await page.$$eval('#form input.bad', (els) => els.length), 0);

  // 3. A pasted program with the seed's P020545: the error is marked in the listing at 2:8.
  await page.click('#tab-paste');
  await page.fill('#source', 'G00 X32 Z5\nG78 P020545 Q0.15 R0.5\nG78 X27.546 Z-30 P1.227 Q0.4 F2\n');
  await page.click('#analyse');
  await page.waitForSelector('#listing mark.err');
  assert.equal(await page.textContent('#listing mark.err'), '05');
  const diag = await page.textContent('#diagnostics li.error');
  assert.match(diag, /E004/);
  assert.match(diag, /line 2, column 8/);
  assert.match(await page.textContent('#gcode'), /no output/);
  await page.screenshot({ path: join(here, 'screenshot-error.png'), fullPage: true });

  // 4. Every controller with a cycle form plans M20x2.5 cleanly; OmniTurn (no form) says so.
  await page.click('#tab-plan');
  for (const [c, cycle] of [['fanuc', 'G76'], ['linuxcnc', 'G76'], ['ab9', 'G78']]) {
    await analysed(() => page.selectOption('#controller', c));
    assert.match(await page.textContent('#listing'), new RegExp(cycle), c);
    assert.match(await page.textContent('#diagnostics'), /No errors or warnings/, c);
    assert.doesNotMatch(await page.textContent('#gcode'), new RegExp(cycle), c);
    const n = await page.$$eval('#passes tbody tr', (trs) => trs.length);
    assert.ok(n >= 5, `${c}: ${n} passes`);
    assert.ok(await page.$('#plot svg'), `${c}: plot`);
    if (c === 'linuxcnc') await page.screenshot({ path: join(here, 'screenshot-linuxcnc.png'), fullPage: true });
  }
  await page.selectOption('#controller', 'omniturn');
  await page.waitForFunction(() => /No cycle form/.test(document.getElementById('form').textContent));

  // 5. An inch thread: pitch in TPI and inches, the lead to the control's resolution
  // (1/13" = 0.0769230769 in: F0.07692 on GSK, P0.0769231 on LinuxCNC; never P0.0769).
  await analysed(() => page.selectOption('#controller', 'gsk980'));
  await page.fill('#thread', '1/2-13 UNC');
  await analysed(() => page.click('#fill'));
  const info = await page.textContent('#thread-info');
  assert.match(info, /13 TPI \(pitch 0\.07692 in\)/, info);
  assert.match(info, /major 0\.5 in/, info);
  assert.doesNotMatch(info, / mm/, info);
  // The wires and gauges of 2A (issue 27): the best wire P/(2·cos 30°) = 0.076923/1.73205 =
  // 0.0444 in (the page shows 4 decimals); the screw ring GO at 2A's largest pitch diameter 0.4485, NOT GO at its least 0.4435.
  assert.match(info, /Three wires: best wire 0\.0444 in/, info);
  assert.match(info, /thread ring \(pitch\) GO 0\.4485 in, NOT GO 0\.4435 in/, info);
  assert.equal(await page.inputValue('#form input[data-field="lead"]'), '0.07692');
  assert.match(await page.textContent('#listing'), /F0\.07692/);
  await analysed(() => page.selectOption('#controller', 'linuxcnc'));
  assert.equal(await page.inputValue('#form input[data-field="lead"]'), '0.0769231');
  assert.match(await page.textContent('#listing'), /P0\.0769231/);
  assert.match(await page.textContent('#diagnostics'), /No errors or warnings/);
  await page.screenshot({ path: join(here, 'screenshot-inch.png'), fullPage: true });

  // 6. A thread that does not exist: the old plan goes, and the page says why in its own words.
  await page.fill('#thread', 'M99');
  await analysed(() => page.press('#thread', 'Enter'));
  const why = await page.textContent('#thread-info');
  assert.match(why, /No plan: “M99” is not a standard thread/, why);
  assert.match(why, /Nearest: M68x6, M64x2, M64x3/, why);
  assert.equal(await page.$$eval('#passes tbody tr', (trs) => trs.length), 0);
  assert.equal(await page.$$eval('#form input', (els) => els.length), 0);
  assert.equal(await page.textContent('#listing'), '');
  assert.match(await page.textContent('#gcode'), /no output/);
  assert.ok(!(await page.$('#plot svg')), 'the old plot is gone');
  assert.match(await page.textContent('#diagnostics li.error'), /No standard thread “M99”/);
  const body = await page.textContent('body');
  assert.doesNotMatch(body, /threadcut thread (--|NAME)|--list|--controller/, 'no command-line advice on the page');
  await page.screenshot({ path: join(here, 'screenshot-unknown.png'), fullPage: true });

  // 7. Convert: a Fanuc G76 program to GSK (its own G76, native), to LinuxCNC (plain G33 moves with
  // the reason), to the inch-only OmniTurn (refused: its G33 cycle cannot cut this job, and it has
  // no plain synchronised move; the 2 mm lead's drift on its .00005" grid is within the class). The right-hand side analyses the converted program on the target.
  await page.fill('#thread', 'M20x2.5');
  await analysed(() => page.selectOption('#controller', 'fanuc'));
  await analysed(() => page.click('#tab-convert'));
  // The tab starts from the program last analysed (step 3's).
  assert.match(await page.inputValue('#convert-source'), /G78 P020545/);
  const fanucProgram = 'G21 G99\nG97 S600 M3\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\nG0 X100. Z100.\nM30\n';
  await page.selectOption('#target', 'gsk980');
  await page.fill('#convert-source', fanucProgram);
  await page.waitForFunction(() => document.getElementById('converted').textContent.includes('G76 P020060 Q100 R0.05'));
  assert.match(await page.textContent('#converted'), /G76 X27\.546 Z-30\. P1227 Q400 F2\./);
  assert.match(await page.textContent('#convert-status li.ok'), /1 of 1 threading cycle as gsk980’s own cycle/);
  await page.waitForFunction(() => /G76 P020060/.test(document.getElementById('listing').textContent) &&
    /No errors or warnings/.test(document.getElementById('diagnostics').textContent));
  await page.selectOption('#target', 'linuxcnc');
  await page.waitForFunction(() => document.getElementById('converted').textContent.includes('G33 '));
  assert.match(await page.textContent('#convert-status li.plain'), /line 5: plain moves, not the native cycle: LinuxCNC's G76/);
  assert.match(await page.textContent('#converted'), /^\(threadcut convert: fanuc to linuxcnc, mm, feed per revolution\)\nG21 G90 G8 G18 G95 G97\n/);
  await page.screenshot({ path: join(here, 'screenshot-convert.png'), fullPage: true });
  await page.selectOption('#target', 'omniturn');
  await page.waitForSelector('#convert-status li.error');
  assert.match(await page.textContent('#convert-status li.error'), /line 5, column \d+: omniturn has no plain synchronised move/);
  assert.match(await page.textContent('#converted'), /no output/);
  assert.ok(await page.isDisabled('#download-converted'), 'nothing to download');

  // 7b. A pasted program that turns Ø19.8 from a Ø25 bar, threads M20x2.5 (G76, line 18), then
  // rapids at line 19 through the thread: the part is drawn above the threads, with the rapid in
  // red at its line, and the finding is E011 at line 19.
  await analysed(() => page.selectOption('#controller', 'fanuc'));
  await page.click('#tab-paste');
  await page.fill('#stock-diameter', '25');
  await page.fill('#stock-start', '0');
  await analysed(() => page.fill('#source', 'G21 G99\nT0101\nG97 S800 M03\nG00 X27. Z2.\nG71 U1.5 R0.5\n' +
    'G71 P10 Q20 U0.4 W0.1 F0.25\nN10 G00 X16.\nG01 Z0. F0.12\nX19.8 Z-1.9\nZ-30.\nX24.\nN20 X27.\n' +
    'G70 P10 Q20\nG00 X100. Z100.\nT0303\nG00 X24. Z5.\nG76 P020060 Q100 R0.05\n' +
    'G76 X16.85 Z-27. P1575 Q400 F2.5\nG00 X15. Z-10.\nG00 X100. Z100.\nM30\n'));
  await page.waitForSelector('#plot svg line.rapid-hit');
  const hit = await page.$eval('#plot svg', (svg) => ({
    red: svg.querySelectorAll('line.rapid-hit[stroke="#d00"]').length,
    label: [...svg.querySelectorAll('text')].some((t) => t.textContent === 'line 19'),
    part: svg.textContent.includes('The part as the program makes it'),
    stock: svg.textContent.includes('dashed: the stock Ø25 as given'),
  }));
  assert.deepEqual(hit, { red: 1, label: true, part: true, stock: true });
  assert.match(await page.textContent('#diagnostics'), /E011/);
  await page.screenshot({ path: join(here, 'screenshot-part.png'), fullPage: true });
  for (const id of ['#stock-diameter', '#stock-start']) await page.fill(id, '');

  // Pastes `big` over the listing and types M30 at its end; the time from the last keystroke to
  // the analysis on screen, the engine's and the drawing's shares, the longest main-thread task.
  const pasteAndTime = async (big) => {
    await page.evaluate((text) => navigator.clipboard.writeText(text), big);
    await page.evaluate(() => {
      window.longTasks = [];
      new PerformanceObserver((list) => {
        for (const e of list.getEntries()) window.longTasks.push({ start: e.startTime, ms: e.duration });
      }).observe({ type: 'longtask' });
    });
    await page.focus('#source');
    await page.keyboard.press('Control+A');
    const before = await page.evaluate(() => document.body.dataset.analysed || '0');
    await page.keyboard.press('Control+V');
    const pastedAt = await page.evaluate(() => performance.now());
    await page.keyboard.type('M30', { delay: 60 });
    // The analysis of the program as typed to its end (an analysis started during the typing,
    // when a slow machine paused longer than the page waits, may be shown first).
    await page.waitForFunction((b) => (document.body.dataset.analysed || '0') !== b &&
      document.getElementById('source').value.endsWith('M30') &&
      document.body.dataset.analysedLength === String(document.getElementById('source').value.length),
    before, { timeout: 30000 });
    await page.waitForTimeout(300);
    const timing = await page.evaluate((from) => {
      const edits = performance.getEntriesByType('mark').filter((m) => m.name === 'threadcut:edit');
      const shown = performance.getEntriesByType('mark').filter((m) => m.name === 'threadcut:shown');
      const lastEdit = edits[edits.length - 1].startTime;
      const after = window.longTasks.filter((t) => t.start + t.ms > from);
      return {
        lastEditToShown: shown[shown.length - 1].startTime - lastEdit,
        page: Number(document.body.dataset.analysedMs),
        engine: Number(document.body.dataset.engineMs),
        show: Number(document.body.dataset.showMs),
        longestTask: Math.max(0, ...after.map((t) => t.ms)),
        status: document.getElementById('status').textContent,
        length: document.getElementById('source').value.length,
        diagnostics: document.getElementById('diagnostics').textContent.slice(0, 300),
      };
    }, pastedAt);
    return timing;
  };

  // 8. A 30,000-line program pasted, then three keystrokes at its end: the analysis runs in the
  // worker once typing pauses, and is on screen within a second of the last keystroke; the page
  // never blocks for long meanwhile (long tasks, measured from the paste's input event on; the
  // paste itself, Chromium inserting 650 KB into a textarea, is the browser's own work).
  await analysed(() => page.selectOption('#controller', 'gsk980'));
  await page.click('#tab-paste');
  let big = 'G0 X80 Z10\n';
  for (let i = 0; i < 30000; i++) big += `G1 X${20 + (i % 50)}.5 Z-${i % 40}.25 F0.2\n`;
  big += 'G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n';
  const timing = await pasteAndTime(big);
  console.log(`big paste: ${timing.status}; shown ${Math.round(timing.lastEditToShown)} ms after the last keystroke ` +
    `(engine ${timing.engine} ms in the worker, drawing ${timing.show} ms); longest main-thread task after the paste ${Math.round(timing.longestTask)} ms`);
  assert.ok(timing.lastEditToShown < 1000, JSON.stringify(timing));
  assert.ok(timing.longestTask < 400, JSON.stringify(timing));
  assert.match(timing.status, /analysed 30,00\d lines/, JSON.stringify(timing));
  assert.equal(await page.$$eval('#passes tbody tr', (trs) => trs.length), 4);
  assert.match(await page.textContent('#listing'), /… 2\d,\d{3} (more )?lines/);
  assert.match(await page.textContent('#gcode'), /more lines \(Copy and Download give the whole program\)/);
  await page.screenshot({ path: join(here, 'screenshot-big.png') });

  // 8b. The heavier paste of issue 28: 10,000 GSK G78 cycles (30,004 lines), each from its own
  // start point: 10,000 threads checked against the part, their passes listed and drawn. Issue 28
  // asks for 1 s, and this machine kind shows it in 0.77–0.81 s (docs/performance.md); the bound
  // here leaves room for a CI machine twice as slow, and still fails if the quadratic costs found
  // earlier in issue 28 came back (several seconds).
  let cycles = '';
  for (let i = 0; i < 10000; i++) cycles += 'G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n';
  const many = await pasteAndTime(cycles);
  console.log(`10,000 cycles: ${many.status}; shown ${Math.round(many.lastEditToShown)} ms after the last keystroke ` +
    `(engine ${many.engine} ms in the worker, drawing ${many.show} ms); longest main-thread task after the paste ${Math.round(many.longestTask)} ms`);
  assert.ok(many.lastEditToShown < 2000, JSON.stringify(many));
  // (Step 8 holds the page's main thread to 400 ms; here 170–370 ms was measured, with the same
  // 660 KB in the text area, so the guard is looser on the slower CI machine.)
  assert.ok(many.longestTask < 1000, JSON.stringify(many));
  assert.match(many.status, /analysed 30,00\d lines/, JSON.stringify(many));
  // The analysis gave the expanded program's first 1,000 lines and counted the rest; Download
  // asks the engine for the whole program: those lines first, as many lines as were counted.
  const shownGcode = await page.textContent('#gcode');
  const more = shownGcode.match(/… ([\d,]+) more lines \(Copy and Download give the whole program\)\n$/);
  assert.ok(more, shownGcode.slice(-200));
  const [whole] = await Promise.all([page.waitForEvent('download'), page.click('#download')]);
  const wholeText = readFileSync(await whole.path(), 'utf8');
  const wholeLines = wholeText.split('\n').length - (wholeText.endsWith('\n') ? 1 : 0);
  assert.equal(wholeLines, 1000 + Number(more[1].replace(/,/g, '')));
  assert.ok(wholeText.startsWith(shownGcode.slice(0, more.index)), 'the shown lines begin the download');
  console.log(`10,000 cycles: the download holds the whole expansion, ${wholeLines.toLocaleString('en')} lines`);

  // 8c. The same weight for Fanuc: 10,000 two-block G76 cycles, each from its start point (the
  // figures for this and other controllers' pastes are in docs/performance.md).
  await analysed(() => page.selectOption('#controller', 'fanuc'));
  const fanuc = await pasteAndTime('G21 G99\nG97 S500 M3\n' +
    'G0 X22. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.933 Z-30. P1534 Q400 F2.5\n'.repeat(10000));
  console.log(`10,000 Fanuc G76: ${fanuc.status}; shown ${Math.round(fanuc.lastEditToShown)} ms after the last keystroke ` +
    `(engine ${fanuc.engine} ms in the worker, drawing ${fanuc.show} ms)`);
  assert.ok(fanuc.lastEditToShown < 2000, JSON.stringify(fanuc));
  assert.match(fanuc.status, /analysed 30,00\d lines/, JSON.stringify(fanuc));

  // 9. The worker's warm-up analysis (the page asks for it after an analysis is shown) has a
  // program of a hundred threading cycles every controller reads as such, with no finding: asked
  // of a worker of its own, each says so.
  const warmed = await page.evaluate(async (names) => {
    const w = new Worker('./worker.js', { type: 'module' });
    const out = {};
    for (const [id, name] of names.entries()) {
      out[name] = await new Promise((resolve) => {
        w.onmessage = (e) => resolve(JSON.parse(e.data.result));
        w.postMessage({ id, fn: 'warm', arg: JSON.stringify({ controller: name, motions: false, blanks: false, max_cycles: 20, gcode_lines: 1000, max_passes: 500 }) });
      });
    }
    w.terminate();
    return out;
  }, await page.$$eval('#controller option', (os) => os.map((o) => o.value)));
  assert.equal(Object.keys(warmed).length, 9, JSON.stringify(warmed));
  for (const [name, r] of Object.entries(warmed)) {
    assert.deepEqual(r, { ok: true, threads: 100, diagnostics: 0 }, `${name}: ${JSON.stringify(r)}`);
  }

  assert.deepEqual(problems, []);
  console.log(`e2e: ok (${url}; screenshots in web/e2e/)`);
} catch (e) {
  failed = true;
  console.error(e);
  if (problems.length) console.error(problems.join('\n'));
} finally {
  await browser.close();
  server.close();
}
process.exit(failed ? 1 : 0);
