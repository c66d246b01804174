// The researcher's view of a study (docs/studio.md §7): who takes part, their group and task,
// counts so far, the recording's files, and closing the study to new participants. Needs an
// administrator's login (the HttpOnly cookie of POST /api/v1/login); refreshed every 5 s.
const $ = (id) => document.getElementById(id);
const COUNTS = ['q', 'accept', 'reject', 'def', 'delete', 'undo', 'reset'];
let open = true;

function showError(text) {
  $('error').textContent = text;
  $('error').hidden = !text;
}

function cell(row, text, cls) {
  const td = document.createElement('td');
  td.textContent = text;
  if (cls) td.className = cls;
  row.append(td);
}

// Ends every login of a participant (docs/studio.md §7 "Shared computers"): the computer they
// used takes the next participant at its next request.
function endButton(participant) {
  const td = document.createElement('td');
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = 'Next participant';
  b.title = `End ${participant}'s logins: their computer starts the next participant`;
  b.dataset.testid = `researcher-end-${participant}`;
  b.addEventListener('click', async () => {
    const res = await fetch('/api/v1/study/end', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ participant }),
    });
    const a = await res.json().catch(() => ({}));
    if (a.ok) b.textContent = 'ended';
    else showError(a.error?.message ?? `HTTP ${res.status}`);
  });
  td.append(b);
  return td;
}

function render(o) {
  open = o.study.open;
  $('study-name').textContent = o.study.name;
  $('study-state').textContent = open ? 'open to new participants' : 'closed to new participants';
  $('study-state').classList.toggle('closed', !open);
  $('close').textContent = open ? 'Close the study' : 'Reopen the study';
  $('close').hidden = false;
  const body = $('participants');
  body.replaceChildren();
  for (const p of o.participants) {
    const tr = document.createElement('tr');
    tr.dataset.participant = p.participant;
    cell(tr, p.participant);
    cell(tr, p.group);
    cell(tr, p.task < 0 ? 'tutorial' : `${p.task + 1}: ${p.task_name}`);
    cell(tr, p.goal_reached ? 'reached' : '');
    cell(tr, p.online ? 'online' : '', p.online ? 'online' : '');
    cell(tr, p.last_seen.replace('T', ' '));
    for (const k of COUNTS) cell(tr, String(p.counts[k] ?? 0), 'num');
    tr.append(endButton(p.participant));
    body.append(tr);
  }
  const files = $('files');
  files.replaceChildren();
  for (const f of o.files) {
    const li = document.createElement('li');
    const a = document.createElement('a');
    a.href = `/api/v1/study/recording/${encodeURIComponent(f.name)}`;
    a.download = f.name;
    a.textContent = f.name;
    a.dataset.testid = `researcher-download-${f.name.split('.')[0]}`;
    li.append(a, ` (${f.bytes} bytes)`);
    files.append(li);
  }
  $('view').hidden = false;
  $('login').hidden = true;
  document.body.dataset.ready = 'true';
  document.dispatchEvent(new Event('researcher-view')); // researcher-lexicon.js follows
}

async function refresh() {
  const res = await fetch('/api/v1/study/overview');
  const o = await res.json().catch(() => ({ ok: false, error: { message: `HTTP ${res.status}` } }));
  if (res.status === 401) {
    $('login').hidden = false;
    $('view').hidden = true;
    document.body.dataset.ready = 'true';
    return;
  }
  if (!o.ok) {
    showError(o.error?.message ?? `HTTP ${res.status}`);
    document.body.dataset.ready = 'true';
    return;
  }
  showError('');
  render(o);
}

$('login').addEventListener('submit', async (e) => {
  e.preventDefault();
  const res = await fetch('/api/v1/login', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ name: $('login-name').value, password: $('login-password').value }),
  });
  const a = await res.json().catch(() => ({}));
  if (!a.ok) return showError(a.error?.message ?? 'the login failed');
  showError('');
  refresh();
});

$('close').addEventListener('click', async () => {
  const res = await fetch('/api/v1/study/close', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ open: !open }),
  });
  const o = await res.json().catch(() => ({}));
  if (o.ok) render(o);
  else showError(o.error?.message ?? `HTTP ${res.status}`);
});

// A one-time code link: a participant resumes on another device, or a new name joins.
$('invite').addEventListener('submit', async (e) => {
  e.preventDefault();
  const res = await fetch('/api/v1/study/invite', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ participant: $('invite-name').value.trim() }),
  });
  const a = await res.json().catch(() => ({}));
  if (!a.ok) return showError(a.error?.message ?? `HTTP ${res.status}`);
  showError('');
  $('invite-url').textContent = `${location.origin}${a.url}`;
});

refresh();
setInterval(refresh, 5000);
