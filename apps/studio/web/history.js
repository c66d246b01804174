// The history of accepted steps, as the 2018 client kept it (docs/studio.md "History"): each step
// is {qid?, utterance, formula, world (after it), steps? (the steps a taught phrase replaced)}.
// Clicking a step shows the world after it; "from here" marks where a new phrase starts (the
// steps after it are its body, shift-click on a later step ends the range there), and "Teach a
// phrase from these N steps" hands the range to the define panel.
const $ = (id) => document.getElementById(id);
const FOLD_AFTER = 8; // older steps fold into "… N earlier steps"

export class HistoryPanel {
  constructor({ onPreview, onTeach }) {
    this.onPreview = onPreview; // (index | null)
    this.onTeach = onTeach; // ([from, to])
    this.steps = [];
    this.range = null; // [from, to] or null
    this.preview = null;
    this.teaching = true;
    $('history-teach').onclick = () => this.range && this.onTeach(this.range);
  }

  // Shows `steps` (the page's state.history); a range or a preview that no longer fits is dropped.
  render(steps, { teaching = this.teaching } = {}) {
    this.steps = steps;
    this.teaching = teaching;
    if (this.range && this.range[1] >= steps.length) this.range = null;
    if (this.preview !== null && this.preview >= steps.length) this.showPreview(null);
    const list = $('history');
    list.innerHTML = '';
    $('history-panel').hidden = steps.length === 0;
    const folded = Math.max(0, steps.length - FOLD_AFTER);
    let target = list;
    if (folded) {
      const li = document.createElement('li');
      li.className = 'fold';
      const details = document.createElement('details');
      const summary = document.createElement('summary');
      summary.textContent = `… ${folded} earlier step${folded === 1 ? '' : 's'}`;
      const inner = document.createElement('ol');
      details.append(summary, inner);
      li.append(details);
      list.append(li);
      target = inner;
    }
    steps.forEach((step, i) => (i < folded ? target : list).append(this.item(step, i)));
    const n = this.range ? this.range[1] - this.range[0] + 1 : 0;
    const teach = $('history-teach');
    teach.hidden = !this.teaching || !n;
    teach.textContent = `Teach a phrase from ${n === 1 ? 'this step' : `these ${n} steps`}`;
  }

  item(step, i) {
    const li = document.createElement('li');
    li.dataset.step = i;
    const inRange = this.range && i >= this.range[0] && i <= this.range[1];
    li.className = [inRange ? 'marked' : '', this.preview === i ? 'previewed' : ''].join(' ').trim();
    const look = document.createElement('button');
    look.type = 'button';
    look.className = 'step';
    look.title = 'Show the world after this step';
    const text = document.createElement('span');
    text.className = 'utterance';
    text.textContent = step.utterance;
    const formula = document.createElement('code');
    formula.textContent = step.formula;
    look.append(text, formula);
    if (step.steps?.length) {
      const note = document.createElement('small');
      note.textContent = ` (taught from ${step.steps.length} steps)`;
      text.append(note);
    }
    look.onclick = () => this.showPreview(this.preview === i ? null : i);
    li.append(look);
    if (this.teaching) {
      const from = document.createElement('button');
      from.type = 'button';
      from.className = 'from';
      from.dataset.testid = 'history-from';
      from.textContent = 'from here';
      from.title = 'The new phrase starts here (shift-click a later step to end it there)';
      from.onclick = (e) => this.mark(i, e.shiftKey);
      li.append(from);
    }
    return li;
  }

  // Marks i..last; with `extend`, ends an existing range at i instead.
  mark(i, extend = false) {
    if (extend && this.range && i >= this.range[0]) this.range = [this.range[0], i];
    else if (this.range && this.range[0] === i && !extend) this.range = null;
    else this.range = [i, this.steps.length - 1];
    this.render(this.steps);
  }

  clearRange() {
    this.range = null;
    this.render(this.steps);
  }

  showPreview(i) {
    this.preview = i;
    for (const li of document.querySelectorAll('#history li[data-step]'))
      li.classList.toggle('previewed', Number(li.dataset.step) === i);
    this.onPreview(i);
  }
}
