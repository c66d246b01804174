// The define panel: the head pre-filled, body lines added one at a time, each parsed as it is
// typed (a protocol `query`), its reading chosen from its candidates (sent as `ranks`), errors
// shown on the line before anything is submitted; then the answer's rules, generalized and
// discarded.
const $ = (id) => document.getElementById(id);

export class DefinePanel {
  constructor({ api, onDefined }) {
    this.api = api;
    this.onDefined = onDefined;
    this.lines = []; // {input, select, status, answer, seq}
    $('define-add').onclick = () => this.addLine('').input.focus();
    $('define-submit').onclick = () => this.submit();
    $('define-cancel').onclick = () => this.close();
  }

  open(head) {
    $('define-panel').hidden = false;
    $('define-head').value = head || '';
    $('define-result').innerHTML = '';
    $('define-lines').innerHTML = '';
    this.lines = [];
    this.addLine('').input.focus();
  }

  close() {
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
    const answer = await this.api.request({ op: 'query', text, k: 5 });
    if (seq !== line.seq) return; // a newer keystroke has its own answer coming
    line.answer = answer;
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

  async submit() {
    const head = $('define-head').value.trim();
    const used = this.lines.filter((l) => l.input.value.trim());
    for (const l of used) if (!l.answer || l.seq === 0) await this.parse(l);
    const result = $('define-result');
    result.innerHTML = '';
    const bad = used.find((l) => l.li.dataset.state === 'error');
    if (!head || !used.length || bad) {
      result.className = 'error';
      result.textContent = !head ? 'Say which phrase to teach.'
        : !used.length ? 'Add at least one line.'
        : 'Fix the lines marked in red first.';
      return null;
    }
    const answer = await this.api.request({
      op: 'define',
      head,
      body: used.map((l) => l.input.value.trim()),
      ranks: used.map((l) => Number(l.select.value || 0)),
    });
    result.className = answer.ok ? 'ok' : 'error';
    if (!answer.ok) {
      result.textContent = `${answer.error.code}: ${answer.error.message}`;
      return answer;
    }
    const h = document.createElement('p');
    h.textContent = `Learned "${head}": ${answer.rules.length} rule${answer.rules.length === 1 ? '' : 's'}.`;
    result.append(h);
    const ul = document.createElement('ul');
    for (const r of answer.rules) {
      const li = document.createElement('li');
      const code = document.createElement('code');
      code.textContent = `${r.lhs} → ${r.rhs.join(' ')}  ⇒  ${r.semantics}`;
      li.append(code, ` (${r.how})`);
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
    this.onDefined?.(answer);
    return answer;
  }
}
