// The example study (examples/study) run as a lab runs it, by the checklist of docs/studio.md §7
// "Running a study": every command of its `<!-- study-test -->` blocks runs as written, in order,
// in a scratch folder that looks like the repository root (build/ linked, examples/study copied,
// HOME there); the server's command gets `--set serve.port=0` (a free port) and nothing else.
// A participant does both tasks in a browser as a person would (typing sentences, accepting the
// reading shown) and reaches each task's goal; the researcher logs in, closes the study and
// downloads every file; the replay recipe on the downloaded folder reproduces the run: the exact
// task_start and goal lines, every status, every accept in its recorded world, byte for byte.
import { spawn, spawnSync } from 'node:child_process';
import { cpSync, mkdirSync, mkdtempSync, readFileSync, readdirSync, rmSync, symlinkSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import {
  args, check, equal, run, launchBrowser, openPage, shot, waitAnimation, robot, accept,
} from './harness.mjs';

const opt = args();
const root = resolve(opt.root || process.cwd());
const STUDY = 'examples/study/study.yaml';
// The checklist's commands, in its order (docs/studio.md §7 "Running a study").
const COMMANDS = {
  account: `build/bin/flipper accounts add mod --role admin --set serve.study=${STUDY}`,
  serve: `build/bin/flipper serve --set serve.study=${STUDY}`,
  invite: `build/bin/flipper accounts invite P1 --url http://127.0.0.1:8410/ --set serve.study=${STUDY}`,
  verify: 'build/bin/flipper replay verify study-download',
  replay: 'build/bin/flipper replay --experiment examples/study/replay.yaml --corpus study-download --out out/study-replay',
};
const PASSWORD = 'researcher password';
// Task 2 ("Put every red item in room4"), a sentence at a time: the red circle at [7,4], the red
// triangles at [4,0] and [10,8] (examples/study/start.json), then all three dropped in room4.
const RED_ITEMS = [
  'visit [7,4]; pick item is red',
  'visit [4,0]; pick item is red',
  'visit [10,8]; pick item is red',
  'visit room4; drop every item',
];

// The commands of docs/studio.md's marked blocks (text after "  # " is the page's comment).
function checklist() {
  const lines = readFileSync(join(root, 'docs/studio.md'), 'utf8').split('\n');
  const out = [];
  lines.forEach((line, i) => {
    if (line.trim() !== '<!-- study-test -->') return;
    if (!lines[i + 1]?.startsWith('```')) throw new Error(`docs/studio.md:${i + 2}: no fenced block after the marker`);
    for (let j = i + 2; j < lines.length && !lines[j].startsWith('```'); j++) {
      const command = lines[j].split('  # ')[0].trim();
      if (command) out.push(command);
    }
  });
  return out;
}

// A folder that looks like the repository root: build/ (the binary's), configs/ and data/ linked,
// examples/study copied without a recording, HOME inside.
function scratchRoot() {
  const dir = mkdtempSync(join(tmpdir(), 'flipper-example-study-'));
  symlinkSync(dirname(dirname(resolve(opt.flipper))), join(dir, 'build'));
  for (const d of ['configs', 'data']) symlinkSync(join(root, d), join(dir, d));
  mkdirSync(join(dir, 'examples'));
  cpSync(join(root, 'examples/study'), join(dir, 'examples/study'), {
    recursive: true, filter: (src) => !src.includes(`${join('examples', 'study', 'recording')}`),
  });
  return dir;
}

function shell(dir, command, input = '') {
  const r = spawnSync('sh', ['-c', command], { cwd: dir, input, encoding: 'utf8', env: { ...process.env, HOME: dir } });
  return { status: r.status, output: `${r.stdout}${r.stderr}`, stdout: r.stdout };
}

// The server's command as written plus a free port; resolves when it listens.
async function serve(dir, command) {
  const proc = spawn('sh', ['-c', `exec ${command} --set serve.port=0`],
    { cwd: dir, stdio: ['ignore', 'pipe', 'pipe'], env: { ...process.env, HOME: dir } });
  let output = '';
  const url = await new Promise((res, rej) => {
    const timer = setTimeout(() => rej(new Error(`the server did not start in 20 s:\n${output}`)), 20000);
    const onData = (d) => {
      output += d;
      const m = output.match(/listening on (http:\/\/127\.0\.0\.1:\d+\/)/);
      if (m) {
        clearTimeout(timer);
        res(m[1]);
      }
    };
    proc.stdout.on('data', onData);
    proc.stderr.on('data', onData);
    proc.on('exit', (code) => rej(new Error(`the server exited with ${code}:\n${output}`)));
  });
  const stop = async () => {
    if (proc.exitCode !== null) return proc.exitCode;
    const done = new Promise((r) => proc.once('exit', r));
    proc.kill('SIGTERM');
    return done;
  };
  return { url, stop };
}

function readJsonl(path) {
  return readFileSync(path, 'utf8').split('\n').filter(Boolean).map((l) => JSON.parse(l));
}

// Rows of a CSV file as objects; quoted fields ("…", "" inside) may hold commas.
function readCsv(path) {
  const parse = (line) => {
    const out = [];
    let field = '', quoted = false;
    for (let i = 0; i < line.length; i++) {
      const c = line[i];
      if (quoted && c === '"' && line[i + 1] === '"') field += line[++i];
      else if (c === '"') quoted = !quoted;
      else if (c === ',' && !quoted) {
        out.push(field);
        field = '';
      } else field += c;
    }
    out.push(field);
    return out;
  };
  const [head, ...rows] = readFileSync(path, 'utf8').trim().split('\n').map(parse);
  return rows.map((r) => Object.fromEntries(r.map((v, i) => [head[i], v])));
}

// Types a sentence, waits for the answer to that very query, and accepts the reading shown;
// resolves to {query, accept, goal} (goal: the accept's Flipper-Goal header).
async function doSentence(page, text) {
  await page.fill('[data-testid=query-input]', text);
  const answer = page.waitForResponse((r) => {
    if (!r.url().includes('/api/v1/request')) return false;
    const req = JSON.parse(r.request().postData() || '{}');
    return req.op === 'query' && req.text === text && !req.studio?.why;
  });
  await page.press('[data-testid=query-input]', 'Enter');
  const query = await (await answer).json();
  await waitAnimation(page);
  const accepted = page.waitForResponse((r) => r.url().includes('/api/v1/request') &&
    r.request().postData()?.includes('"op":"accept"'));
  await accept(page);
  const response = await accepted;
  return { query, accept: await response.json(), goal: response.headers()['flipper-goal'] ?? null };
}

run(async () => {
  const commands = checklist();
  equal(commands, Object.values(COMMANDS), 'the checklist\'s commands are the ones this test runs, in order');
  const dir = scratchRoot();
  const record = join(dir, 'examples/study/recording');
  const download = join(dir, 'study-download');

  // ---- Before ----
  const added = shell(dir, COMMANDS.account, `${PASSWORD}\n`);
  equal([added.status, added.stdout], [0, 'added mod\n'], 'before: the researcher\'s account is added', added.output);
  check(readdirSync(record).includes('accounts.sqlite'), 'in the study\'s own store (its recording folder)');
  const server = await serve(dir, COMMANDS.serve);
  const b1 = await launchBrowser();
  const b2 = await launchBrowser();
  const b3 = await launchBrowser();
  let p1Accepts;
  try {
    // ---- During: P1 does both tasks ----
    const p = await openPage(b1.context, server.url);
    equal(await p.evaluate(() => window.flipperStudio.api.user), 'P1', 'the first visitor is P1');
    check(await p.isVisible('#study-tutorial'), 'P1 starts with the tutorial');
    await p.click('#study-start');
    await p.waitForSelector('#study-banner:not([hidden])');
    equal(await p.textContent('#study-task-title'), 'Task 1 of 2: warm-up', 'the banner shows task 1');
    let step = await doSentence(p, 'visit room1');
    equal([step.query.status, step.accept.ok, step.goal], ['core', true, 'reached'], 'task 1: "visit room1" reaches its goal');
    equal(await robot(p), { x: 9, y: 0, holding: [] }, 'the robot is at [9,0], room1\'s nearest cell');
    check(await p.isVisible('#goal-reached'), 'the page says the goal is reached');
    await p.click('#study-next');
    await p.waitForFunction(() => window.flipperStudio.state.taskIndex === 1 && window.flipperStudio.state.world.robot.x === 2);
    equal(await p.textContent('#study-task-title'), 'Task 2 of 2: red items', 'the banner shows task 2');
    check(!(await p.isVisible('#goal-reached')), 'task 2 starts without its goal');
    const goals = [];
    for (const sentence of RED_ITEMS) {
      step = await doSentence(p, sentence);
      check(step.query.status === 'core' && step.accept.ok, `task 2: "${sentence}" is understood and runs`, JSON.stringify(step.query).slice(0, 200));
      goals.push(step.goal);
    }
    equal(goals, [null, null, null, 'reached'], 'only the last sentence (all three red items dropped in room4) reaches task 2\'s goal');
    equal(await robot(p), { x: 5, y: 7, holding: [] }, 'the robot ends in room4 ([5,7], its nearest cell) with empty hands');
    await shot(p, opt.artifacts, 'example-study-P1');
    equal(p.jsErrors, [], 'no JavaScript errors on P1\'s page');

    // A one-time code for P1's other device, then that device resumes P1 at task 2.
    const invited = shell(dir, COMMANDS.invite);
    const code = invited.stdout.split('\n')[0];
    check(invited.status === 0 && /^[A-Za-z0-9_-]{8,}$/.test(code)
      && invited.stdout.includes(`http://127.0.0.1:8410/?code=${code}`), 'during: the invitation code and its link', invited.output);
    const other = await openPage(b2.context, `${server.url}?code=${code}`);
    await other.waitForFunction(() => window.flipperStudio.api.user === 'P1');
    equal(await other.evaluate(() => window.flipperStudio.state.taskIndex), 1, 'the other device resumes P1 at task 2');

    // ---- After: the researcher closes the study and downloads every file ----
    const r = await b3.context.newPage();
    await r.goto(`${server.url}researcher.html`);
    await r.waitForSelector('[data-testid=researcher-login]:not([hidden])');
    await r.fill('#login-name', 'mod');
    await r.fill('#login-password', PASSWORD);
    await r.click('[data-testid=researcher-login-submit]');
    await r.waitForSelector('[data-testid=researcher-table] tbody tr');
    const rows = await r.$$eval('[data-testid=researcher-table] tbody tr',
      (trs) => trs.map((tr) => [...tr.children].slice(0, 4).map((td) => td.textContent)));
    equal(rows, [['P1', 'A', '2: red items', 'reached']], 'the researcher sees P1 in group A, task 2, its goal reached');
    await r.click('[data-testid=researcher-close]');
    await r.waitForFunction(() => document.getElementById('study-state').textContent.includes('closed'));
    mkdirSync(download);
    const links = await r.$$eval('a[data-testid^=researcher-download-]', (as) => as.map((a) => a.dataset.testid));
    for (const id of links) {
      const [file] = await Promise.all([r.waitForEvent('download'), r.click(`[data-testid=${id}]`)]);
      await file.saveAs(join(download, file.suggestedFilename()));
    }
    await shot(r, opt.artifacts, 'example-study-researcher');
    p1Accepts = RED_ITEMS.length + 1;
  } finally {
    await b1.close();
    await b2.close();
    await b3.close();
    equal(await server.stop(), 0, 'after: the server stops on SIGTERM with status 0');
  }
  const files = readdirSync(download).sort();
  equal(files, ['audit.jsonl', 'definitions.jsonl', 'exchanges.jsonl', 'original-answers.jsonl', 'participants.json', 'preload-C.jsonl',
    'queries.jsonl', 'sessions.json', 'study.json', 'worlds.jsonl'], 'every file of the recording is downloaded');
  for (const f of files.filter((name) => name !== 'audit.jsonl'))
    check(readFileSync(join(download, f)).equals(readFileSync(join(record, f))), `the download of ${f} is the server's file`);

  // The task and goal lines, exactly (docs/studio.md §7 "The recording", "Goals").
  const lines = readJsonl(join(download, 'queries.jsonl'));
  const byQid = Object.fromEntries(lines.map((c) => [c.qid, c]));
  const taskLines = lines.filter((c) => ['task_start', 'goal', 'task_skip'].includes(c.kind)).map((c) => [
    c.participant, c.kind, c.task, c.task_name, c.for_qid ? byQid[c.for_qid]?.utterance : null]);
  equal(taskLines, [
    ['P1', 'task_start', 0, 'warm-up', null],
    ['P1', 'goal', 0, 'warm-up', 'visit room1'],
    ['P1', 'task_start', 1, 'red items', null],
    ['P1', 'goal', 1, 'red items', 'visit room4; drop every item'],
  ], 'the recording has each task\'s start and its goal, reached by the accept of the sentence that did it');
  const goalLines = lines.filter((c) => c.kind === 'goal');
  check(goalLines.every((c) => Number.isInteger(c.task_ms) && c.task_ms >= 0), 'each goal line has the task\'s time (task_ms)', JSON.stringify(goalLines.map((c) => c.task_ms)));
  const acceptLines = lines.filter((c) => c.kind === 'accept');
  equal(acceptLines.map((c) => c.utterance), ['visit room1', ...RED_ITEMS], 'P1\'s accepts are the sentences typed');
  equal(acceptLines.length, p1Accepts, 'one accept per sentence');

  // ---- The replay recipe on the downloaded folder ----
  const verify = shell(dir, COMMANDS.verify);
  const exchanges = readJsonl(join(download, 'exchanges.jsonl'));
  equal([verify.status, verify.stdout.trim()], [0, `${exchanges.length} exchanges, every answer equal byte for byte (ms excluded)`],
    'after: `flipper replay verify` finds every answer equal', verify.output);
  const replay = shell(dir, COMMANDS.replay);
  check(replay.status === 0, 'after: `flipper replay` on the downloaded folder runs', replay.output);
  const runDir = join(dir, 'out/study-replay/latest/plain');
  const queries = readCsv(join(runDir, 'queries.csv'));
  equal(queries.map((q) => [q.qid, q.utterance, q.agree]), lines.filter((c) => c.kind === 'q').map((c) => [c.qid, c.utterance, '1']),
    'the replay answers every recorded query with the recorded status');
  const accepts = readCsv(join(runDir, 'accepts.csv'));
  const outcome = (a) => `${a.matched}${a.executed}${a.robot}${a.held}${a.floor}`;
  equal(accepts.map((a) => [a.qid, outcome(a)]), acceptLines.map((c) => [c.qid, '11111']),
    'every accept is matched, executed and ends in the recorded world');
  equal(goalLines.map((g) => outcome(accepts.find((a) => a.qid === g.for_qid) ?? {})), ['11111', '11111'],
    'the replay reaches both goal worlds with the accepts that reached them live');
  rmSync(dir, { recursive: true, force: true });
});
