// Flipper Studio: type a command, flip through its readings as animated plans, accept one, teach
// the phrases Flipper does not understand. Everything goes through the session protocol.
import { Api } from './api.js';
import { MapView, drawShape, worldGeometry } from './map.js';
import { EXAMPLES } from './help.js';
import { DefinePanel } from './define.js';
import { suggest } from './suggest.js';

const $ = (id) => document.getElementById(id);

const state = {
  info: null,
  world: null, // the session's current world
  startWorld: null, // for "Reset world"
  history: [], // worlds before each accept, for "Undo"
  query: null, // {text, answer}
  selected: 0,
  cancelAnimation: null,
  user: '',
  rules: [],
  taskIndex: -1,
  ready: false,
};

const api = new Api(new URLSearchParams(location.search).get('group') || '');
const map = new MapView($('map'));
const goalMap = new MapView($('goal-map'));
map.onFloorChange = () => renderFloors();

function toast(text) {
  const t = $('toast');
  t.textContent = text;
  t.classList.add('show');
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => t.classList.remove('show'), 2600);
}

function showError(el, error) {
  if (!error) {
    el.hidden = true;
    el.textContent = '';
    return;
  }
  el.hidden = false;
  el.innerHTML = '';
  const code = document.createElement('code');
  code.textContent = error.code;
  el.append(code, ' ', error.message);
}

// ---- world ---------------------------------------------------------------------------------

function setWorld(world, { animate = false } = {}) {
  state.world = world;
  map.setWorld(world);
  renderFloors();
  map.draw(world);
  renderHolding(world);
  updateCaption();
}

function renderFloors() {
  const el = $('floor-select');
  const geo = map.geo;
  el.innerHTML = '';
  el.hidden = !(geo && geo.dims === 3);
  if (el.hidden) return;
  for (const z of geo.floors) {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = `z = ${z}`;
    b.className = z === map.floor ? 'active' : '';
    b.dataset.testid = `floor-${z}`;
    b.onclick = () => {
      map.floor = z;
      renderFloors();
      redraw();
    };
    el.append(b);
  }
}

function updateCaption() {
  const cand = currentCandidate();
  const preview = cand && !cand.error;
  const r = preview ? cand.world.robot : state.world?.robot;
  if (!r) return;
  const pos = r.z !== undefined ? `[${r.x}, ${r.y}, ${r.z}]` : `[${r.x}, ${r.y}]`;
  const floor = map.geo?.dims === 3 ? ` · showing floor z = ${map.floor}` : '';
  const held = (r.holding || []).length;
  $('map-caption').textContent = preview
    ? `Preview of reading ${state.selected + 1}: the robot ends at ${pos} holding ${held} item(s)${floor}`
    : `Robot at ${pos}, holding ${held} item(s)${floor}`;
}

function renderHolding(world) {
  const el = $('holding');
  el.innerHTML = '';
  const held = world?.robot?.holding || [];
  const label = document.createElement('span');
  label.textContent = held.length ? 'Holding:' : 'Holding nothing';
  el.append(label);
  for (const it of held) {
    const c = document.createElement('canvas');
    c.width = 22;
    c.height = 22;
    c.title = `${it.color} ${it.shape}`;
    drawShape(c.getContext('2d'), it.shape, it.color, 11, 11, 8);
    el.append(c);
  }
}

function redraw() {
  const cand = currentCandidate();
  if (cand && !cand.error) {
    const start = [state.world.robot.x, state.world.robot.y, state.world.robot.z ?? 0];
    map.draw(cand.world, { trace: cand.trace, upTo: cand.trace.length, start, ok: cand.realizable });
  } else map.draw(state.world);
  updateCaption();
}

// ---- queries and candidates ------------------------------------------------------------------

function currentCandidate() {
  return state.query?.answer?.candidates?.[state.selected] ?? null;
}

async function runQuery(text) {
  showError($('query-error'), null);
  renderSuggestions(text);
  const answer = await api.request({ op: 'query', text });
  if (!answer.ok) {
    state.query = null;
    renderCandidates();
    showError($('query-error'), answer.error);
    return answer;
  }
  state.query = { text, answer };
  state.selected = 0;
  renderCandidates();
  refreshRules(); // others may have taught phrases since (shared mode)
  if (answer.status === 'unparsable') {
    showError($('query-error'), {
      code: 'unparsable',
      message: `Flipper does not understand "${text}" yet. Teach it below.`,
    });
    definePanel.open(text);
  } else {
    selectCandidate(0);
  }
  return answer;
}

function renderCandidates() {
  const list = $('candidates');
  list.innerHTML = '';
  const cands = state.query?.answer?.candidates || [];
  $('candidates-panel').hidden = !state.query || cands.length === 0;
  cands.forEach((c, i) => {
    const li = document.createElement('li');
    li.tabIndex = -1;
    li.dataset.rank = i;
    li.className = i === state.selected ? 'selected' : '';
    li.setAttribute('aria-selected', i === state.selected);
    const formula = document.createElement('code');
    formula.textContent = c.formula;
    const meta = document.createElement('div');
    meta.className = 'meta';
    const badges = [];
    badges.push(c.induced ? `taught by ${c.authors.join(', ')}` : 'core');
    if (c.error) badges.push(`error: ${c.error.code ?? c.error}`);
    else badges.push(c.realizable ? 'realizable' : 'not fully realizable');
    badges.push(`${(c.prob * 100).toFixed(0)}%`);
    for (const b of badges) {
      const s = document.createElement('span');
      s.className = 'badge';
      s.textContent = b;
      meta.append(s);
    }
    li.append(formula, meta);
    li.onclick = () => selectCandidate(i);
    li.ondblclick = () => accept();
    list.append(li);
  });
}

function describeTrace(c) {
  if (c.error) return typeof c.error === 'object' ? `${c.error.code}: ${c.error.message}` : String(c.error);
  const moves = c.trace.filter((s) => s.act === 'move').length;
  const picks = c.trace.filter((s) => s.act === 'pick').map((s) => `${s.item.color} ${s.item.shape}`);
  const drops = c.trace.filter((s) => s.act === 'drop').map((s) => `${s.item.color} ${s.item.shape}`);
  const parts = [`${moves} step${moves === 1 ? '' : 's'}`];
  if (picks.length) parts.push(`picks ${picks.join(', ')}`);
  if (drops.length) parts.push(`drops ${drops.join(', ')}`);
  if (!picks.length && !drops.length && !moves) parts.push('does nothing');
  return parts.join(' · ');
}

function selectCandidate(i) {
  const cands = state.query?.answer?.candidates || [];
  if (!cands.length) return;
  state.selected = (i + cands.length) % cands.length;
  for (const li of $('candidates').children) {
    const on = Number(li.dataset.rank) === state.selected;
    li.classList.toggle('selected', on);
    li.setAttribute('aria-selected', on);
    if (on) li.scrollIntoView({ block: 'nearest' });
  }
  const c = cands[state.selected];
  const detail = $('candidate-detail');
  detail.innerHTML = '';
  const p = document.createElement('p');
  p.textContent = describeTrace(c);
  detail.append(p);
  for (const w of c.warnings || []) {
    const warn = document.createElement('p');
    warn.className = 'warning';
    warn.textContent = `⚠ ${w}`;
    detail.append(warn);
  }
  $('accept').disabled = Boolean(c.error);
  state.cancelAnimation?.();
  state.animating = true;
  document.body.dataset.animating = 'true';
  if (c.error) {
    map.draw(state.world);
    state.animating = false;
    document.body.dataset.animating = 'false';
    return;
  }
  state.cancelAnimation = map.animate(state.world, c.trace, c.world, c.realizable, () => {
    state.animating = false;
    document.body.dataset.animating = 'false';
    updateCaption();
  });
}

async function accept() {
  const c = currentCandidate();
  if (!c || c.error) return;
  const before = state.world;
  const answer = await api.request({ op: 'accept', rank: state.selected });
  if (!answer.ok) {
    showError($('query-error'), answer.error);
    return;
  }
  state.cancelAnimation?.();
  state.history.push(before);
  state.query = null;
  renderCandidates();
  setWorld(answer.world);
  for (const w of answer.warnings || []) toast(`⚠ ${w}`);
  $('query-input').value = '';
  $('query-input').focus();
  refreshRules();
}

function reject() {
  state.cancelAnimation?.();
  const text = state.query?.text;
  state.query = null;
  renderCandidates();
  setWorld(state.world);
  if (text) {
    toast('None of the readings was right: teach Flipper what you meant.');
    definePanel.open(text);
  }
}

async function replaceWorld(world) {
  const answer = await api.request({ op: 'world', world });
  if (!answer.ok) {
    toast(`${answer.error.code}: ${answer.error.message}`);
    return false;
  }
  state.cancelAnimation?.();
  state.query = null;
  renderCandidates();
  setWorld(answer.world);
  return true;
}

async function undo() {
  if (!state.history.length) {
    toast('Nothing to undo');
    return;
  }
  const prev = state.history.pop();
  if (!(await replaceWorld(prev))) state.history.push(prev);
}

async function reset() {
  if (state.startWorld && (await replaceWorld(state.startWorld))) state.history = [];
}

// ---- "did you mean" ----------------------------------------------------------------------------

function vocabulary() {
  const words = new Set(state.info?.vocabulary || []);
  for (const name of Object.keys(state.world?.rooms || {})) words.add(name);
  for (const r of state.rules) for (const t of r.rhs || []) if (!t.startsWith('$')) words.add(t);
  return words;
}

function renderSuggestions(text) {
  const el = $('did-you-mean');
  const hints = suggest(text, vocabulary());
  el.hidden = hints.length === 0;
  el.innerHTML = '';
  if (!hints.length) return;
  el.append('Unknown word: ');
  hints.forEach(({ word, best }, i) => {
    if (i) el.append('; ');
    const w = document.createElement('strong');
    w.textContent = word;
    el.append(w);
    if (best) {
      el.append(' — did you mean ');
      const b = document.createElement('button');
      b.type = 'button';
      b.className = 'link';
      b.textContent = best;
      b.onclick = () => {
        const input = $('query-input');
        input.value = input.value.replace(new RegExp(`\\b${word}\\b`), best);
        renderSuggestions(input.value);
        input.focus();
      };
      el.append(b, '?');
    }
  });
}

// ---- rules sidebar -----------------------------------------------------------------------------

async function refreshRules() {
  const answer = await api.request({ op: 'rules' });
  if (!answer.ok) return;
  state.rules = answer.rules;
  renderRules();
}

function renderRules() {
  const q = $('rules-search').value.trim().toLowerCase();
  const list = $('rules');
  list.innerHTML = '';
  const shown = state.rules.filter((r) =>
    !q || [r.head, r.author, r.semantics, (r.rhs || []).join(' ')].join(' ').toLowerCase().includes(q));
  if (!shown.length) {
    const li = document.createElement('li');
    li.className = 'empty';
    li.textContent = state.rules.length ? 'No rule matches.' : 'No taught phrases yet.';
    list.append(li);
  }
  for (const r of shown) {
    const li = document.createElement('li');
    const own = r.author === state.user;
    li.className = own ? 'own' : 'other';
    li.dataset.rule = r.id;
    const head = document.createElement('div');
    head.className = 'rule-head';
    head.textContent = (r.rhs || []).join(' ');
    const sem = document.createElement('code');
    sem.textContent = r.semantics;
    const meta = document.createElement('div');
    meta.className = 'meta';
    meta.textContent = `${r.lhs} · by ${r.author}${own ? ' (you)' : ''} · ${r.how} · used ${r.uses ?? 0}×`;
    const del = document.createElement('button');
    del.type = 'button';
    del.className = 'delete';
    del.textContent = 'Delete';
    del.disabled = !own;
    del.title = own ? 'Delete this rule' : `Only ${r.author} can delete this rule`;
    del.onclick = () => deleteRule(r.id);
    li.append(head, sem, meta, del);
    list.append(li);
  }
}

async function deleteRule(id) {
  const answer = await api.request({ op: 'delete_rule', rule: id });
  if (!answer.ok) toast(`${answer.error.code}: ${answer.error.message}`);
  else toast(`Deleted rule ${id}`);
  refreshRules();
  return answer;
}

// ---- user, worlds, study -----------------------------------------------------------------------

// Over HTTP a session acts as the account logged in (or its guest name); `user` with another
// name is refused (docs/accounts.md).
async function setUser(name) {
  const answer = await api.request({ op: 'user', name });
  if (!answer.ok) toast(`${answer.error.code}: ${answer.error.message}`);
  return answer;
}

function showLogin(show) {
  $('login-form').hidden = !show;
  $('login-guest').hidden = !state.info?.guests || !!state.info?.account;
  if (show) $('login-name').focus();
}

// Logs in (password or code); the page starts again as that account.
async function logIn(credentials) {
  const answer = await api.login(credentials);
  if (!answer.ok) {
    showError($('login-error'), answer.error);
    return answer;
  }
  const url = new URL(location.href);
  url.searchParams.delete('code');
  location.replace(url.toString());
  return answer;
}

function renderStudy() {
  const study = state.info.study;
  if (!study) return;
  $('world-select').parentElement.hidden = true;
  const t = study.tasks[state.taskIndex];
  $('study-banner').hidden = state.taskIndex < 0;
  if (t) {
    $('study-task-title').textContent = `Task ${state.taskIndex + 1} of ${study.tasks.length}: ${t.name}`;
    $('study-task-text').textContent = t.text;
    $('study-next').hidden = state.taskIndex + 1 >= study.tasks.length;
    $('goal-area').hidden = !t.goal;
    if (t.goal) {
      goalMap.setWorld(t.goal);
      goalMap.draw(t.goal);
    }
  }
}

async function startTask(i) {
  const t = state.info.study.tasks[i];
  state.taskIndex = i;
  $('study-tutorial').hidden = true;
  if (await replaceWorld(t.start)) {
    state.startWorld = state.world;
    state.history = [];
  }
  renderStudy();
  $('query-input').focus();
}

async function loadWorldFile(name) {
  const answer = await api.request({ op: 'world', file: name });
  if (!answer.ok) {
    toast(`${answer.error.code}: ${answer.error.message}`);
    return;
  }
  state.query = null;
  renderCandidates();
  state.history = [];
  state.startWorld = answer.world;
  setWorld(answer.world);
}

// ---- wiring ------------------------------------------------------------------------------------

function renderHelp() {
  const dl = $('help-examples');
  for (const [example, meaning] of EXAMPLES) {
    const dt = document.createElement('dt');
    const b = document.createElement('button');
    b.type = 'button';
    b.className = 'link';
    b.textContent = example;
    b.onclick = () => {
      $('query-input').value = example;
      $('query-input').focus();
    };
    dt.append(b);
    const dd = document.createElement('dd');
    dd.textContent = meaning;
    dl.append(dt, dd);
  }
}

function toggleHelp(force) {
  const help = $('help');
  help.hidden = force === undefined ? !help.hidden : !force;
  $('help-toggle').setAttribute('aria-expanded', String(!help.hidden));
}

const definePanel = new DefinePanel({
  api,
  onDefined: (answer) => {
    refreshRules();
    const text = $('query-input').value.trim();
    if (text && answer.ok) runQuery(text);
  },
});

function wire() {
  $('query-form').onsubmit = (e) => {
    e.preventDefault();
    const text = $('query-input').value.trim();
    if (text) runQuery(text);
  };
  $('query-input').addEventListener('input', (e) => {
    if (!e.target.value.trim()) $('did-you-mean').hidden = true;
  });
  $('accept').onclick = accept;
  $('reject').onclick = reject;
  $('teach').onclick = () => definePanel.open(state.query?.text || $('query-input').value.trim());
  $('undo').onclick = undo;
  $('reset').onclick = reset;
  $('rules-search').oninput = renderRules;
  $('rules-search').onfocus = refreshRules;
  // Others' phrases appear without a reload (shared mode); cheap: one `rules` request.
  setInterval(() => document.visibilityState === 'visible' && state.ready && refreshRules(), 10000);
  $('login-open').onclick = () => showLogin(true);
  $('login-guest').onclick = () => showLogin(false);
  $('logout').onclick = async () => {
    await api.logout();
    location.reload();
  };
  $('login-form').onsubmit = (e) => {
    e.preventDefault();
    logIn({ name: $('login-name').value.trim(), password: $('login-password').value });
  };
  $('login-code-submit').onclick = () => logIn({ code: $('login-code').value.trim() });
  $('help-toggle').onclick = () => toggleHelp();
  $('world-select').onchange = (e) => loadWorldFile(e.target.value);
  $('study-start').onclick = () => startTask(0);
  $('study-next').onclick = () => startTask(state.taskIndex + 1);
  document.addEventListener('keydown', (e) => {
    const inDefine = e.target.closest?.('#define-panel');
    if (e.key === 'F1') {
      e.preventDefault();
      toggleHelp();
    } else if (inDefine) {
      return;
    } else if ((e.key === 'ArrowDown' || e.key === 'ArrowUp') && state.query?.answer?.candidates?.length) {
      e.preventDefault();
      selectCandidate(state.selected + (e.key === 'ArrowDown' ? 1 : -1));
    } else if (e.key === 'Enter' && (e.ctrlKey || e.metaKey) && state.query) {
      e.preventDefault();
      accept();
    } else if (e.key === 'Escape') {
      if (!$('help').hidden) toggleHelp(false);
      else if (state.query) reject();
    } else if (e.key === 'z' && (e.ctrlKey || e.metaKey) && e.target.tagName !== 'INPUT') {
      e.preventDefault();
      undo();
    }
  });
  window.addEventListener('resize', redraw);
}

async function main() {
  wire();
  renderHelp();
  // Who we are first: a code in the link logs in; a server without guests asks for a login.
  state.info = await api.info();
  const code = new URLSearchParams(location.search).get('code');
  if (code && !state.info.account) {
    await logIn({ code });
    return;
  }
  if (!state.info.account && !state.info.guests) {
    showLogin(true);
    document.body.dataset.ready = 'login';
    return;
  }
  // The first request makes (or resumes) the session; its answer is the current world.
  const st = await api.request({ op: 'state' });
  state.info = await api.info();
  const who = await api.request({ op: 'rules' });
  $('sharing').textContent = `${state.info.study?.sharing ?? state.info.sharing} lexicon`;
  const select = $('world-select');
  const current = document.createElement('option');
  current.value = '';
  current.textContent = '(start world)';
  current.disabled = true;
  select.append(current);
  for (const w of state.info.worlds) {
    const o = document.createElement('option');
    o.value = w;
    o.textContent = w.replace(/\.json$/, '');
    select.append(o);
  }
  setWorld(st.world);
  state.startWorld = st.world;
  select.value = '';
  // The session's user: the account logged in, or the guest name the server gave it.
  state.user = api.user;
  $('who').textContent = state.user;
  $('login-open').hidden = !!state.info.account;
  $('logout').hidden = !state.info.account;
  if (who.ok) {
    state.rules = who.rules;
    renderRules();
  }
  if (state.info.study) {
    $('study-tutorial-text').textContent = state.info.study.tutorial || 'Follow the tasks shown at the top.';
    $('study-tutorial').hidden = false;
    renderStudy();
  }
  state.ready = true;
  document.body.dataset.ready = 'true';
  $('query-input').focus();
}

// Exposed for the browser tests and the curious.
window.flipperStudio = { state, api, map, runQuery, selectCandidate, accept, setUser, deleteRule, logIn };
main();
