// /sempre from a real browser (docs/sempre.md): a minimal client page served by a second static
// server on another loopback port — another origin — calls flipper serve's /sempre with fetch and
// encodeURIComponent, as the 2018 web client does. Proves the CORS header and the encoding of
// every command form (quotes, brackets, semicolons, '+', non-ASCII) work in chromium, and that the
// same page cannot read the studio's own API (no CORS there).
import { createServer } from 'node:http';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import {
  args, check, equal, run, startServer, launchBrowser, shot,
} from './harness.mjs';

const opt = args();
const root = opt.root ?? process.cwd();
const page = readFileSync(new URL('./sempre-client.html', import.meta.url));

// The study map as the client's context: robot, walls and items, rooms.
function contextOf(world) {
  return {
    robot: [world.robot.x, world.robot.y, world.robot.holding.map((h) => [h.color, h.shape])],
    world: [...world.walls.map(([x, y]) => [x, y, 'wall', null, null]),
      ...world.items.map((i) => [i.x, i.y, 'item', i.color, i.shape])],
    rooms: world.rooms,
  };
}

function startStatic() {
  const server = createServer((req, res) => {
    res.writeHead(200, { 'Content-Type': 'text/html; charset=utf-8' });
    res.end(page);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

run(async () => {
  const statics = await startStatic();
  // The client's page is another origin: listed in serve.sempre_origins (docs/sempre.md).
  const flipper = await startServer(opt.flipper, ['serve.sempre=true',
    `serve.sempre_origins=[http://127.0.0.1:${statics.address().port}]`]);
  const browser = await launchBrowser();
  try {
    const api = flipper.url.replace(/\/$/, '');
    const pageUrl = `http://127.0.0.1:${statics.address().port}/?server=${encodeURIComponent(api)}`;
    check(new URL(pageUrl).origin !== new URL(api).origin, 'the page comes from another origin');
    const tab = await browser.context.newPage();
    const errors = [];
    tab.on('pageerror', (e) => errors.push(String(e)));
    await tab.goto(pageUrl);
    await tab.waitForSelector('body[data-ready=true]', { state: 'attached' });
    const world = contextOf(JSON.parse(readFileSync(join(root, 'configs/worlds/study2018.json'), 'utf8')));
    const call = (fn, ...a) => tab.evaluate(([f, xs]) => window.client[f](...xs), [fn, a]);

    let a = await call('context', world);
    equal(a.lines, [], 'the context is taken');
    a = await call('query', '  visit world containing item is red; pick item is red ');
    equal(a.stats.status, 'Core', ':q through fetch: a core reading');
    equal(a.candidates[0].formula, '{{visit {world containing item {is red}}};{pick item {is red}}}',
      'its formula is the canonical text');
    const value = JSON.parse(a.candidates[0].value);
    equal(value.path[0], [2, 4, 'path', 'null', 'null', true], 'the path starts at the robot\'s cell');
    equal(value.path.at(-1), [7, 4, 'pickitem', 'red', 'circle', true], 'and ends picking the red circle');

    // '+' and brackets survive encodeURIComponent and the server's decoding.
    await call('context', world);
    a = await call('query', 'visit [2 + 1, 4]');
    equal(a.candidates[0]?.formula, '{visit [{2 + 1},4]}', 'arithmetic with "+" arrives intact');
    a = await call('query', 'zorp é');
    equal([a.stats.status, a.candidates], ['Nothing', []], 'an unknown (non-ASCII) command: no candidates');
    equal((await call('reject', 'zorp é')).lines, [], ':reject');

    // A definition whose head holds quotes and ends with a space, then its use and the dictionary.
    a = await call('define', 'def', 'say "hi" ', [['move up', '{move up}'], ['move right', '(: move right)']]);
    equal(a.lines, [], ':def with a quoted head');
    equal(a.candidates[0]?.formula, '{{move up};{move right}}', ':def answers the body\'s formula');
    await call('context', world);
    a = await call('query', 'say "hi"');
    equal([a.stats.status, a.stats.author], ['Induced', await tab.evaluate(() => window.client.sessionId)],
      'the new phrase is understood, authored by this page\'s sessionId');
    equal((await call('accept', 'say "hi"', a.candidates[0].formula)).lines, [], ':accept');
    const dict = JSON.parse((await call('dictionary')).stats.dictionary);
    equal(dict.map((r) => r.head), ['say "hi" '], ':dictionary lists it');
    equal((await call('remove', dict[0].index)).lines, [], ':delete of our own rule');
    equal(JSON.parse((await call('dictionary')).stats.dictionary), [], 'and it is gone');

    equal(await call('readStudioInfo'), 'blocked', 'the same page cannot read /api/v1 (no CORS there)');
    equal(errors, [], 'no page errors');
    await shot(tab, opt.artifacts, 'sempre-client');
  } finally {
    await browser.close();
    statics.close();
    await flipper.stop();
  }
});
