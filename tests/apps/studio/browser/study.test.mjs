// Study mode end to end (docs/studio.md §7): a scripted study with two participants in groups B
// (private) and C (shared) run through the page: a goal reached, two definitions of one phrase,
// a definition whose second line uses its second reading, an induced phrase accepted, a reject,
// a delete, an undo and a reload; then the researcher's view (login, the table, close: a new
// participant is refused). The recording must then replay exactly: `flipper replay` agrees on
// every status, accept, induced rule and delete, and `flipper replay verify` finds every answer
// equal byte for byte (and names the exchange whose answer a copy changes).
//
// The page annotates its requests (`studio.why`: live, rerun, task_start, undo, reset, history)
// and sends events (reject, flip, page_load); a page without them (detected by its history list)
// leaves those kinds out, and the assertions that need them are skipped with a note.
import { execFileSync, spawnSync } from 'node:child_process';
import { cpSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, waitAnimation, robot, accept,
  addAccount,
} from './harness.mjs';

const opt = args();
const root = opt.root || process.cwd();
const started = Date.now();

function readJsonl(path) {
  return readFileSync(path, 'utf8').split('\n').filter(Boolean).map((l) => JSON.parse(l));
}

function readCsv(path) {
  const [head, ...rows] = readFileSync(path, 'utf8').trim().split('\n');
  const cols = head.split(',');
  return rows.map((r) => Object.fromEntries(r.split(',').map((v, i) => [cols[i], v])));
}

function makeStudy() {
  const dir = mkdtempSync(join(tmpdir(), 'flipper-study-'));
  const map = JSON.parse(readFileSync(join(root, 'configs/worlds/study2018.json'), 'utf8'));
  const goal = { ...map, robot: { x: 3, y: 4, holding: [] } };
  const second = { ...map, robot: { x: 10, y: 1, holding: [] } };
  writeFileSync(join(dir, 'start.json'), JSON.stringify(map));
  writeFileSync(join(dir, 'goal.json'), JSON.stringify(goal));
  writeFileSync(join(dir, 'second.json'), JSON.stringify(second));
  writeFileSync(join(dir, 'experts.jsonl'),
    `${JSON.stringify({ head: 'go to red', body: ['visit world containing item is red'], author: 'expert' })}\n`);
  writeFileSync(join(dir, 'study.yaml'), [
    'name: pilot',
    'tutorial: "Tell the robot what to do; teach it what it does not understand."',
    'groups: [B, C]',
    'preload: experts.jsonl',
    'record: recording',
    'tasks:',
    '  - {name: warm-up, text: "Move the robot one step right.", start: start.json, goal: goal.json}',
    '  - {name: room1, text: "Bring the blue square out of room1.", start: second.json}',
    '',
  ].join('\n'));
  return dir;
}

// The answer of the next protocol request whose body includes `fragment`.
function nextAnswer(page, fragment) {
  return page.waitForResponse((r) => r.url().includes('/api/v1/request') &&
    r.request().postData()?.includes(fragment));
}

// Types a command and waits for the answer to that very query (not a live check or a re-run the
// page may still be sending).
async function ask(page, text) {
  await page.fill('[data-testid=query-input]', text);
  const answer = page.waitForResponse((r) => {
    if (!r.url().includes('/api/v1/request')) return false;
    const req = JSON.parse(r.request().postData() || '{}');
    return req.op === 'query' && req.text === text && !req.studio?.why;
  });
  await page.press('[data-testid=query-input]', 'Enter');
  return (await answer).json();
}

// Teaches `head` through the define panel (already open): one line per body text, each line's
// reading chosen by index (`readings`), then Teach; resolves to the define answer.
async function teach(page, head, lines, readings = []) {
  await page.waitForSelector('[data-testid=define-panel]:not([hidden])');
  await page.fill('[data-testid=define-head]', head);
  for (let i = 0; i < lines.length; i++) {
    if (i > 0 && (await page.locator('[data-testid=define-line]').count()) <= i)
      await page.click('[data-testid=define-add]');
    const line = page.locator('#define-lines li').nth(i);
    await line.locator('[data-testid=define-line]').fill(lines[i]);
    await page.waitForFunction((n) => document.querySelectorAll('#define-lines li')[n]?.dataset.state === 'ok', i);
    if (readings[i]) await line.locator('[data-testid=define-reading]').selectOption(String(readings[i]));
  }
  const answer = nextAnswer(page, '"op":"define"');
  await page.click('[data-testid=define-submit]');
  return (await answer).json();
}

run(async () => {
  const dir = makeStudy();
  const server = await startServer(opt.flipper, [`serve.study=${join(dir, 'study.yaml')}`], { dir });
  // Each participant has a browser of their own: one browser's cookie is one participant.
  const b1 = await launchBrowser();
  const b2 = await launchBrowser();
  const b3 = await launchBrowser();
  let withPage = false; // the page annotates requests and sends events
  try {
    // ---- P1, group B ----
    const p1 = await openPage(b1.context, `${server.url}?group=B`);
    p1.on('dialog', (d) => d.accept());
    withPage = await p1.evaluate(() => !!document.querySelector('[data-testid=history]'));
    console.log(`     the page ${withPage ? 'annotates' : 'does not annotate'} its requests (history list ${withPage ? 'present' : 'absent'})`);
    check(await p1.isVisible('#study-tutorial'), 'the study starts with its tutorial');
    check(!(await p1.isVisible('#sharing')) || !(await p1.textContent('#sharing')).match(/private|shared|core/),
      'the page does not show the participant\'s condition');
    await p1.click('#study-start');
    await p1.waitForSelector('#study-banner:not([hidden])');
    check((await p1.textContent('#study-banner')).includes('Task 1 of 2: warm-up'), 'the banner shows the first task');
    await ask(p1, 'move right');
    await waitAnimation(p1);
    const accepted = nextAnswer(p1, '"op":"accept"');
    await accept(p1);
    // The server knows the task from the page's task_start annotation.
    if (withPage) equal((await accepted).headers()['flipper-goal'], 'reached', 'the accept that reaches the goal says so (Flipper-Goal)');
    else console.log('     skip: Flipper-Goal (the page does not say which task started)');
    equal(await robot(p1), { x: 3, y: 4, holding: [] }, 'the participant reaches the goal (robot at (3,4))');

    // hop := move up, then hop := move left: two readings, the newer first.
    let a = await ask(p1, 'hop');
    equal(a.status, 'unparsable', '"hop" is not understood yet');
    if (!(await p1.isVisible('[data-testid=define-panel]'))) await p1.click('[data-testid=teach]');
    let d = await teach(p1, 'hop', ['move up']);
    equal(d.ok, true, 'the participant teaches hop := move up');
    await p1.waitForFunction(() => window.flipperStudio.state.query?.answer?.status === 'induced'
      || document.querySelector('[data-testid=define-panel]')?.hidden === false);
    await waitAnimation(p1);
    await p1.click('[data-testid=teach]');
    d = await teach(p1, 'hop', ['move left']);
    equal(d.ok, true, 'and hop := move left');
    // zig := move right; hop (its second reading, {move up}).
    a = await ask(p1, 'zig');
    equal(a.status, 'unparsable', '"zig" is not understood yet');
    if (!(await p1.isVisible('[data-testid=define-panel]'))) await p1.click('[data-testid=teach]');
    await p1.fill('[data-testid=define-head]', 'zig');
    await p1.locator('[data-testid=define-line]').first().fill('move right');
    await p1.waitForFunction(() => document.querySelector('#define-lines li')?.dataset.state === 'ok');
    await p1.click('[data-testid=define-add]');
    await p1.locator('[data-testid=define-line]').nth(1).fill('hop');
    await p1.waitForFunction(() => document.querySelectorAll('#define-lines li')[1]?.dataset.state === 'ok');
    const readings = await p1.locator('#define-lines li').nth(1).locator('[data-testid=define-reading] option').allTextContents();
    equal(readings, ['{move left}', '{move up}'], '"hop" has two readings, the newer first');
    await p1.locator('#define-lines li').nth(1).locator('[data-testid=define-reading]').selectOption('1');
    const defined = nextAnswer(p1, '"op":"define"');
    await p1.click('[data-testid=define-submit]');
    d = await (await defined).json();
    equal(d.ok, true, 'the participant teaches zig := move right; hop (second reading)');
    equal(d.rules?.map((r) => r.semantics), ['{{move right};{move up}}'], 'the induced rule uses the chosen reading');
    const zigRule = d.rules?.[0]?.id;
    await p1.waitForFunction(() => window.flipperStudio.state.query?.answer?.status === 'induced'
      && window.flipperStudio.state.query.text === 'zig');
    await waitAnimation(p1);
    await accept(p1);
    equal(await robot(p1), { x: 4, y: 5, holding: [] }, 'the taught phrase runs (right, then up)');
    // A reject: hop's readings shown, none of them meant.
    await ask(p1, 'hop');
    await waitAnimation(p1);
    await p1.click('[data-testid=reject]');
    // Delete zig's rule with its Delete button.
    await p1.waitForSelector(`#rules li[data-rule="${zigRule}"] button.delete`);
    const deleted = nextAnswer(p1, '"op":"delete_rule"');
    await p1.click(`#rules li[data-rule="${zigRule}"] button.delete`);
    equal((await (await deleted).json()).ok, true, 'the participant deletes the rule of zig');
    await ask(p1, 'move up');
    await waitAnimation(p1);
    await accept(p1);
    const accepted3 = await p1.evaluate(() => window.flipperStudio.state.history?.length ?? null);
    await p1.click('[data-testid=undo]');
    await p1.waitForFunction(() => window.flipperStudio.state.world.robot.y === 5);
    // The page pops its history once the world is back.
    if (accepted3 !== null) await p1.waitForFunction((n) => window.flipperStudio.state.history.length === n - 1, accepted3);
    const historyBefore = await p1.evaluate(() => window.flipperStudio.state.history?.length ?? null);
    await p1.reload();
    await p1.waitForSelector('body[data-ready=true]', { state: 'attached' });
    equal(await robot(p1), { x: 4, y: 5, holding: [] }, 'a reload keeps the world');
    if (withPage) {
      check(!(await p1.isVisible('#study-tutorial')), 'a reload does not show the tutorial again');
      equal(await p1.evaluate(() => window.flipperStudio.state.taskIndex), 0, 'a reload keeps the task');
      equal(await p1.evaluate(() => window.flipperStudio.state.history?.length), historyBefore, 'a reload keeps the history');
    } else {
      console.log('     skip: tutorial, task and history after a reload (the page restores them)');
      await p1.click('#study-start');
    }
    await p1.click('#study-next');
    await p1.waitForFunction(() => window.flipperStudio.state.world.robot.x === 10);
    check((await p1.textContent('#study-banner')).includes('Task 2 of 2'), 'the next task loads its start world');
    await shot(p1, opt.artifacts, 'study-1-participant1');

    // ---- P2, group C ----
    const p2 = await openPage(b2.context, `${server.url}?group=C`);
    await p2.click('#study-start');
    await p2.waitForSelector('#study-banner:not([hidden])');
    a = await ask(p2, 'go to green');
    equal(a.status, 'induced', 'group C has the preloaded expert definition ("go to red" generalises)');
    await waitAnimation(p2);
    await accept(p2);
    a = await ask(p2, 'move lfet');
    equal(a.status, 'unparsable', '"move lfet" is not understood');
    if (withPage && await p2.isVisible('[data-testid=history-from]')) {
      await ask(p2, 'move up');
      await waitAnimation(p2);
      await accept(p2);
      await p2.locator('[data-testid=history-from]').first().click();
      await p2.click('[data-testid=history-teach]');
      await p2.waitForSelector('[data-testid=define-panel]:not([hidden])');
      await p2.fill('[data-testid=define-head]', 'go green then up');
      const fromHistory = nextAnswer(p2, '"why":"history"');
      await p2.click('[data-testid=define-submit]');
      equal((await (await fromHistory).json()).ok, true, 'P2 teaches a phrase from the history');
    } else {
      console.log('     skip: define from history (the page has no history list)');
    }
    await shot(p2, opt.artifacts, 'study-2-participant2');
    equal(p1.jsErrors.concat(p2.jsErrors), [], 'no JavaScript errors on the pages');

    // ---- the researcher ----
    addAccount(opt.flipper, server, 'mod', 'moderator password', 'admin');
    const r = await b3.context.newPage();
    await r.goto(`${server.url}researcher.html`);
    await r.waitForSelector('[data-testid=researcher-login]:not([hidden])');
    await r.fill('#login-name', 'mod');
    await r.fill('#login-password', 'moderator password');
    await r.click('[data-testid=researcher-login-submit]');
    await r.waitForSelector('[data-testid=researcher-table] tbody tr');
    const rows = await r.$$eval('[data-testid=researcher-table] tbody tr',
      (trs) => trs.map((tr) => [...tr.children].slice(0, 3).map((td) => td.textContent)));
    if (withPage) equal(rows, [['P1', 'B', '2: room1'], ['P2', 'C', '1: warm-up']], 'the researcher sees both participants, their group and task');
    else equal(rows.map((row) => row.slice(0, 2)), [['P1', 'B'], ['P2', 'C']], 'the researcher sees both participants and their group (tasks need the page\'s task_start)');
    check(await r.isVisible('[data-testid=researcher-download-queries]'), 'the recording can be downloaded file by file');
    // The lexicon section (docs/studio.md §7 "Lexicon"): group B's history holds P1's two
    // definitions of `hop`; this study holds nothing for approval.
    await r.waitForSelector('body[data-lexicon-ready=true]');
    equal(await r.$$eval('#lexicon-group option', (os) => os.map((o) => o.value)), ['B', 'C'],
      'the lexicon section offers the study\'s groups');
    equal(await r.textContent('[data-testid=researcher-pending]'), 'nothing held',
      'nothing is held without moderation');
    const heads = await r.$$eval('[data-testid=researcher-history] li[data-action=define]',
      (lis) => lis.map((li) => li.textContent.includes("'hop'")));
    equal(heads.filter(Boolean).length, 2, 'group B\'s history shows both definitions of hop');
    await r.fill('#invite-name', 'P1');
    await r.click('[data-testid=researcher-invite] button');
    await r.waitForFunction(() => document.getElementById('invite-url').textContent.includes('/?code='));
    check(true, 'the researcher makes a code link for P1\'s other device');
    await shot(r, opt.artifacts, 'researcher');
    await r.click('[data-testid=researcher-close]');
    await r.waitForFunction(() => document.getElementById('study-state').textContent.includes('closed'));
    const late = await fetch(`${server.url}api/v1/request`, { method: 'POST', body: '{"op":"state"}' });
    equal([late.status, (await late.json()).error?.code], [403, 'study_closed'], 'a closed study takes no new participant');
    // A new visitor (here the researcher's own browser, not a participant) gets the closed page.
    const visitor = await b3.context.newPage();
    await visitor.goto(`${server.url}`);
    await visitor.waitForSelector('body[data-ready=closed]', { state: 'attached', timeout: 15000 });
    check(await visitor.isVisible('[data-testid=study-closed]'), 'a new visitor sees that the study is closed');
    check(!(await visitor.isVisible('main')), 'and no app that could not answer');
    equal(await visitor.textContent('#study-closed-name'), '"pilot"', 'the closed page names the study');
    await shot(visitor, opt.artifacts, 'study-closed');
    const back = await openPage(b2.context, `${server.url}`);
    equal(await back.evaluate(() => window.flipperStudio.api.user), 'P2', 'a participant who reopens the page is still P2');
    await shot(r, opt.artifacts, 'researcher-closed');
    // A computer participants share (docs/studio.md §7 "Shared computers"): the study reopened, a
    // kiosk page takes P3; its "Next participant" starts the page over as P4; the researcher's
    // "Next participant" on P4's row makes the kiosk's next request a new participant, P5.
    await r.click('[data-testid=researcher-close]');
    await r.waitForFunction(() => document.getElementById('study-state').textContent.includes('open to'));
    const b4 = await launchBrowser();
    try {
      const kiosk = await openPage(b4.context, `${server.url}?kiosk`);
      equal(await kiosk.evaluate(() => window.flipperStudio.api.user), 'P3', 'the kiosk page takes a new participant');
      check(await kiosk.isVisible('[data-testid=kiosk-next]'), 'the kiosk page offers the next participant');
      check(!(await back.isVisible('[data-testid=kiosk-next]')), 'a page without ?kiosk does not');
      await kiosk.click('[data-testid=kiosk-next]');
      await kiosk.waitForFunction(() => window.flipperStudio?.api.user === 'P4' && document.body.dataset.ready === 'true');
      check(true, 'the kiosk\'s next participant: the page starts over as P4');
      await r.waitForSelector('[data-testid=researcher-end-P4]', { timeout: 15000 });
      const [ended] = await Promise.all([
        r.waitForResponse((res) => res.url().endsWith('/api/v1/study/end')),
        r.click('[data-testid=researcher-end-P4]'),
      ]);
      equal((await ended.json()).logins, 1, 'the researcher ends P4\'s login');
      equal(await kiosk.evaluate(async () => {
        await window.flipperStudio.api.request({ op: 'state' });
        return window.flipperStudio.api.user;
      }), 'P5', 'the kiosk\'s next request is the next participant');
    } finally {
      await b4.close();
    }
  } finally {
    await b1.close();
    await b2.close();
    await b3.close();
    await server.stop();
  }
  console.log(`     the scripted study took ${((Date.now() - started) / 1000).toFixed(1)} s`);

  // ---- the recording ----
  const rec = join(dir, 'recording');
  const files = ['queries.jsonl', 'worlds.jsonl', 'definitions.jsonl', 'original-answers.jsonl', 'exchanges.jsonl',
    'sessions.json', 'participants.json', 'study.json', 'preload-C.jsonl'];
  // `head -3` of each file, for the record (an artefact).
  writeFileSync(join(opt.artifacts, 'study-recording-head.txt'), files.map((f) =>
    `==> ${f} <==\n${readFileSync(join(rec, f), 'utf8').split('\n').slice(0, 3).join('\n')}\n`).join('\n'));
  const commands = readJsonl(join(rec, 'queries.jsonl'));
  // P1's recording in brief (the closing note shows it): one line per action, the main fields.
  const brief = (c) => [c.line, c.kind, `task ${c.task}`, c.utterance ?? c.head ?? '', c.status ?? c.formula ?? '',
    c.body ? JSON.stringify(c.body) : '', c.exchange ?? '-'].join(' | ');
  writeFileSync(join(opt.artifacts, 'study-recording-P1.txt'),
    `${commands.filter((c) => c.participant === 'P1').map(brief).join('\n')}\n`);
  const of = (p, kind) => commands.filter((c) => c.participant === p && c.kind === kind);
  const kinds = (p) => commands.filter((c) => c.participant === p).map((c) => c.kind);
  console.log(`     P1: ${kinds('P1').join(' ')}`);
  console.log(`     P2: ${kinds('P2').join(' ')}`);
  equal(commands.map((c) => c.line), commands.map((_, i) => i + 1), 'queries.jsonl lines are numbered in order');
  check(commands.every((c) => c.participant && c.group && 'task' in c && c.time && c.phase), 'every line names participant, group, task, time and phase');
  equal(of('P1', 'accept').length, 3, 'P1\'s three accepts are recorded');
  equal(of('P1', 'def').map((c) => c.head), ['hop', 'hop', 'zig'], 'P1\'s three definitions are recorded');
  const zig = of('P1', 'def')[2];
  const line2 = zig?.body?.[1] ?? {};
  check(line2.formula === '{move up}' || (line2.formula === '' && line2.rank === 1),
    'zig\'s second line is recorded with the reading chosen', JSON.stringify(line2));
  const del = of('P1', 'delete');
  equal(del.map((c) => [c.def_id, c.rule_pos, c.status]), [[zig?.def_id, 0, 'ok']], 'the delete names its definition and position');
  equal(of('P1', 'resume').length, 0, 'a reload is the same protocol session (no resume)');
  if (withPage) {
    equal(of('P1', 'goal').map((c) => c.task), [0], 'P1 reached task 1\'s goal once');
    const q1 = of('P1', 'q').map((c) => c.utterance);
    equal(q1, ['move right', 'hop', 'zig', 'hop', 'move up'], 'P1\'s queries are what P1 asked (no live check, no re-run)');
    check(of('P1', 'live').length > 0, 'the define lines\' live checks are recorded as live');
    equal(of('P1', 'reject').map((c) => c.utterance), ['hop'], 'the reject is recorded');
    equal(of('P1', 'undo').length, 1, 'the undo is recorded');
    equal(of('P1', 'task_start').map((c) => c.task), [0, 1], 'both task starts are recorded');
    check(of('P1', 'page_load').some((c) => c.reloaded === true), 'the reload is recorded');
    equal(of('P2', 'q').map((c) => c.utterance).slice(0, 2), ['go to green', 'move lfet'], 'P2\'s queries are recorded');
    equal(of('P1', 'rerun').map((c) => c.utterance), ['hop', 'hop', 'zig'], 'the re-runs after each definition are recorded as rerun');
    const fromHistory = of('P2', 'def');
    if (fromHistory.length) {
      const accepts2 = of('P2', 'accept');
      equal(fromHistory[0].from_history, accepts2.map((c) => c.qid), 'the definition from history names the accepts it came from');
      equal(fromHistory[0].body.map((b) => [b.utterance, b.formula]), accepts2.map((c) => [c.utterance, c.formula]),
        'each of its lines is the accepted step with the program accepted');
      const p2 = JSON.parse(readFileSync(join(rec, 'participants.json'), 'utf8')).participants.find((p) => p.participant === 'P2');
      equal([p2.history.length, p2.history[0]?.utterance, p2.history[0]?.steps?.length], [1, 'go green then up', 2],
        'the server\'s history collapses the steps into the new phrase');
    }
  } else {
    console.log('     skip: goal, live, rerun, reject, undo, task_start, page_load and the query list (the page does not annotate)');
  }
  const sessions = JSON.parse(readFileSync(join(rec, 'sessions.json'), 'utf8'));
  equal(sessions.map((s) => [s.session, s.source]).slice(0, 2), [['P1', 'studio/pilot/B'], ['P2', 'studio/pilot/C']],
    'sessions.json names both participants\' runs');

  // Replay: statuses, accepts, induced rules and the delete.
  const experiment = join(dir, 'replay.yaml');
  writeFileSync(experiment, 'name: studio pilot\nconfig: ""\ncorpus: recording\nset: [induction.alignment=true]\nvariants:\n  - {name: plain, set: []}\n');
  const out = join(dir, 'replay');
  execFileSync(opt.flipper, ['replay', '--experiment', experiment, '--corpus', rec, '--out', out, '--no-plots'], { cwd: root, stdio: 'inherit' });
  const runDir = join(out, 'latest', 'plain');
  const queries = readCsv(join(runDir, 'queries.csv'));
  equal(queries.length, commands.filter((c) => c.kind === 'q').length, 'the replay answers every recorded query');
  equal(queries.filter((r) => r.agree !== '1').map((r) => r.utterance), [], 'the replay gets the same status for every query');
  const accepts = readCsv(join(runDir, 'accepts.csv'));
  equal(accepts.map((r) => `${r.matched}${r.executed}${r.robot}${r.held}${r.floor}`), Array(commands.filter((c) => c.kind === 'accept').length).fill('11111'),
    'every recorded accept is matched, executed and ends in the recorded world');
  const defines = readCsv(join(runDir, 'definitions.csv')).filter((r) => r.preloaded === '0');
  equal(defines.map((r) => `${r.head}:${r.ok}:${r.rule_match}`), commands.filter((c) => c.kind === 'def').map((c) => `${c.head}:1:identical`),
    'every definition induces the same rules (lhs, rhs and semantics)');
  const deletes = readCsv(join(runDir, 'deletions.csv'));
  equal(deletes.map((r) => r.deleted !== ''), [true], 'the delete removes our rule of that definition');

  // Byte for byte.
  const verify = spawnSync(opt.flipper, ['replay', 'verify', rec], { cwd: root, encoding: 'utf8' });
  const exchanges = readJsonl(join(rec, 'exchanges.jsonl'));
  equal([verify.status, verify.stdout.trim()], [0, `${exchanges.length} exchanges, every answer equal byte for byte (ms excluded)`],
    '`flipper replay verify` finds every answer equal', verify.stderr);
  const copy = join(dir, 'changed');
  cpSync(rec, copy, { recursive: true });
  const n = exchanges.findIndex((e) => JSON.parse(e.request).op === 'accept');
  const e = exchanges[n];
  e.answer = e.answer.replace('"ok":true', '"ok":frue');
  writeFileSync(join(copy, 'exchanges.jsonl'), `${exchanges.map((x) => JSON.stringify(x)).join('\n')}\n`);
  const bad = spawnSync(opt.flipper, ['replay', 'verify', copy], { cwd: root, encoding: 'utf8' });
  equal(bad.status, 1, 'verify fails on a recording whose answer was changed');
  check(bad.stdout.startsWith(`flipper replay verify: exchange ${e.n} (participant ${e.participant}`),
    'and names that exchange', bad.stdout.slice(0, 200));
});
