// A 3-D world (octomap3d, configs/octomap-astar.yaml) is drawn one floor at a time: the floor
// selector switches floors, a plan that climbs follows the robot to its floor, the view goes back
// to the robot's floor after an accept, and a point with z is explained.
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, canvasData, waitAnimation, query, accept,
} from './harness.mjs';

const opt = args();

run(async () => {
  const server = await startServer(opt.flipper, [], { config: `${opt.root}/configs/octomap-astar.yaml` });
  const { context, close } = await launchBrowser();
  try {
    const page = await openPage(context, server.url);
    // configs/worlds/two-floors.json: floors z = 0, 1, 2; the robot at (1,1,0).
    equal(await page.$$eval('#floor-select button', (bs) => bs.map((b) => b.textContent)), ['z = 0', 'z = 1', 'z = 2'],
      'the floor selector lists the world\'s floors');
    check((await page.textContent('[data-testid=map-caption]')).includes('[1, 1, 0]'), 'the caption gives the robot\'s x, y, z');
    await shot(page, opt.artifacts, 'floors-1-ground');
    const ground = await canvasData(page);
    await page.click('[data-testid=floor-2]');
    check(await canvasData(page) !== ground, 'another floor draws another map');
    await shot(page, opt.artifacts, 'floors-2-top');
    await page.click('[data-testid=floor-0]');
    const a = await query(page, 'visit room3');
    equal(a.status, 'core', '"visit room3" (on floor 2) parses');
    await waitAnimation(page);
    const end = a.candidates[0].world.robot;
    equal(end.z, 2, 'the plan ends on floor 2');
    equal(await page.evaluate(() => window.flipperStudio.map.floor), 2, 'the animation follows the robot to floor 2');
    await shot(page, opt.artifacts, 'floors-3-climbed');
    await page.keyboard.press('Escape');

    // Looking at floor 1 while the robot is on floor 0: an accepted step brings the view back.
    await query(page, 'move right');
    await waitAnimation(page);
    await page.click('[data-testid=floor-1]');
    equal(await page.evaluate(() => window.flipperStudio.map.floor), 1, 'the floor-1 button shows floor 1');
    await accept(page);
    equal(await page.evaluate(() => window.flipperStudio.state.world.robot.z), 0, 'the robot stays on floor 0');
    equal(await page.$$eval('#floor-select button.active', (bs) => bs.map((b) => b.textContent)), ['z = 0'],
      'after the accept the view follows the robot\'s floor (the floor-0 button is active)');
    check((await page.textContent('[data-testid=map-caption]')).includes('showing floor z = 0'), 'the caption says floor 0');

    // A point with z is not core language: the error says how points work here.
    const z = await query(page, 'visit [1, 2, 0]');
    equal(z.status, 'unparsable', '"visit [1, 2, 0]" is not understood');
    await page.waitForSelector('[data-testid=query-error]:not([hidden])');
    check((await page.textContent('[data-testid=query-error]')).includes('Points are [x, y] on the robot\'s floor'),
      'the error explains points on a 3-D world', await page.textContent('[data-testid=query-error]'));
    const flat = await query(page, 'visit [1, 2]');
    equal(flat.status, 'core', '"visit [1, 2]" (the hint\'s form) is understood');
    equal(page.jsErrors, [], 'no JavaScript errors on the page');
  } finally {
    await close();
    await server.stop();
  }
});
