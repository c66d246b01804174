// The session protocol over HTTP (docs/serve.md): one request object per POST, the
// session named by the token the server issued. The token lives in sessionStorage, so a reload
// keeps the session and another tab is another session. Who the session's user is comes from
// the login cookie (HttpOnly: this code never sees it; docs/accounts.md), or the server names a
// guest. Every request and study event goes through one promise chain, so the server sees (and a
// study records) them in the page's order (docs/studio.md "The page").
const KEY = 'flipper.session';

export class Api {
  constructor(group) {
    this.token = sessionStorage.getItem(KEY) || '';
    this.reloaded = Boolean(this.token); // the page had a session before this load
    this.group = group || '';
    this.chain = Promise.resolve();
    this.events = false; // set when the server records study events
  }

  // Runs `task` after everything queued before it; a failure does not break the chain.
  queue(task) {
    const run = this.chain.then(task, task);
    this.chain = run.catch(() => {});
    return run;
  }

  url(path) {
    const params = new URLSearchParams();
    if (this.token) params.set('session', this.token);
    else if (this.group) params.set('group', this.group);
    const q = params.toString();
    return q ? `${path}?${q}` : path;
  }

  remember(res) {
    this.user = res.headers.get('Flipper-User') || this.user || '';
    const token = res.headers.get('Flipper-Session');
    if (token && token !== this.token) {
      this.token = token;
      sessionStorage.setItem(KEY, token);
    }
  }

  // One protocol request; resolves to the answer object (ok true or false). A session the
  // server no longer knows (restart, expiry) is replaced by a new one, once.
  request(req) {
    return this.queue(() => this.send(req));
  }

  async send(req, retried = false) {
    const res = await fetch(this.url('/api/v1/request'), {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(req),
    });
    this.remember(res);
    let answer;
    try {
      answer = await res.json();
    } catch {
      answer = { ok: false, op: req.op, error: { code: 'http_error', message: `HTTP ${res.status}` } };
    }
    // An expired session, or one whose login ended: start a new one, once.
    const gone = answer.error?.code === 'unknown_session' || answer.error?.code === 'login_required';
    if ((res.status === 404 || res.status === 401) && gone && this.token && !retried) {
      this.token = '';
      sessionStorage.removeItem(KEY);
      return this.send(req, true);
    }
    // The reply's headers (e.g. Flipper-Goal on an accept), kept out of the answer's JSON.
    if (answer && typeof answer === 'object') Object.defineProperty(answer, 'headers', { value: res.headers });
    return answer;
  }

  // A study event (POST /api/v1/study/event: flip, reject, page_load), in order with the
  // requests. Sent only to a server that records them; a 404 (no study, an older server) is
  // ignored, as is any other refusal: an event never stops the participant.
  event(kind, fields = {}) {
    if (!this.events || !this.token) return Promise.resolve(null);
    return this.queue(async () => {
      const res = await fetch(`/api/v1/study/event?session=${encodeURIComponent(this.token)}`, {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify({ kind, ...fields }),
      });
      return res.ok ? res.json().catch(() => null) : null;
    });
  }

  // POST /api/v1/login with {name, password} or {code}: the server sets an HttpOnly cookie. The
  // protocol session belonged to the previous identity: forget it.
  async login(credentials) {
    const res = await fetch('/api/v1/login', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify(credentials),
    });
    const answer = await res.json().catch(() => ({ ok: false, error: { code: 'http_error', message: `HTTP ${res.status}` } }));
    if (answer.ok) this.forget();
    return answer;
  }

  async logout() {
    await fetch('/api/v1/logout', { method: 'POST' });
    this.forget();
  }

  forget() {
    this.token = '';
    sessionStorage.removeItem(KEY);
  }

  info() {
    return this.queue(async () => (await fetch(this.url('/api/v1/info'))).json());
  }
}
