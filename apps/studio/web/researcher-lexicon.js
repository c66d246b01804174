// The researcher's lexicon section (docs/studio.md §7 "Lexicon"): a study group's lexicon
// history, newest first, and the definitions held for approval (lexicon.moderation: hold_new,
// docs/naturalization.md §5 "Moderation") with approve and reject. Same login as the rest of the
// page; refreshed with it every 5 s.
const $ = (id) => document.getElementById(id);

function showError(text) {
  $('error').textContent = text;
  $('error').hidden = !text;
}

function utc(seconds) {
  return new Date(seconds * 1000).toISOString().replace('T', ' ').replace('.000Z', 'Z');
}

function ruleText(r) {
  return `${r.lhs} -> ${r.rhs.join(' ')} := ${r.semantics}`;
}

async function decide(action, id, reason) {
  const group = $('lexicon-group').value;
  const res = await fetch(`/api/v1/study/lexicon/${action}`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(reason ? { group, id, reason } : { group, id }),
  });
  const a = await res.json().catch(() => ({}));
  if (!a.ok) return showError(a.error?.message ?? `HTTP ${res.status}`);
  showError('');
  refresh();
}

function button(text, testid, onClick) {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = text;
  b.dataset.testid = testid;
  b.addEventListener('click', onClick);
  return b;
}

function renderPending(pending) {
  const list = $('lexicon-pending');
  list.replaceChildren();
  if (pending.length === 0) {
    const li = document.createElement('li');
    li.textContent = 'nothing held';
    list.append(li);
  }
  for (const h of pending) {
    const li = document.createElement('li');
    li.dataset.held = h.id;
    li.append(`${h.id} ${h.author} (${utc(h.time)}): '${h.head}' := '${h.body.join('; ')}' `);
    li.append(button('Approve', `researcher-approve-${h.id}`, () => decide('approve', h.id)));
    li.append(' ');
    li.append(
      button('Reject', `researcher-reject-${h.id}`, () =>
        decide('reject', h.id, window.prompt(`Why reject '${h.head}'? (optional)`) ?? ''),
      ),
    );
    const rules = document.createElement('ul');
    for (const r of h.rules) {
      const item = document.createElement('li');
      item.textContent = ruleText(r);
      rules.append(item);
    }
    li.append(rules);
    list.append(li);
  }
}

function renderHistory(a) {
  const list = $('lexicon-history');
  list.replaceChildren();
  list.start = a.history_total;
  for (const e of a.history) {
    const li = document.createElement('li');
    li.dataset.action = e.action;
    let text = `${utc(e.time)} ${e.author} ${e.action}`;
    if (e.rule) text += ` ${e.effect === 'remove' ? '-' : '+'}${e.rule}`;
    if (e.head) text += ` '${e.head}'`;
    if (e.note) text += ` [${e.note}]`;
    li.textContent = text;
    list.append(li);
  }
  $('lexicon-total').textContent = `(${a.history.length} of ${a.history_total} entries)`;
}

async function refresh() {
  const select = $('lexicon-group');
  if (!select.value) {
    const res = await fetch('/api/v1/study/overview');
    if (!res.ok) return; // not logged in yet: researcher.js shows the login
    const o = await res.json();
    for (const g of o.study.groups) {
      const option = document.createElement('option');
      option.value = g;
      option.textContent = `group ${g}`;
      select.append(option);
    }
  }
  const res = await fetch(`/api/v1/study/lexicon?group=${encodeURIComponent(select.value)}`);
  const a = await res.json().catch(() => ({}));
  if (!a.group) return;
  $('lexicon-moderation').textContent =
    a.moderation === 'hold_new' ? 'new definitions wait for approval' : 'no moderation';
  renderPending(a.pending);
  renderHistory(a);
  document.body.dataset.lexiconReady = 'true';
}

$('lexicon-group').addEventListener('change', refresh);
// After a login (and each refresh of the overview): the group list needs the researcher's login.
let loaded = false;
document.addEventListener('researcher-view', () => {
  if (!loaded) refresh();
  loaded = true;
});
setInterval(() => loaded && refresh(), 5000);
