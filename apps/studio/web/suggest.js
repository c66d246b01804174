// "Did you mean": words of an utterance the grammar does not know, each with the closest known
// word (Damerau-Levenshtein distance, at most 2 edits and less than half the word).
function distance(a, b) {
  const d = Array.from({ length: a.length + 1 }, (_, i) => [i, ...Array(b.length).fill(0)]);
  for (let j = 1; j <= b.length; j++) d[0][j] = j;
  for (let i = 1; i <= a.length; i++)
    for (let j = 1; j <= b.length; j++) {
      const cost = a[i - 1] === b[j - 1] ? 0 : 1;
      d[i][j] = Math.min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost);
      if (i > 1 && j > 1 && a[i - 1] === b[j - 2] && a[i - 2] === b[j - 1])
        d[i][j] = Math.min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.length][b.length];
}

export function tokens(text) {
  return text.toLowerCase().match(/[a-z_][a-z0-9_]*|[0-9]+|[^\s]/g) || [];
}

export function suggest(text, vocabulary) {
  const out = [];
  const seen = new Set();
  for (const t of tokens(text)) {
    if (!/^[a-z]/.test(t) || vocabulary.has(t) || seen.has(t)) continue;
    seen.add(t);
    let best = null, bestD = Infinity;
    for (const w of vocabulary) {
      if (Math.abs(w.length - t.length) > 2) continue;
      const dist = distance(t, w);
      if (dist < bestD) [best, bestD] = [w, dist];
    }
    out.push({ word: t, best: bestD <= 2 && bestD * 2 < t.length ? best : null });
  }
  return out;
}
