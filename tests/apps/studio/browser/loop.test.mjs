// One user's whole loop in a real browser: type, flip (the canvas changes), accept (the world
// changes as docs/core-language.md §10 says), undo, reset, a bad utterance with its error and
// "did you mean", teaching a phrase through the define panel and using it.
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, canvasData, waitAnimation,
  query, robot, accept,
} from './harness.mjs';

const opt = args();

run(async () => {
  const server = await startServer(opt.flipper);
  const { context, close } = await launchBrowser();
  try {
    const page = await openPage(context, server.url);
    await shot(page, opt.artifacts, 'loop-1-start');
    // The study map (§10): robot at (2,4) holding nothing; rooms labelled.
    equal(await robot(page), { x: 2, y: 4, holding: [] }, 'the page shows the study map with the robot at (2,4)');
    // The plain world, drawn again once the page's fonts are in (labels are text).
    await page.evaluate(async () => {
      await document.fonts.ready;
      window.flipperStudio.map.draw(window.flipperStudio.state.world);
    });
    const before = await canvasData(page);

    // §10 example 2: the nearest red item is at (7,4), a red circle is picked there.
    let a = await query(page, 'visit world containing item is red; pick item is red');
    equal(a.status, 'core', 'a core command parses');
    await page.waitForSelector('[data-testid=candidates] li.selected');
    await waitAnimation(page);
    // The map shows the plan, not just the world: compare with the plain world drawn now.
    const [shown, plain] = await page.evaluate(() => {
      const { map, state } = window.flipperStudio;
      const now = map.canvas.toDataURL();
      map.draw(state.world);
      return [now, map.canvas.toDataURL()];
    });
    check(shown !== plain && shown !== before, 'the selected candidate is drawn on the map');
    await page.evaluate(() => window.flipperStudio.selectCandidate(0));
    await waitAnimation(page);
    await shot(page, opt.artifacts, 'loop-2-candidate');
    await accept(page);
    await page.waitForFunction(() => window.flipperStudio.state.world.robot.x === 7);
    equal(await robot(page), { x: 7, y: 4, holding: ['red circle'] }, 'accept moves the robot to (7,4) holding the red circle');
    check((await page.textContent('[data-testid=holding]')).includes('Holding:'), 'the holding strip shows the held item');
    await shot(page, opt.artifacts, 'loop-3-accepted');

    await page.click('[data-testid=undo]');
    await page.waitForFunction(() => window.flipperStudio.state.world.robot.x === 2);
    equal(await robot(page), { x: 2, y: 4, holding: [] }, 'undo restores the world before the accept');

    // A reading that cannot be done here says why, and the nearest that can (docs/protocol.md
    // "Repairs"): no red item lies at (2,4), going to one first is the variant.
    a = await query(page, 'pick item is red');
    equal(a.repair?.unrealizable?.[0]?.variant?.edit, "visit 'world containing item {is red}' first",
      'the answer has the nearest realizable variant');
    await page.waitForSelector('[data-testid=candidate-why]');
    const why = await page.textContent('[data-testid=candidate-why]');
    check(why.includes('no red item at [2,4], where the robot is') && why.includes('Nearest that works'),
      'the reading says why it cannot be done and what can', why);

    // A bad utterance: unparsable, with its error and a "did you mean".
    a = await query(page, 'move lfet');
    equal(a.status, 'unparsable', '"move lfet" does not parse');
    await page.waitForSelector('[data-testid=query-error]:not([hidden])');
    check((await page.textContent('[data-testid=did-you-mean]')).includes('left'), '"did you mean" offers "left" for "lfet"',
      await page.textContent('[data-testid=did-you-mean]'));
    check(await page.isVisible('[data-testid=define-panel]'), 'an unparsable command opens the define panel');
    equal(await page.inputValue('[data-testid=define-head]'), 'move lfet', 'the define panel has the head pre-filled');
    // Its repair (docs/protocol.md "Repairs"): the nearest sentence is one click away.
    check((await page.textContent('[data-testid=repair-nearest]')).includes('move left'), 'the repair offers "move left"',
      await page.textContent('[data-testid=repair]'));
    check((await page.textContent('[data-testid=repair-words]')).includes('lfet (unknown, did you mean left?)'),
      'the repair names the unknown word', await page.textContent('[data-testid=repair]'));
    await page.click('[data-testid=repair-teach] button');
    await page.waitForFunction(() => document.querySelectorAll('[data-testid=define-line]').length === 1
      && document.querySelector('[data-testid=define-line]').value === 'move left');
    check(true, '"teach it as" fills the define panel with the nearest sentence');
    await shot(page, opt.artifacts, 'loop-4-unparsable');

    a = await query(page, 'move ' + 'left '.repeat(500));
    equal(a.error?.code, 'input_too_long', 'a too long command is refused with input_too_long');
    check((await page.textContent('[data-testid=query-error]')).includes('input_too_long'), 'the page shows the error code');

    // Teach "go to red" (a line parsed as it is typed, an error shown before submitting).
    await page.fill('[data-testid=query-input]', 'go to red');
    await page.click('[data-testid=teach]');
    await page.fill('[data-testid=define-head]', 'go to red');
    const line = page.locator('[data-testid=define-line]').first();
    await line.fill('visti world containing item is red');
    await page.waitForSelector('#define-lines li[data-state=error]');
    check(true, 'a wrong body line is marked before anything is submitted');
    await shot(page, opt.artifacts, 'loop-5-define-error');
    await line.fill('visit world containing item is red');
    await page.waitForSelector('#define-lines li[data-state=ok]');
    await page.click('[data-testid=define-submit]');
    await page.waitForSelector('[data-testid=define-result] li');
    const result = await page.textContent('[data-testid=define-result]');
    check(result.includes('go to $Color') || result.includes('go to $Property'), 'the define answer lists the induced rule', result);
    await page.waitForSelector('[data-testid=rules] li[data-rule]');
    await shot(page, opt.artifacts, 'loop-6-defined');

    // Use it: "go to yellow" is understood through the taught rule.
    a = await query(page, 'go to yellow');
    equal(a.status, 'induced', 'the taught phrase generalises to "go to yellow"');

    // Flip readings: "visit room3 or room5 containing item is red" has two readings (the `or` binds
    // either way) whose plans go to different rooms.
    a = await query(page, 'visit room3 or room5 containing item is red');
    check(a.candidates.length >= 2, 'an ambiguous command has several readings', String(a.candidates.length));
    await waitAnimation(page);
    const first = await canvasData(page);
    await shot(page, opt.artifacts, 'loop-7-reading-1');
    await page.keyboard.press('ArrowDown');
    await waitAnimation(page);
    equal(await page.evaluate(() => window.flipperStudio.state.selected), 1, 'ArrowDown selects the next reading');
    const second = await canvasData(page);
    check(second !== first, 'flipping to the next reading changes the canvas');
    await shot(page, opt.artifacts, 'loop-8-reading-2');
    await page.keyboard.press('ArrowUp');
    await waitAnimation(page);
    check(await canvasData(page) === first, 'flipping back draws the first reading again');

    // Reset world.
    await page.keyboard.press('Escape');
    await page.click('[data-testid=reset]');
    equal(await robot(page), { x: 2, y: 4, holding: [] }, 'reset brings back the starting world');
    equal(page.jsErrors, [], 'no JavaScript errors on the page');
  } finally {
    await close();
    await server.stop();
  }
});
