// Study mode end to end: a small scripted study run through the page by two participants, its
// recording replayed with `flipper replay`, which must get the same status for every recorded
// query (and reproduce every accept) as the participants saw.
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, query, waitAnimation, robot, accept,
} from './harness.mjs';

const opt = args();
const root = opt.root || process.cwd();

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
    'groups: [C]',
    'preload: experts.jsonl',
    'record: recording',
    'tasks:',
    '  - {name: warm-up, text: "Move the robot one step right.", start: start.json, goal: goal.json}',
    '  - {name: room1, text: "Bring the blue square out of room1.", start: second.json}',
    '',
  ].join('\n'));
  return dir;
}

// Every query answer the page received, in order.
function watchQueries(page, into) {
  page.on('response', async (r) => {
    if (!r.url().includes('/api/v1/request') || !r.request().postData()?.includes('"op":"query"')) return;
    const a = await r.json().catch(() => null);
    if (a?.ok) into.push(a.status);
  });
}

run(async () => {
  const dir = makeStudy();
  const server = await startServer(opt.flipper, [`serve.study=${join(dir, 'study.yaml')}`], { dir });
  const { context, close } = await launchBrowser();
  const seen = [];
  try {
    const p1 = await openPage(context, server.url);
    if (process.env.STUDIO_DEBUG) p1.on('response', async (r) => r.url().includes('/api/') && console.log('   ', r.status(), r.request().postData()?.slice(0, 70), (await r.text()).slice(0, 120)));
    watchQueries(p1, seen);
    check(await p1.isVisible('#study-tutorial'), 'the study starts with its tutorial');
    await shot(p1, opt.artifacts, 'study-1-tutorial');
    await p1.click('#study-start');
    await p1.waitForSelector('#study-banner:not([hidden])');
    check((await p1.textContent('#study-banner')).includes('Task 1 of 2: warm-up'), 'the banner shows the first task');
    check(await p1.isVisible('#goal-map'), 'the task\'s goal world is drawn');
    await query(p1, 'move right');
    await waitAnimation(p1);
    await accept(p1);
    await p1.waitForFunction(() => window.flipperStudio.state.world.robot.x === 3);
    equal(await robot(p1), { x: 3, y: 4, holding: [] }, 'the participant reaches the goal (robot at (3,4))');
    let a = await query(p1, 'go to green');
    equal(a.status, 'induced', 'group C has the preloaded expert definition ("go to red" generalises)');
    await waitAnimation(p1);
    await accept(p1);
    a = await query(p1, 'pick 3 items');
    equal(a.status, 'unparsable', '"pick 3 items" is not understood yet');
    await p1.locator('[data-testid=define-line]').first().fill('repeat 3 times pick item');
    await p1.waitForSelector('#define-lines li[data-state=ok]');
    const defined = p1.waitForResponse((r) => r.request().postData()?.includes('"op":"define"'));
    await p1.click('[data-testid=define-submit]');
    equal((await (await defined).json()).ok, true, 'the participant teaches "pick 3 items"');
    await p1.waitForFunction(() => window.flipperStudio.state.query?.answer?.status === 'induced');
    await waitAnimation(p1);
    await accept(p1);
    await shot(p1, opt.artifacts, 'study-2-task1');
    await p1.click('#study-next');
    await p1.waitForFunction(() => window.flipperStudio.state.world.robot.x === 10);
    check((await p1.textContent('#study-banner')).includes('Task 2 of 2'), 'the next task loads its start world');
    await query(p1, 'visit world containing item is blue; pick item is blue; move up');
    await waitAnimation(p1);
    await accept(p1);
    await p1.waitForFunction(() => window.flipperStudio.state.world.robot.holding.length === 1);

    const p2 = await openPage(context, server.url);
    watchQueries(p2, seen);
    await p2.click('#study-start');
    await p2.waitForSelector('#study-banner:not([hidden])');
    a = await query(p2, 'drop 2 items');
    equal(a.status, 'induced', 'the second participant uses the first one\'s phrase (group C: shared)');
    await query(p2, 'move lfet');
    await query(p2, 'visit room4');
    await waitAnimation(p2);
    await accept(p2);
    await p2.waitForFunction(() => window.flipperStudio.state.world.robot.y === 7);
    await shot(p2, opt.artifacts, 'study-3-participant2');
    equal(p1.jsErrors.concat(p2.jsErrors), [], 'no JavaScript errors on the pages');
  } finally {
    await close();
    await server.stop();
  }

  // The recording: the corpus format.
  const rec = join(dir, 'recording');
  const commands = readJsonl(join(rec, 'queries.jsonl'));
  const recorded = commands.filter((c) => c.kind === 'q');
  const statusWord = { core: 'Core', induced: 'Induced', unparsable: 'Nothing' };
  equal(recorded.map((c) => c.status), seen.map((s) => statusWord[s]), 'every query the pages made is recorded with its status');
  equal(commands.filter((c) => c.kind === 'accept').length, 5, 'the five accepts are recorded');
  equal(commands.filter((c) => c.kind === 'def').length, 1, 'the definition is recorded');
  const sessions = JSON.parse(readFileSync(join(rec, 'sessions.json'), 'utf8'));
  equal(sessions.map((s) => s.source), ['studio/pilot/C', 'studio/pilot/C'], 'sessions.json names both participants\' run');

  // Replay it with the existing experiment tools.
  const experiment = join(dir, 'replay.yaml');
  writeFileSync(experiment, 'name: studio pilot\nconfig: ""\ncorpus: recording\nset: [induction.alignment=true]\nvariants:\n  - {name: plain, set: []}\n');
  const out = join(dir, 'replay');
  execFileSync(opt.flipper, ['replay', '--experiment', experiment, '--corpus', rec, '--out', out], { cwd: root, stdio: 'inherit' });
  // The run goes into a new folder under --out; `latest` links it (docs/experiments.md §1).
  const rows = readCsv(join(out, 'latest', 'plain', 'queries.csv'));
  equal(rows.length, recorded.length, 'the replay answers every recorded query');
  equal(rows.map((r) => r.ours), seen, 'the replay gets the same status for every query');
  equal(rows.filter((r) => r.agree !== '1').length, 0, 'every row agrees with the recording');
  const accepts = readCsv(join(out, 'latest', 'plain', 'accepts.csv'));
  equal(accepts.map((r) => `${r.matched}${r.executed}${r.robot}${r.held}${r.floor}`), Array(5).fill('11111'),
    'every recorded accept is matched, executed and ends in the recorded world');
});
