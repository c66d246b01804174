// The define panel (docs/studio.md "Teaching"). Typed mode: the head pre-filled, body lines added
// one at a time, each parsed as it is typed (a protocol `query` marked as a live check), its
// reading chosen from its candidates and sent as the line's formula, errors shown on the line
// before anything is submitted. History mode: the body is a range of accepted steps, each with
// the program that was accepted. Then the answer's rules as their example, generalized and
// discarded; the panel closes by itself a few seconds after a success.
import { ruleView } from './rule-view.js';

const $ = (id) => document.getElementById(id);
const CLOSE_AFTER_MS = 4000;

export class DefinePanel {
  constructor({ api, onDefined, onLiveCheck, toast }) {
    this.api = api;
    // Body lines as {"text","formula"}; off only for a study server whose recording keeps string
    // lines alone (one without info.study.teaching): then strings and `ranks`, as it replays them.
    this.formulaLines = true;
    this.onLiveCheck = onLiveCheck; // a live check replaces the session's last query
    this.onDefined = onDefined; // (answer, {history: [from, to] | null, head})
    this.toast = toast;
    this.lines = []; // {input, select, status, answer, seq}
    this.history = null; // {steps, range} in history mode
    $('define-add').onclick = () => this.addLine('').input.focus();
    $('define-submit').onclick = () => this.submit();
    $('define-cancel').onclick = () => this.close();
    // Working in the panel again keeps it open, and a new edit clears the last success.
    $('define-panel').addEventListener('click', (e) => {
      if (e.target.id !== 'define-submit') clearTimeout(this.closeTimer);
    });
    $('define-panel').addEventListener('input', () => {
      clearTimeout(this.closeTimer);
      if ($('define-result').className === 'ok') {
        $('define-result').innerHTML = '';
        $('define-result').className = '';
      }
    });
  }

  get isOpen() {
    return !$('define-panel').hidden;
  }

  // Typed lines not yet taught (closing the panel would lose them).
  hasWork() {
    const taught = $('define-result').className.includes('ok');
    return !this.history && !taught && this.lines.some((l) => l.input.value.trim());
  }

  // Typed mode (history absent), or history mode with {steps, range: [from, to]}. `lines`: typed
  // steps to start with (a repair's "teach it as"), each read at once.
  open(head, history = null, lines = []) {
    clearTimeout(this.closeTimer);
    this.history = history;
    $('define-panel').hidden = false;
    $('define-panel').dataset.mode = history ? 'history' : 'typed';
    $('define-head').value = head || '';
    $('define-result').innerHTML = '';
    $('define-result').className = '';
    $('define-lines').innerHTML = '';
    $('define-steps').innerHTML = '';
    $('define-add').hidden = Boolean(history);
    $('define-hint').textContent = history
      ? 'These steps, with the readings you accepted, become what the phrase means.'
      : 'Say it again in words Flipper understands, one step per line. Each line is read as you type; '
        + 'pick the right reading.';
    this.lines = [];
    if (history) {
      const [from, to] = history.range;
      for (const step of history.steps.slice(from, to + 1)) {
        const li = document.createElement('li');
        const code = document.createElement('code');
        code.textContent = step.formula;
        li.append(`${step.utterance} ⇒ `, code);
        $('define-steps').append(li);
      }
      $('define-head').focus();
    } else if (lines.length) {
      for (const text of lines) this.parse(this.addLine(text));
      $('define-head').focus();
    } else this.addLine('').input.focus();
  }

  close() {
    clearTimeout(this.closeTimer);
    $('define-panel').hidden = true;
  }

  addLine(text) {
    const li = document.createElement('li');
    const input = document.createElement('input');
    input.value = text;
    input.spellcheck = false;
    input.placeholder = 'a step Flipper understands, e.g. repeat 3 times pick item';
    input.dataset.testid = 'define-line';
    const select = document.createElement('select');
    select.dataset.testid = 'define-reading';
    select.hidden = true;
    const status = document.createElement('div');
    status.className = 'line-status';
    status.dataset.testid = 'define-line-status';
    li.append(input, select, status);
    $('define-lines').append(li);
    const line = { li, input, select, status, answer: null, seq: 0 };
    this.lines.push(line);
    let timer;
    input.addEventListener('input', () => {
      clearTimeout(timer);
      timer = setTimeout(() => this.parse(line), 250);
    });
    input.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') {
        e.preventDefault();
        this.parse(line).then(() => {
          const next = this.lines[this.lines.indexOf(line) + 1] || this.addLine('');
          next.input.focus();
        });
      }
    });
    return line;
  }

  async parse(line) {
    const text = line.input.value.trim();
    const seq = ++line.seq;
    line.li.dataset.state = 'parsing';
    if (!text) {
      line.answer = null;
      line.select.hidden = true;
      line.status.textContent = '';
      line.li.dataset.state = 'empty';
      return;
    }
    // A live check, not a participant's query (a study records it as its own kind).
    this.onLiveCheck?.();
    const answer = await this.api.request({ op: 'query', text, k: 5, studio: { why: 'live' } });
    if (seq !== line.seq) return; // a newer keystroke has its own answer coming
    line.answer = answer;
    line.text = text;
    line.select.innerHTML = '';
    if (!answer.ok || answer.status === 'unparsable') {
      line.select.hidden = true;
      line.status.className = 'line-status error';
      line.status.textContent = answer.ok
        ? 'Flipper does not understand this line.'
        : `${answer.error.code}: ${answer.error.message}`;
      line.li.dataset.state = 'error';
      return;
    }
    answer.candidates.forEach((c, i) => {
      const o = document.createElement('option');
      o.value = i;
      o.textContent = c.formula;
      line.select.append(o);
    });
    line.select.hidden = answer.candidates.length < 2;
    line.status.className = 'line-status ok';
    line.status.textContent =
      answer.candidates.length > 1 ? `${answer.candidates.length} readings: pick one` : `✓ ${answer.candidates[0].formula}`;
    line.li.dataset.state = 'ok';
  }

  // The body as the protocol's formula lines: each line's chosen reading, whatever the parser
  // reads in its text later (docs/protocol.md "define").
  body() {
    if (this.history) {
      const [from, to] = this.history.range;
      return this.history.steps.slice(from, to + 1).map((s) => ({ text: s.utterance, formula: s.formula }));
    }
    return this.lines.filter((l) => l.input.value.trim()).map((l) => ({
      text: l.input.value.trim(),
      formula: l.answer.candidates[Number(l.select.value || 0)].formula,
    }));
  }

  async submit() {
    const head = $('define-head').value.trim();
    const used = this.history ? [] : this.lines.filter((l) => l.input.value.trim());
    for (const l of used) if (!l.answer || l.seq === 0 || l.text !== l.input.value.trim()) await this.parse(l);
    const result = $('define-result');
    result.innerHTML = '';
    const bad = used.find((l) => l.li.dataset.state === 'error');
    if (!head || (!this.history && !used.length) || bad) {
      result.className = 'error';
      result.textContent = !head ? 'Say which phrase to teach.'
        : !used.length ? 'Add at least one line.'
        : 'Fix the lines marked in red first.';
      return null;
    }
    const body = this.body();
    const request = { op: 'define', head, body };
    if (!this.formulaLines && !this.history) {
      request.body = body.map((l) => l.text);
      request.ranks = used.map((l) => Number(l.select.value || 0));
    }
    if (this.history) request.studio = { why: 'history', steps: this.history.range };
    const answer = await this.api.request(request);
    result.className = answer.ok ? 'ok' : 'error';
    if (!answer.ok) {
      result.textContent = `${answer.error.code}: ${answer.error.message}`;
      return answer;
    }
    this.showResult(answer, head, body);
    const learned = `Learned "${head}"`;
    this.toast?.(learned);
    const history = this.history?.range ?? null;
    this.closeTimer = setTimeout(() => this.close(), CLOSE_AFTER_MS);
    this.onDefined?.(answer, { history, head });
    return answer;
  }

  showResult(answer, head, body) {
    const result = $('define-result');
    const n = answer.rules.length;
    const h = document.createElement('p');
    h.textContent = `Learned "${head}": ${n} rule${n === 1 ? '' : 's'}.`;
    // lexicon.moderation: hold_new (docs/naturalization.md §5 "Moderation").
    if (answer.held)
      h.textContent = `"${head}" (${n} rule${n === 1 ? '' : 's'}) waits for the researcher's approval; until then it is not understood.`;
    result.append(h);
    const ul = document.createElement('ul');
    for (const r of answer.rules) {
      const li = document.createElement('li');
      li.append(...ruleView(r, { head, body: body.map((l) => l.text) }));
      li.append(` (${r.how})`);
      ul.append(li);
    }
    result.append(ul);
    if (answer.generalized) {
      const g = document.createElement('p');
      g.textContent = `Generalized to: ${answer.generalized}`;
      result.append(g);
    }
    if (answer.discarded?.length) {
      const d = document.createElement('details');
      const s = document.createElement('summary');
      s.textContent = `${answer.discarded.length} rewriting(s) discarded`;
      d.append(s);
      for (const x of answer.discarded) {
        const p = document.createElement('p');
        p.textContent = `${x.formula} — ${x.rewriting}: ${x.reason}`;
        d.append(p);
      }
      result.append(d);
    }
  }
}
