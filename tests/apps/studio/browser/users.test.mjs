// Two users at once on one server, each in their own browser (their own login cookie): ana and
// bob log in with their accounts through the page's login form (docs/accounts.md). In shared
// mode bob sees and uses ana's phrase but cannot delete it, and cannot become ana; in private
// mode he sees nothing of hers.
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, query, waitAnimation, robot, accept,
  addAccount, logIn,
} from './harness.mjs';

const opt = args();

// Two browsers (separate cookies), ana logged in in one and bob in the other.
async function anaAndBob(server) {
  addAccount(opt.flipper, server, 'ana', 'ana password');
  addAccount(opt.flipper, server, 'bob', 'bob password');
  const browsers = [await launchBrowser(), await launchBrowser()];
  const ana = await openPage(browsers[0].context, server.url);
  const bob = await openPage(browsers[1].context, server.url);
  await logIn(ana, 'ana', 'ana password');
  await logIn(bob, 'bob', 'bob password');
  return { ana, bob, close: async () => { for (const b of browsers) await b.close(); } };
}

async function teach(page, head, lines) {
  await page.fill('[data-testid=query-input]', head);
  await page.click('[data-testid=teach]');
  await page.fill('[data-testid=define-head]', head);
  for (let i = 0; i < lines.length; i++) {
    if (i > 0) await page.click('[data-testid=define-add]');
    await page.locator('[data-testid=define-line]').nth(i).fill(lines[i]);
  }
  await page.waitForFunction((n) => document.querySelectorAll('#define-lines li[data-state=ok]').length === n, lines.length);
  const answer = page.waitForResponse((r) => r.request().postData()?.includes('"op":"define"'));
  await page.click('[data-testid=define-submit]');
  return (await answer).json();
}

async function ruleRows(page) {
  return page.$$eval('[data-testid=rules] li[data-rule]', (lis) => lis.map((li) => ({
    text: li.querySelector('.rule-head').textContent,
    author: li.querySelector('.meta').textContent,
    deletable: !li.querySelector('button.delete').disabled,
  })));
}

run(async () => {
  // ---- shared mode -------------------------------------------------------------------------------
  let server = await startServer(opt.flipper, ['lexicon.sharing=shared']);
  let browser = null;
  try {
    browser = await anaAndBob(server);
    const { ana, bob } = browser;
    equal(await ana.textContent('[data-testid=who]'), 'ana', 'ana is logged in');
    equal(await bob.textContent('[data-testid=who]'), 'bob', 'bob is logged in');
    const bobAsAna = await bob.evaluate(() => window.flipperStudio.setUser('ana'));
    equal(bobAsAna.error?.code, 'forbidden', 'bob cannot become ana');
    equal(await bob.evaluate(() => window.flipperStudio.state.user), 'bob', 'bob stays bob');

    const defined = await teach(ana, 'pick 3 items', ['repeat 3 times pick item']);
    equal(defined.ok, true, 'ana teaches "pick 3 items" through the define panel');
    await shot(ana, opt.artifacts, 'users-1-ana-defined');

    // ana uses it right away: at (7,4) lie four items (§10); she picks three of them.
    let a = await query(ana, 'visit [7, 4]');
    await accept(ana);
    a = await query(ana, 'pick 3 items');
    equal(a.status, 'induced', 'ana\'s phrase parses for ana');
    await waitAnimation(ana);
    await accept(ana);
    await ana.waitForFunction(() => window.flipperStudio.state.world.robot.holding.length === 3);
    equal((await robot(ana)).holding.length, 3, 'accepting "pick 3 items" at (7,4) leaves the robot holding 3 items');

    // bob sees it (shared), uses it, but cannot delete it.
    a = await query(bob, 'drop 2 items');
    equal(a.status, 'induced', 'in shared mode bob\'s "drop 2 items" parses with ana\'s rule');
    equal(a.candidates[0].authors, ['ana'], 'the reading names ana as its author');
    await bob.click('[data-testid=rules-search]');
    await bob.waitForSelector('[data-testid=rules] li[data-rule]');
    const rows = await ruleRows(bob);
    check(rows.length >= 1 && rows.every((r) => r.author.includes('by ana') && !r.deletable),
      'bob\'s sidebar lists ana\'s rules, with delete greyed out', JSON.stringify(rows));
    await bob.fill('[data-testid=rules-search]', 'zzz');
    equal((await ruleRows(bob)).length, 0, 'searching the sidebar filters the rules');
    await bob.fill('[data-testid=rules-search]', '');
    await shot(bob, opt.artifacts, 'users-2-bob-sees-ana');
    const id = defined.rules[0].id;
    const refused = await bob.evaluate((rule) => window.flipperStudio.deleteRule(rule), id);
    equal(refused.error?.code, 'forbidden', 'bob\'s delete of ana\'s rule is refused');
    // ana deletes her own rule from the sidebar.
    await ana.click('[data-testid=rules-search]');
    const del = ana.waitForResponse((r) => r.request().postData()?.includes('"op":"delete_rule"'));
    await ana.click(`[data-testid=rules] li[data-rule="${id}"] button.delete`);
    equal((await del.then((r) => r.json())).ok, true, 'ana deletes her rule from the sidebar');
    equal(ana.jsErrors.concat(bob.jsErrors), [], 'no JavaScript errors on either page');
  } finally {
    await browser?.close();
    await server.stop();
  }

  // ---- private mode ------------------------------------------------------------------------------
  server = await startServer(opt.flipper, ['lexicon.sharing=private']);
  browser = null;
  try {
    browser = await anaAndBob(server);
    const { ana, bob } = browser;
    equal((await teach(ana, 'pick 3 items', ['repeat 3 times pick item'])).ok, true, 'ana teaches in private mode');
    equal((await query(ana, 'drop 2 items')).status, 'induced', 'ana uses her own phrase');
    const a = await query(bob, 'drop 2 items');
    equal(a.status, 'unparsable', 'in private mode bob cannot use ana\'s phrase');
    await bob.click('[data-testid=rules-search]');
    const rules = await bob.evaluate(() => window.flipperStudio.api.request({ op: 'rules' }));
    equal(rules.rules.length, 0, 'in private mode bob sees none of ana\'s rules');
    await shot(bob, opt.artifacts, 'users-3-private-bob');
    // ana logs out: the page is a guest's again.
    await Promise.all([ana.waitForNavigation(), ana.click('[data-testid=logout]')]);
    await ana.waitForFunction(() => document.body.dataset.ready === 'true');
    check((await ana.textContent('[data-testid=who]')).startsWith('guest-'), 'after logging out ana is a guest');
  } finally {
    await browser?.close();
    await server.stop();
  }
});
