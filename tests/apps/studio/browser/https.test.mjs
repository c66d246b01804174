// The page over HTTPS (docs/serve.md "HTTPS"): `flipper serve` with serve.tls.cert/key from a
// test CA made at test time (tests/apps/studio/make-test-pki), chromium told to accept exactly
// that server key (--ignore-certificate-errors-spki-list; Debian's chromium has no NSS tools to
// trust a CA in a throwaway profile), a login through the page's form whose cookie is Secure,
// and a command answered. A chromium without the key's pin refuses the page.
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import {
  args, check, equal, run, startServer, launchBrowser, openPage, shot, query, addAccount, logIn,
} from './harness.mjs';

const opt = args();

run(async () => {
  const pki = mkdtempSync(join(tmpdir(), 'flipper-test-pki-'));
  const made = spawnSync('bash', [join(opt.root ?? '.', 'tests/apps/studio/make-test-pki'), pki],
    { encoding: 'utf8' });
  if (made.status !== 0) throw new Error(`make-test-pki: ${made.stdout}${made.stderr}`);
  const spki = readFileSync(join(pki, 'server.spki'), 'utf8').trim();
  const server = await startServer(opt.flipper,
    [`serve.tls.cert=${join(pki, 'server.pem')}`, `serve.tls.key=${join(pki, 'server.key')}`]);
  const pinned = await launchBrowser({ extraArgs: [`--ignore-certificate-errors-spki-list=${spki}`] });
  const plain = await launchBrowser();
  try {
    check(server.url.startsWith('https://127.0.0.1:'), 'the server says it listens on https://', server.url);
    addAccount(opt.flipper, server, 'ana', 'ana password');
    const page = await openPage(pinned.context, server.url);
    const main = await page.evaluate(() => ({ secure: window.isSecureContext, protocol: location.protocol }));
    equal(main, { secure: true, protocol: 'https:' }, 'the page is an HTTPS secure context');
    await logIn(page, 'ana', 'ana password');
    const cookies = await pinned.context.cookies(server.url);
    const login = cookies.find((c) => c.name === 'flipper_login');
    equal(login && { secure: login.secure, httpOnly: login.httpOnly, sameSite: login.sameSite },
      { secure: true, httpOnly: true, sameSite: 'Strict' }, 'the login cookie is Secure, HttpOnly, SameSite=Strict');
    const answer = await query(page, 'move left');
    equal(answer.status, 'core', 'a command is answered over HTTPS as ana');
    equal(await page.evaluate(() => window.flipperStudio.state.user), 'ana', 'the page is logged in as ana');
    const info = await page.evaluate(async () => {
      const r = await fetch('/api/v1/info');
      return { csp: r.headers.get('content-security-policy'), nosniff: r.headers.get('x-content-type-options'),
        referrer: r.headers.get('referrer-policy') };
    });
    equal(info, { csp: "default-src 'none'; frame-ancestors 'none'", nosniff: 'nosniff', referrer: 'no-referrer' },
      'API answers carry the CSP, nosniff and Referrer-Policy');
    await shot(page, opt.artifacts, 'https-logged-in');
    check(page.jsErrors.length === 0, 'no script errors on the HTTPS page', page.jsErrors.join('\n'));

    // Without the pin chromium refuses the test CA's certificate: the pin is what lets it in.
    const stranger = await plain.context.newPage();
    let refused = '';
    try {
      await stranger.goto(server.url);
    } catch (e) {
      refused = String(e.message);
    }
    check(refused.includes('ERR_CERT_AUTHORITY_INVALID'), 'a browser that does not trust the test CA refuses the page', refused);
  } finally {
    await pinned.close();
    await plain.close();
    await server.stop();
  }
});
