// A taught rule shown as the example it was learned from (docs/studio.md "Taught phrases"): the
// head as said ("pick 2 items"), what it means (the body lines), and the grammar notation
// (`$ItemAct $Number items → …`) on demand.
export function ruleView(rule, { head = rule.head, body = rule.body } = {}) {
  const title = document.createElement('div');
  title.className = 'rule-head';
  title.textContent = head || (rule.rhs || []).join(' ');
  const means = document.createElement('div');
  means.className = 'rule-means';
  means.textContent = body?.length ? `means: ${body.join('; ')}` : '';
  const notation = document.createElement('details');
  notation.className = 'rule-notation';
  const summary = document.createElement('summary');
  summary.textContent = 'notation';
  const code = document.createElement('code');
  code.textContent = `${rule.lhs} → ${(rule.rhs || []).join(' ')}  ⇒  ${rule.semantics}`;
  notation.append(summary, code);
  return [title, means, notation];
}
