// The page's smaller promises (docs/studio.md "The page"), each checked in chromium: a phone
// layout without sideways scrolling, Ctrl+Z from the command box, every help example parses, the
// World menu offers only worlds the server loads, no "did you mean" for words a taught rule
// read, a typed definition sends each line's chosen reading, the define panel resets after a
// success, and taught rules read as their example with the notation on demand.
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, query, waitAnimation, robot, accept,
} from './harness.mjs';

const opt = args();

// A second protocol session (another guest) on the same server: the page does not know its rules.
async function otherSession(url) {
  let token = '';
  return async (req) => {
    const res = await fetch(`${url}api/v1/request${token ? `?session=${token}` : ''}`, {
      method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(req),
    });
    token = res.headers.get('Flipper-Session') || token;
    return res.json();
  };
}

// Every protocol request the page sends, parsed, in order.
function watchRequests(page) {
  const seen = [];
  page.on('request', (r) => r.url().includes('/api/v1/request') && seen.push(JSON.parse(r.postData())));
  return seen;
}

async function phoneLayout(context, url) {
  const page = await openPage(context, url);
  await page.setViewportSize({ width: 390, height: 844 });
  await query(page, 'move up');
  await waitAnimation(page);
  const m = await page.evaluate(() => ({
    scroll: document.documentElement.scrollWidth,
    map: Math.round(document.getElementById('map').getBoundingClientRect().width),
    input: Math.round(document.getElementById('query-input').getBoundingClientRect().width),
  }));
  check(m.scroll <= 390, 'at 390×844 the page does not scroll sideways', `scrollWidth ${m.scroll}`);
  check(m.map >= 340, 'at 390×844 the map takes the full width', `map ${m.map} px`);
  check(m.input >= 200, 'at 390×844 the command box is usable', `input ${m.input} px`);
  await shot(page, opt.artifacts, 'phone');
  await page.close();
}

async function ctrlZ(page) {
  await query(page, 'move up');
  await waitAnimation(page);
  await accept(page);
  equal((await robot(page)).y, 5, 'move up accepted: y = 5');
  // Text in the box: Ctrl+Z is the box's own text undo, the world stays.
  await page.fill('[data-testid=query-input]', 'move');
  await page.focus('[data-testid=query-input]');
  await page.keyboard.press('Control+z');
  equal((await robot(page)).y, 5, 'Ctrl+Z with text in the command box leaves the world alone');
  await page.fill('[data-testid=query-input]', '');
  await page.focus('[data-testid=query-input]');
  await page.keyboard.press('Control+z');
  const undone = await page.waitForFunction(() => window.flipperStudio.state.world.robot.y === 4, null, { timeout: 5000 })
    .then(() => true, () => false);
  check(undone, 'Ctrl+Z in the empty command box undoes the accepted step', `robot ${JSON.stringify(await robot(page))}`);
}

async function helpExamples(page) {
  const results = await page.evaluate(async () => {
    const { EXAMPLES } = await import('/help.js');
    const out = [];
    for (const [text] of EXAMPLES) {
      const a = await window.flipperStudio.api.request({ op: 'query', text });
      out.push({ text, status: a.status ?? a.error?.code, error: a.candidates?.[0]?.error ?? null });
    }
    return out;
  });
  check(results.length >= 15, 'the help has its examples', String(results.length));
  const bad = results.filter((r) => r.status === 'unparsable' || !['core', 'induced'].includes(r.status) || r.error);
  equal(bad, [], 'every help example parses and its first reading runs');
  const shown = await page.$$eval('#help-examples dt button', (bs) => bs.map((b) => b.textContent));
  equal(shown, results.map((r) => r.text), 'the help panel shows exactly these examples');
}

async function worldMenu(page) {
  const options = await page.$$eval('[data-testid=world-select] option', (os) => os.map((o) => o.value));
  equal(options, ['', 'study2018.json'], 'the World menu of a 2-D server offers study2018 only (not the 3-D two-floors)');
  // A choice the server refuses leaves the menu on the world shown.
  await page.evaluate(() => {
    const o = document.createElement('option');
    o.value = 'two-floors.json';
    document.getElementById('world-select').append(o);
  });
  const refused = page.waitForResponse((r) => r.request().postData()?.includes('"file":"two-floors.json"'));
  await page.selectOption('[data-testid=world-select]', 'two-floors.json');
  equal((await (await refused).json()).error?.code, 'bad_world', 'the server refuses a 3-D world');
  await page.waitForFunction(() => document.getElementById('world-select').value === '');
  check(true, 'after the refusal the menu shows the world in use again');
  await page.selectOption('[data-testid=world-select]', 'study2018.json');
  await page.waitForFunction(() => document.getElementById('world-select').value === 'study2018.json'
    && window.flipperStudio.state.history.length === 0);
  check(true, 'study2018 loads from the menu');
}

async function didYouMean(page, url) {
  // Another guest teaches "hop to the den" (shared mode): this page's rule list does not have it yet.
  const other = await otherSession(url);
  const d = await other({ op: 'define', head: 'hop to the den', body: ['visit room1'] });
  equal(d.ok, true, 'another session teaches "hop to the den"');
  const a = await query(page, 'hop to the den');
  equal(a.status, 'induced', 'the page reads "hop to the den" through that rule');
  await waitAnimation(page);
  check(await page.isHidden('[data-testid=did-you-mean]'), 'no "did you mean" for words the chosen reading covers',
    await page.textContent('[data-testid=did-you-mean]'));
  const b = await query(page, 'hop to the dne');
  equal(b.status, 'unparsable', 'a misspelt "hop to the dne" is not understood');
  await page.waitForSelector('[data-testid=did-you-mean]:not([hidden])');
  const hint = await page.textContent('[data-testid=did-you-mean]');
  check(hint.includes('dne') && hint.includes('den') && !hint.includes('hop'),
    'for the unparsable text, only the unknown word gets a hint', hint);
  await page.click('#define-cancel');

  // A generalized rule ("go to $Color") reads as the example it was taught from.
  equal((await other({ op: 'define', head: 'go to red', body: ['visit world containing item is red'] })).ok, true,
    'another session teaches "go to red"');
  equal((await query(page, 'go to blue')).status, 'induced', '"go to blue" is read through the generalized rule');
  await page.waitForSelector('#rules li[data-rule] .rule-head >> text=go to red', { timeout: 5000 });
  const rows = await page.$$eval('#rules li[data-rule]', (lis) => lis.map((li) => ({
    head: li.querySelector('.rule-head').textContent,
    notation: li.querySelector('.rule-notation code').textContent,
  })));
  const general = rows.filter((r) => r.notation.includes('$Color') || r.notation.includes('$Property'));
  check(general.length > 0 && general.every((r) => r.head === 'go to red'),
    'a generalized rule is titled by its example, the notation ($Color) folded', JSON.stringify(rows));
}

async function typedDefine(page) {
  const seen = watchRequests(page);
  await query(page, 'move up');
  await waitAnimation(page);
  await page.fill('[data-testid=query-input]', 'zag');
  await page.click('[data-testid=teach]');
  equal(await page.inputValue('[data-testid=define-head]'), 'zag', 'Teach takes the box\'s text as the head');
  await page.locator('[data-testid=define-line]').first().fill('move left');
  await page.waitForSelector('#define-lines li[data-state=ok]');
  // The live check replaced the session's last query: "move up"'s readings can no longer be accepted.
  check(await page.isHidden('#candidates-panel'), 'a define line\'s check takes away the readings of the query before it');
  await page.press('[data-testid=define-line] >> nth=0', 'Enter');
  await page.locator('[data-testid=define-line]').nth(1).fill('visit room3 or room5 containing item is red');
  await page.waitForFunction(() => document.querySelectorAll('#define-lines li[data-state=ok]').length === 2);
  const options = await page.locator('[data-testid=define-reading]').nth(1).evaluate((s) => [...s.options].map((o) => o.textContent));
  check(options.length >= 2, 'the second line has several readings', String(options.length));
  await page.locator('[data-testid=define-reading]').nth(1).selectOption('1');
  const answered = page.waitForResponse((r) => r.request().postData()?.includes('"op":"define"'));
  const reran = page.waitForResponse((r) => r.request().postData()?.includes('"why":"rerun"'));
  await page.click('[data-testid=define-submit]');
  const answer = await (await answered).json();
  equal(answer.ok, true, 'zag is taught');
  const define = seen.find((r) => r.op === 'define');
  const firstLine = seen.filter((r) => r.op === 'query' && r.text === 'move left').pop();
  equal(define, { op: 'define', head: 'zag', body: [
    { text: 'move left', formula: define.body[0].formula },
    { text: 'visit room3 or room5 containing item is red', formula: options[1] },
  ] }, 'a typed definition sends each line with its chosen reading (line 2: reading 2), no ranks');
  equal(firstLine?.studio, { why: 'live' }, 'the define lines\' checks are marked as live checks');
  // The panel shows the result, a toast says so, then the panel closes and the phrase is read again.
  check((await page.textContent('#toast')).includes('Learned "zag"'), 'a toast says what was learned');
  const rerun = await reran;
  equal(JSON.parse(rerun.request().postData()), { op: 'query', text: 'zag', studio: { why: 'rerun' } },
    'the page reads the taught head again, marked as a re-run');
  await page.waitForSelector('[data-testid=define-panel]', { state: 'hidden', timeout: 8000 });
  check(true, 'the define panel closes after a success');
  await page.click('[data-testid=teach]');
  equal(await page.textContent('[data-testid=define-result]'), '', 'opened again, the panel has no old "Learned…" text');
  equal(await page.$$eval('[data-testid=define-line]', (l) => l.map((i) => i.value)), [''], 'and one empty line');

  // Typing on right after a success keeps the panel open (and clears the old result).
  await page.fill('[data-testid=define-head]', 'zog');
  await page.locator('[data-testid=define-line]').first().fill('move down');
  await page.waitForSelector('#define-lines li[data-state=ok]');
  await page.click('[data-testid=define-submit]');
  await page.waitForSelector('[data-testid=define-result].ok');
  await page.fill('[data-testid=define-head]', 'zog zog');
  equal(await page.textContent('[data-testid=define-result]'), '', 'an edit after a success clears its result');
  await page.waitForTimeout(4500); // past the close after a success: nothing to await, the panel must stay
  check(await page.isVisible('[data-testid=define-panel]'), 'and the panel stays open while it is worked in');
  await page.click('#define-cancel');

  // The rule reads as its example; the notation is there on demand.
  await page.waitForSelector('#rules li[data-rule]');
  const row = await page.$$eval('#rules li[data-rule]', (lis) => lis.map((li) => ({
    head: li.querySelector('.rule-head').textContent,
    means: li.querySelector('.rule-means').textContent,
    open: li.querySelector('details.rule-notation').open,
    notation: li.querySelector('details.rule-notation code').textContent,
  })).find((r) => r.head === 'zag') ?? {});
  equal([row.head, row.means, row.open], ['zag', 'means: move left; visit room3 or room5 containing item is red', false],
    'a taught rule shows its head and body, the notation folded');
  check(row.notation.includes('→') && row.notation.includes('⇒'), 'the notation is there on demand', row.notation);
}

run(async () => {
  const server = await startServer(opt.flipper, ['lexicon.sharing=shared']);
  const { context, close } = await launchBrowser();
  try {
    await phoneLayout(context, server.url);
    const page = await openPage(context, server.url);
    await ctrlZ(page);
    await helpExamples(page);
    await worldMenu(page);
    await typedDefine(page);
    await didYouMean(page, server.url);
    equal(page.jsErrors.filter((e) => !e.includes('status of 400')), [], 'no JavaScript errors on the page');
  } finally {
    await close();
    await server.stop();
  }
});
