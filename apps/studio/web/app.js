// Flipper Studio: type a command, flip through its readings as animated plans, accept one, teach
// the phrases Flipper does not understand. Everything goes through the session protocol.
import { Api } from './api.js';
import { MapView, drawShape, worldGeometry } from './map.js';
import { EXAMPLES } from './help.js';
import { DefinePanel } from './define.js';
import { HistoryPanel } from './history.js';
import { ruleView } from './rule-view.js';
import { suggest } from './suggest.js';

const $ = (id) => document.getElementById(id);

const state = {
  info: null,
  world: null, // the session's current world
  startWorld: null, // for "Reset world" (a study: the task's start)
  history: [], // the accepted steps since startWorld: {qid?, utterance, formula, world, steps?}
  query: null, // {text, answer}
  lastUnsaid: '', // the last text not understood or rejected: the head a history define suggests
  selected: 0,
  cancelAnimation: null,
  user: '',
  rules: [],
  taskIndex: -1,
  goalReached: false,
  teaching: true, // false for a study group that cannot teach (the core-lexicon condition)
  ready: false,
};

const NO_TEACHING = 'Flipper cannot learn new phrases in this study: say it with words it knows (Help, F1).';
const POINTS_3D = 'Points are [x, y] on the robot\'s floor; change floor with move ascend / move descend, '
  + 'or visit a room on that floor.';

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

// `follow`: show the robot's floor (after an accept, undo, reset or a new world); the floor also
// follows when the robot changed floor.
function setWorld(world, { follow = false } = {}) {
  const previousZ = state.world?.robot?.z;
  state.world = world;
  map.setWorld(world);
  const z = world.robot?.z;
  if (map.geo?.dims === 3 && z !== undefined && (follow || z !== previousZ)) map.floor = z;
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

// A query. `why` marks the page's own queries for a study's recording (docs/studio.md "Study
// annotations"): "rerun" after a definition; a participant's query has none.
async function runQuery(text, { why = '' } = {}) {
  showError($('query-error'), null);
  $('did-you-mean').hidden = true;
  renderRepair(text, null);
  showPreview(null);
  // A participant's failure says how to repair it (docs/protocol.md "Repairs"; other answers are
  // unchanged); the page's own re-runs need none.
  const request = { op: 'query', text };
  if (why) request.studio = { why };
  else request.repair = true;
  const answer = await api.request(request);
  if (!answer.ok) {
    state.query = null;
    renderCandidates();
    showError($('query-error'), answer.error);
    return answer;
  }
  state.query = { text, answer };
  state.selected = 0;
  renderCandidates();
  await renderSuggestions(text, answer);
  refreshRules(); // others may have taught phrases since (shared mode)
  if (answer.status === 'unparsable') {
    state.lastUnsaid = text;
    const points3d = map.geo?.dims === 3 && /\[\s*-?\d+\s*,\s*-?\d+\s*,\s*-?\d+\s*\]/.test(text);
    const message = state.teaching
      ? `Flipper does not understand "${text}" yet. Teach it below.`
      : `Flipper does not understand "${text}". ${NO_TEACHING}`;
    showError($('query-error'), { code: 'unparsable', message: points3d ? `${message} ${POINTS_3D}` : message });
    if (state.teaching) definePanel.open(text);
    renderRepair(text, answer.repair);
  } else {
    // A finished definition (or an empty panel) gives way to the new query's readings.
    if (!why && definePanel.isOpen && !definePanel.hasWork()) definePanel.close();
    selectCandidate(0, { user: false });
  }
  return answer;
}

// The define panel's live checks replace the session's last query: the readings shown for an
// earlier query could no longer be accepted (accept names a rank of the last query).
function dropCandidates() {
  if (!state.query) return;
  state.cancelAnimation?.();
  state.query = null;
  renderCandidates();
  redraw();
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

// `user`: the participant flipped to this reading (a study records which one was shown).
function selectCandidate(i, { user = true } = {}) {
  const cands = state.query?.answer?.candidates || [];
  if (!cands.length) return;
  state.selected = (i + cands.length) % cands.length;
  showPreview(null);
  if (user) {
    api.event('flip', { rank: state.selected, formula: cands[state.selected].formula });
    renderSuggestions(state.query.text, state.query.answer);
  }
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
  // Why a reading cannot be done here, and the nearest one that can (docs/protocol.md "Repairs").
  const why = state.query.answer.repair?.unrealizable?.find((u) => u.rank === c.rank);
  if (why) {
    const p = document.createElement('p');
    p.dataset.testid = 'candidate-why';
    const step = document.createElement('code');
    step.textContent = why.step;
    p.append('Cannot be done here: ', step, ` fails at [${why.at.join(',')}]: ${why.why}.`);
    if (why.variant) {
      const v = document.createElement('code');
      v.textContent = why.variant.formula;
      p.append(' Nearest that works: ', v, ` (${why.variant.edit}).`);
    } else {
      p.append(` No variant found (${why.tried} tried).`);
    }
    detail.append(p);
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
  const text = state.query.text;
  const answer = await api.request({ op: 'accept', rank: state.selected });
  if (!answer.ok) {
    showError($('query-error'), answer.error);
    return;
  }
  state.cancelAnimation?.();
  state.history.push({ utterance: text, formula: c.formula, world: answer.world });
  state.query = null;
  renderCandidates();
  setWorld(answer.world, { follow: true });
  if (answer.headers?.get('Flipper-Goal') === 'reached') state.goalReached = true;
  renderHistory();
  renderStudy();
  for (const w of answer.warnings || []) toast(`⚠ ${w}`);
  $('query-input').value = '';
  $('did-you-mean').hidden = true;
  $('query-input').focus();
  refreshRules();
}

function reject() {
  state.cancelAnimation?.();
  const text = state.query?.text;
  if (text) api.event('reject');
  state.query = null;
  renderCandidates();
  setWorld(state.world);
  if (!text) return;
  state.lastUnsaid = text;
  if (state.teaching) {
    toast('None of the readings was right: teach Flipper what you meant.');
    definePanel.open(text);
  } else showError($('query-error'), { code: 'rejected', message: `None of the readings was right. ${NO_TEACHING}` });
}

// Replaces the session's world; `why` annotates it for a study's recording (undo, reset,
// task_start) and `task` names the task started.
async function replaceWorld(world, why = '', task = undefined) {
  const request = { op: 'world', world };
  if (why) request.studio = task === undefined ? { why } : { why, task };
  const answer = await api.request(request);
  if (!answer.ok) {
    toast(`${answer.error.code}: ${answer.error.message}`);
    return false;
  }
  state.cancelAnimation?.();
  state.query = null;
  renderCandidates();
  showPreview(null);
  setWorld(answer.world, { follow: true });
  return true;
}

// The world before step i of the history.
function worldBefore(i) {
  return i > 0 ? state.history[i - 1].world : state.startWorld;
}

async function undo() {
  if (!state.history.length) {
    toast('Nothing to undo');
    return;
  }
  const last = state.history.length - 1;
  if (await replaceWorld(worldBefore(last), 'undo')) {
    state.history.pop();
    renderHistory();
  }
}

async function reset() {
  if (state.startWorld && (await replaceWorld(state.startWorld, 'reset'))) {
    state.history = [];
    renderHistory();
  }
}

// ---- history -----------------------------------------------------------------------------------

// Keeps the page's place for a reload (the server's info.study, when it has it, wins; README
// "Flipper Studio").
function persist() {
  const saved = state.info?.study
    ? { task: state.taskIndex, goal_reached: state.goalReached, history: state.history }
    : { start: state.startWorld, history: state.history };
  try {
    sessionStorage.setItem(state.info?.study ? 'flipper.study' : 'flipper.history', JSON.stringify(saved));
  } catch {
    // a full storage only costs the restore after a reload
  }
}

function renderHistory() {
  historyPanel.render(state.history, { teaching: state.teaching && definePanel.formulaLines });
  persist();
}

// Shows the world after step i on the map (null: the current world again).
function showPreview(i) {
  if (i === null || i === undefined) {
    if (document.body.dataset.preview === undefined) return;
    delete document.body.dataset.preview;
    if (historyPanel.preview !== null) historyPanel.showPreview(null);
    map.setWorld(state.world);
    renderFloors();
    redraw();
    return;
  }
  const world = state.history[i].world;
  state.cancelAnimation?.();
  document.body.dataset.preview = String(i + 1);
  map.setWorld(world);
  if (map.geo?.dims === 3 && world.robot.z !== undefined) map.floor = world.robot.z;
  renderFloors();
  map.draw(world);
  $('map-caption').textContent = `World after step ${i + 1} — click it again or press Esc to return`;
}

// A phrase taught from steps from..to: they collapse into one step (the world does not change).
function collapseHistory([from, to], head) {
  const part = state.history.slice(from, to + 1);
  state.history.splice(from, part.length, {
    utterance: head,
    formula: `{${part.map((s) => s.formula).join(';')}}`,
    world: part[part.length - 1].world,
    steps: part,
  });
  historyPanel.range = null;
  renderHistory();
}

// ---- repairs (docs/protocol.md "Repairs") -------------------------------------------------------

// What Flipper understood of an unparsable sentence, the words it did not, the nearest sentences
// it understands (a click runs one) and, when the page teaches, the definition that teaches it
// (a click fills the define panel's steps).
function renderRepair(text, repair) {
  const el = $('repair');
  el.innerHTML = '';
  el.hidden = !repair;
  if (!repair) return;
  const row = (label, testid) => {
    const div = document.createElement('div');
    div.dataset.testid = testid;
    div.append(label);
    el.append(div);
    return div;
  };
  if (repair.understood.length) {
    const d = row('Understood: ', 'repair-understood');
    repair.understood.forEach((p, i) => {
      const c = document.createElement('code');
      c.textContent = p.text;
      c.title = p.formula;
      d.append(i ? ', ' : '', c);
    });
  }
  if (repair.words.length) {
    const d = row('Not understood: ', 'repair-words');
    repair.words.forEach((w, i) => {
      const b = document.createElement('strong');
      b.textContent = w.word;
      d.append(i ? ', ' : '', b, ` (${w.kind}${w.did_you_mean ? `, did you mean ${w.did_you_mean}?` : ''})`);
    });
  }
  if (repair.nearest.length) {
    const d = row('Nearest sentences Flipper understands: ', 'repair-nearest');
    repair.nearest.forEach((s, i) => {
      const b = document.createElement('button');
      b.type = 'button';
      b.className = 'link';
      b.textContent = s.text;
      b.title = `${s.edit} ⇒ ${s.formula}`;
      b.onclick = () => {
        $('query-input').value = s.text;
        runQuery(s.text);
      };
      d.append(i ? ' · ' : '', b);
    });
  }
  if (repair.teach && state.teaching) {
    const d = row('Teach it as: ', 'repair-teach');
    const b = document.createElement('button');
    b.type = 'button';
    b.className = 'link';
    b.textContent = repair.teach.body.join('; ');
    b.onclick = () => definePanel.open(text, null, repair.teach.body);
    d.append(b);
  }
}

// ---- "did you mean" ----------------------------------------------------------------------------

function vocabulary() {
  const words = new Set(state.info?.vocabulary || []);
  for (const name of Object.keys(state.world?.rooms || {})) words.add(name);
  for (const r of state.rules) for (const t of r.rhs || []) if (!t.startsWith('$')) words.add(t);
  return words;
}

// "Did you mean", from the answer: the words neither the grammar, the rooms nor a visible rule
// knows. The rules of the chosen reading are fetched first when the page does not know one yet
// (another participant's, in a shared group), so a word a taught rule read is never "unknown".
async function renderSuggestions(text, answer) {
  const el = $('did-you-mean');
  const candidate = answer.candidates?.[state.selected];
  const ids = candidate?.induced ? candidate.rules || [] : [];
  if (ids.some((id) => !state.rules.find((r) => r.id === id))) await refreshRules();
  if (state.query?.answer !== answer) return; // a newer query has its own
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
        el.hidden = true;
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
    const meta = document.createElement('div');
    meta.className = 'meta';
    meta.textContent = `by ${r.author}${own ? ' (you)' : ''} · ${r.how} · used ${r.uses ?? 0}×`;
    const del = document.createElement('button');
    del.type = 'button';
    del.className = 'delete';
    del.textContent = 'Delete';
    del.disabled = !own;
    del.title = own ? 'Delete this rule' : `Only ${r.author} can delete this rule`;
    del.onclick = () => deleteRule(r.id);
    li.append(...ruleView(r), meta, del);
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
  const study = state.info?.study;
  if (!study) return;
  $('world-select').parentElement.hidden = true;
  const t = study.tasks[state.taskIndex];
  $('study-banner').hidden = state.taskIndex < 0;
  $('goal-reached').hidden = !state.goalReached;
  if (state.goalReached) $('study-next').dataset.goal = 'reached';
  else delete $('study-next').dataset.goal;
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
  $('study-tutorial').hidden = true;
  if (await replaceWorld(t.start, 'task_start', i)) {
    state.taskIndex = i;
    state.goalReached = false;
    state.startWorld = state.world;
    state.history = [];
    renderHistory();
  }
  renderStudy();
  $('query-input').focus();
}

async function loadWorldFile(name) {
  const select = $('world-select');
  const answer = await api.request({ op: 'world', file: name });
  if (!answer.ok) {
    toast(`${answer.error.code}: ${answer.error.message}`);
    select.value = select.dataset.current ?? '';
    return;
  }
  select.dataset.current = name;
  state.query = null;
  renderCandidates();
  state.history = [];
  state.startWorld = answer.world;
  setWorld(answer.world, { follow: true });
  renderHistory();
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
  toast,
  onLiveCheck: dropCandidates,
  onDefined: (answer, { history, head }) => {
    refreshRules();
    // What was not understood is now taught: its error and hints go.
    showError($('query-error'), null);
    $('did-you-mean').hidden = true;
    if (history) collapseHistory(history, head);
    else {
      // The phrase just taught, read again (marked: not the participant's query).
      $('query-input').value = head;
      runQuery(head, { why: 'rerun' });
    }
  },
});

const historyPanel = new HistoryPanel({
  onPreview: (i) => showPreview(i),
  onTeach: (range) => definePanel.open(state.lastUnsaid, { steps: state.history, range }),
});

// Ctrl+Z undoes the last accepted step, also from the command box when it is empty (with text
// in it, Ctrl+Z is the box's own text undo).
function isUndoKey(e) {
  if (e.key !== 'z' || !(e.ctrlKey || e.metaKey) || e.shiftKey) return false;
  if (e.target.id === 'query-input') return e.target.value === '';
  return !['INPUT', 'TEXTAREA', 'SELECT'].includes(e.target.tagName);
}

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
  $('teach').onclick = () => definePanel.open($('query-input').value.trim() || state.query?.text);
  $('undo').onclick = undo;
  $('kiosk-next').onclick = nextParticipant;
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
      else if (document.body.dataset.preview !== undefined) showPreview(null);
      else if (state.query) reject();
    } else if (isUndoKey(e)) {
      e.preventDefault();
      undo();
    }
  });
  window.addEventListener('resize', redraw);
}

// Robot and items of two worlds (key order aside): is it the same place?
function sameWorld(a, b) {
  const canon = (v) => (Array.isArray(v) ? v.map(canon)
    : v && typeof v === 'object' ? Object.fromEntries(Object.keys(v).sort().map((k) => [k, canon(v[k])])) : v);
  return Boolean(a && b) && JSON.stringify(canon([a.robot, a.items])) === JSON.stringify(canon([b.robot, b.items]));
}

function readSaved(key) {
  try {
    return JSON.parse(sessionStorage.getItem(key) || 'null');
  } catch {
    return null;
  }
}

// After a reload: the task, goal and history from the server's info.study when it keeps them,
// else from this tab's sessionStorage (kept only when it still ends in the session's world).
function restorePlace(world) {
  const study = state.info.study;
  const saved = readSaved(study ? 'flipper.study' : 'flipper.history');
  const fits = (h, start) => sameWorld(h.length ? h[h.length - 1].world : start, world);
  if (!study) {
    const ok = api.reloaded && saved?.start && Array.isArray(saved.history) && fits(saved.history, saved.start);
    state.startWorld = ok ? saved.start : world;
    state.history = ok ? saved.history : [];
    return;
  }
  state.taskIndex = study.task ?? (api.reloaded ? saved?.task : undefined) ?? -1;
  state.goalReached = Boolean(study.goal_reached ?? (api.reloaded && saved?.goal_reached));
  state.startWorld = study.tasks[state.taskIndex]?.start ?? world;
  if (Array.isArray(study.history)) state.history = study.history;
  else if (api.reloaded && Array.isArray(saved?.history) && fits(saved.history, state.startWorld))
    state.history = saved.history;
}

// Kiosk mode (`?kiosk`, a computer participants share; docs/studio.md §7 "Shared computers"):
// this participant's login ends and the page starts over as the next participant.
async function nextParticipant() {
  await fetch('/api/v1/study/next', { method: 'POST' });
  sessionStorage.clear();
  location.reload();
}

// The page a visitor sees when the study no longer takes participants.
function showStudyClosed(study) {
  document.querySelector('main').hidden = true;
  $('study-closed-name').textContent = study?.name ? `"${study.name}"` : 'This study';
  $('study-closed').hidden = false;
  document.body.dataset.ready = 'closed';
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
  if (st.error?.code === 'study_closed') {
    // A closed study takes no new participants (docs/studio.md §7): say so instead of an app
    // that cannot answer; a participant comes back through their own link or login.
    showStudyClosed(state.info.study);
    return;
  }
  state.info = await api.info();
  const who = await api.request({ op: 'rules' });
  const study = state.info.study;
  // A study group without teaching (the core lexicon) is told so instead of a define panel; the
  // condition itself is not shown to participants.
  state.teaching = !study || (study.teaching ?? study.sharing !== 'core');
  // A study server that records page events and formula lines says `teaching`; an older one
  // records string lines only, so the page sends those and offers no define from history.
  api.events = Boolean(study) && 'teaching' in study;
  definePanel.formulaLines = !study || 'teaching' in study;
  $('sharing').hidden = Boolean(study);
  $('sharing').textContent = `${state.info.sharing} lexicon`;
  $('teach').hidden = !state.teaching;
  $('rules-area').hidden = !state.teaching; // a group that cannot teach has no taught phrases
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
  select.value = '';
  select.dataset.current = '';
  restorePlace(st.world);
  setWorld(st.world, { follow: true });
  // The session's user: the account logged in, or the guest name the server gave it.
  state.user = api.user;
  $('who').textContent = state.user;
  $('login-open').hidden = !!state.info.account;
  $('logout').hidden = !state.info.account;
  if (who.ok) {
    state.rules = who.rules;
    renderRules();
  }
  if (study) {
    $('study-tutorial-text').textContent = study.tutorial || 'Follow the tasks shown at the top.';
    $('study-tutorial').hidden = state.taskIndex >= 0;
    renderStudy();
    $('kiosk-next').hidden = !new URLSearchParams(location.search).has('kiosk');
    api.event('page_load', { reloaded: api.reloaded });
  }
  renderHistory();
  state.ready = true;
  document.body.dataset.ready = 'true';
  $('query-input').focus();
}

// Exposed for the browser tests and the curious.
window.flipperStudio = {
  state, api, map, runQuery, selectCandidate, accept, undo, reset, setUser, deleteRule, logIn, historyPanel,
};
main();
