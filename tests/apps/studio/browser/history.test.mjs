// Define from history (docs/studio.md "History"), as the 2018 client did: three accepted steps
// are listed with their readings; "from here" on the first marks them as a new phrase's body;
// the define request carries each step's accepted program; the history collapses into the new
// phrase, which then works from another start. A reload keeps the history.
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, query, waitAnimation, robot, accept,
} from './harness.mjs';

const opt = args();

const steps = (page) => page.$$eval('#history li[data-step]', (lis) => lis.map((li) => ({
  utterance: li.querySelector('.utterance').firstChild.textContent,
  formula: li.querySelector('code').textContent,
})));

run(async () => {
  const server = await startServer(opt.flipper);
  const { context, close } = await launchBrowser();
  try {
    const page = await openPage(context, server.url);
    const start = await robot(page);
    equal(start, { x: 2, y: 4, holding: [] }, 'the default world starts the robot at (2,4)');
    check(await page.isHidden('#history-panel'), 'no history before the first accept');
    const accepted = [];
    for (const text of ['move up', 'move right', 'move right']) {
      const a = await query(page, text);
      await waitAnimation(page);
      accepted.push({ utterance: text, formula: a.candidates[0].formula });
      await accept(page);
    }
    const after = await robot(page);
    equal(after, { x: 4, y: 5, holding: [] }, 'three steps take the robot to (4,5)');
    equal(await steps(page), accepted, 'the history lists the three steps with their accepted readings');

    // Look at the world after step 1, then come back.
    await page.click('#history li[data-step="0"] .step');
    equal(await page.evaluate(() => document.body.dataset.preview), '1', 'clicking step 1 previews the world after it');
    check((await page.textContent('[data-testid=map-caption]')).includes('World after step 1'),
      'the caption says which step is shown', await page.textContent('[data-testid=map-caption]'));
    await page.keyboard.press('Escape');
    equal(await page.evaluate(() => document.body.dataset.preview ?? null), null, 'Esc returns to the current world');

    // "trip" is not understood; the three steps become its meaning.
    const t = await query(page, 'trip');
    equal(t.status, 'unparsable', '"trip" is not understood yet');
    await page.click('#history li[data-step="0"] [data-testid=history-from]');
    equal(await page.$$eval('#history li.marked', (l) => l.length), 3, '"from here" on step 1 marks steps 1..3');
    equal(await page.textContent('[data-testid=history-teach]'), 'Teach a phrase from these 3 steps', 'the teach button counts the steps');
    await page.click('#history li[data-step="1"] [data-testid=history-from]', { modifiers: ['Shift'] });
    equal(await page.textContent('[data-testid=history-teach]'), 'Teach a phrase from these 2 steps', 'shift-click on step 2 ends the range there');
    await page.click('#history li[data-step="0"] [data-testid=history-from]');
    check(await page.isHidden('[data-testid=history-teach]'), 'a second click on the start unmarks the range');
    await page.click('#history li[data-step="0"] [data-testid=history-from]');
    equal(await page.textContent('[data-testid=history-teach]'), 'Teach a phrase from these 3 steps', 'marked again: steps 1..3');
    await page.click('[data-testid=history-teach]');
    equal(await page.inputValue('[data-testid=define-head]'), 'trip', 'the head is the text not understood');
    equal(await page.$$eval('#define-steps li', (l) => l.length), 3, 'the define panel shows the 3 steps read-only');
    const sent = page.waitForRequest((r) => r.postData()?.includes('"op":"define"'));
    const answered = page.waitForResponse((r) => r.request().postData()?.includes('"op":"define"'));
    await page.click('[data-testid=define-submit]');
    const request = JSON.parse((await sent).postData());
    equal(request, {
      op: 'define', head: 'trip', body: accepted.map((s) => ({ text: s.utterance, formula: s.formula })),
      studio: { why: 'history', steps: [0, 2] },
    }, 'the define request carries each step\'s accepted program (no ranks)');
    equal((await (await answered).json()).ok, true, 'the definition is accepted');
    await page.waitForFunction(() => document.querySelectorAll('#history li[data-step]').length === 1);
    const collapsed = `{${accepted.map((s) => s.formula).join(';')}}`;
    equal(await steps(page), [{ utterance: 'trip', formula: collapsed }], 'the history collapses into the new phrase');
    equal(await robot(page), after, 'teaching does not move the robot');
    await shot(page, opt.artifacts, 'history');

    // A reload keeps the history (this tab's sessionStorage on a plain server).
    await page.reload();
    await page.waitForSelector('body[data-ready=true]', { state: 'attached' });
    equal(await steps(page), [{ utterance: 'trip', formula: collapsed }], 'a reload keeps the history');

    // Undo of the collapsed step goes back to before its first step.
    await page.click('[data-testid=undo]');
    await page.waitForFunction(() => window.flipperStudio.state.world.robot.x === 2);
    equal(await robot(page), start, 'undo of the taught step restores the world before step 1');
    equal((await steps(page)).length, 0, 'and empties the history');

    // Use it: from the start, "trip" does the three steps.
    const u = await query(page, 'trip');
    equal(u.status, 'induced', '"trip" is understood through the taught rule');
    equal(u.candidates[0].formula, collapsed, 'its first reading is the three accepted programs in order');
    equal(u.candidates[0].world.robot.x === after.x && u.candidates[0].world.robot.y === after.y, true,
      'its first reading ends where the three steps ended');
    await waitAnimation(page);
    await accept(page);
    equal(await robot(page), after, 'accepting "trip" walks the three steps');
    equal((await steps(page)).map((s) => s.utterance), ['trip'], 'the history lists the new phrase as one step');
    // A long history folds all but the last eight steps.
    const fold = await page.evaluate(() => {
      const { historyPanel, state } = window.flipperStudio;
      const many = Array.from({ length: 10 }, (_, i) => ({ ...state.history[0], utterance: `step ${i + 1}` }));
      historyPanel.render(many);
      const out = {
        summary: document.querySelector('#history li.fold summary')?.textContent,
        folded: document.querySelectorAll('#history li.fold li[data-step]').length,
        all: document.querySelectorAll('#history li[data-step]').length,
      };
      historyPanel.render(state.history);
      return out;
    });
    equal(fold, { summary: '… 2 earlier steps', folded: 2, all: 10 }, 'ten steps: the two oldest fold under "… 2 earlier steps"');
    equal(page.jsErrors, [], 'no JavaScript errors on the page');
  } finally {
    await close();
    await server.stop();
  }
});
