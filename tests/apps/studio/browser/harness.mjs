// Shared by the browser tests: start `flipper serve` on a free loopback port with a throwaway
// lexicon, launch Debian's chromium through playwright-core with a fresh profile, save
// screenshots as test artefacts, and small assertion helpers that say what differed.
import { spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, mkdirSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);

export function args() {
  const out = {};
  const argv = process.argv.slice(2);
  for (let i = 0; i < argv.length; i += 2) out[argv[i].replace(/^--/, '')] = argv[i + 1];
  for (const k of ['flipper', 'artifacts'])
    if (!out[k]) throw new Error(`usage: node TEST --flipper BIN --artifacts DIR [--root DIR] (missing --${k})`);
  mkdirSync(out.artifacts, { recursive: true });
  return out;
}

let failures = 0;
let checks = 0;
export function check(cond, what, detail = '') {
  checks++;
  if (cond) console.log(`ok   ${what}`);
  else {
    failures++;
    console.log(`FAIL ${what}${detail ? `: ${detail}` : ''}`);
  }
  return cond;
}
export function equal(actual, expected, what) {
  const a = JSON.stringify(actual), e = JSON.stringify(expected);
  return check(a === e, what, `got ${a}, expected ${e}`);
}
export function summary() {
  console.log(`${checks - failures} passed, ${failures} failed`);
  return failures === 0 ? 0 : 1;
}

// Starts the server; resolves to {url, stop, dir, output}. `sets` are --set assignments.
export async function startServer(flipper, sets = [], { dir, cwd, config } = {}) {
  dir ??= mkdtempSync(join(tmpdir(), 'flipper-studio-'));
  const all = ['serve', ...(config ? ['--config', config] : []), '--set', 'serve.host=127.0.0.1', '--set', 'serve.port=0',
    '--set', `lexicon.path=${join(dir, 'lexicon.sqlite')}`, '--set', 'lexicon.preload=',
    ...sets.flatMap((s) => ['--set', s])];
  const proc = spawn(flipper, all, { cwd, stdio: ['ignore', 'pipe', 'pipe'] });
  let output = '';
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`server did not start in 20 s:\n${output}`)), 20000);
    const onData = (d) => {
      output += d;
      const m = output.match(/listening on (https?:\/\/127\.0\.0\.1:\d+\/)/);
      if (m) {
        clearTimeout(timer);
        resolve(m[1]);
      }
    };
    proc.stdout.on('data', onData);
    proc.stderr.on('data', onData);
    proc.on('exit', (code) => reject(new Error(`server exited with ${code}:\n${output}`)));
  });
  const stop = async (signal = 'SIGTERM') => {
    if (proc.exitCode !== null) return;
    const done = new Promise((r) => proc.once('exit', r));
    proc.kill(signal);
    await done;
  };
  // The sets that choose the accounts store, for `flipper accounts` on the same one.
  const accountSets = sets.filter((s) => s.startsWith('serve.study=') || s.startsWith('serve.accounts='));
  return { url, stop, dir, proc, output: () => output, accountSets };
}

// `flipper accounts add NAME` on a server's store (the password on standard input).
export function addAccount(flipper, server, name, password, role = 'user') {
  const r = spawnSync(flipper, ['accounts', 'add', name, '--role', role, '--set',
    `lexicon.path=${join(server.dir, 'lexicon.sqlite')}`, ...server.accountSets.flatMap((s) => ['--set', s])],
  { input: `${password}\n`, encoding: 'utf8' });
  if (r.status !== 0) throw new Error(`flipper accounts add ${name}: ${r.stdout}${r.stderr}`);
}

// Logs a ready page in through the login form; resolves when the page is ready as `name`.
export async function logIn(page, name, password) {
  await page.click('[data-testid=login-open]');
  await page.fill('[data-testid=login-name]', name);
  await page.fill('[data-testid=login-password]', password);
  await Promise.all([page.waitForNavigation(), page.click('[data-testid=login-submit]')]);
  await page.waitForFunction((n) => document.body.dataset.ready === 'true'
    && window.flipperStudio.state.user === n, name, { timeout: 15000 });
}

export const CHROMIUM_FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic',
  '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'];

// A fresh chromium profile per browser; the caller closes it (profile removed then).
// `extraArgs`: more chromium flags (the HTTPS test's certificate pin).
export async function launchBrowser({ extraArgs = [] } = {}) {
  let playwright;
  try {
    playwright = require('playwright-core');
  } catch (e) {
    throw new Error('playwright-core is not installed: run `bash scripts/setup` (npm ci in tests/apps/studio/browser)');
  }
  const profile = mkdtempSync(join(tmpdir(), 'flipper-chromium-'));
  const context = await playwright.chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: [...CHROMIUM_FLAGS, ...extraArgs],
    viewport: { width: 1400, height: 900 },
  });
  const close = async () => {
    await context.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { context, close };
}

// A page with the app loaded and ready.
export async function openPage(context, url) {
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
  await page.goto(url);
  try {
    await page.waitForSelector('body[data-ready=true]', { state: 'attached', timeout: 15000 });
  } catch (e) {
    throw new Error(`the page did not get ready: ${e.message}\npage errors: ${errors.join('\n')}`);
  }
  page.jsErrors = errors;
  return page;
}

export async function shot(page, artifacts, name) {
  const path = join(artifacts, `${name}.png`);
  await page.screenshot({ path, fullPage: true });
  console.log(`     screenshot ${path}`);
}

export async function canvasData(page) {
  return page.evaluate(() => document.getElementById('map').toDataURL());
}

export async function waitAnimation(page) {
  await page.waitForFunction(() => document.body.dataset.animating === 'false', null, { timeout: 15000 });
}

// Types a command and waits for its answer (candidates or an error).
export async function query(page, text) {
  await page.fill('[data-testid=query-input]', text);
  const answer = page.waitForResponse((r) => r.url().includes('/api/v1/request') &&
    r.request().postData()?.includes('"op":"query"'));
  await page.press('[data-testid=query-input]', 'Enter');
  return (await answer).json();
}

// Clicks Accept and waits for the answer (and the page's update of its world).
export async function accept(page) {
  const answer = page.waitForResponse((r) => r.url().includes('/api/v1/request') &&
    r.request().postData()?.includes('"op":"accept"'));
  await page.click('[data-testid=accept]');
  const a = await (await answer).json();
  await page.waitForFunction(() => window.flipperStudio.state.query === null);
  return a;
}

export async function robot(page) {
  return page.evaluate(() => {
    const r = window.flipperStudio.state.world.robot;
    return { x: r.x, y: r.y, holding: r.holding.map((i) => `${i.color} ${i.shape}`) };
  });
}

export async function run(main) {
  try {
    await main();
  } catch (e) {
    check(false, 'the test ran to its end', e.stack || String(e));
  }
  process.exit(summary());
}
