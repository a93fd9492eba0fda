#include "s3m/mapping/label_set.hpp"

#include <algorithm>

namespace s3m::mapping {

float LabelSet::sum() const {
  float s = 0.0f;
  for (int i = 0; i < n; ++i) s += probs[i];
  return s;
}

int LabelSet::find(ClassId id) const {
  for (int i = 0; i < n; ++i)
    if (ids[i] == id) return i;
  return -1;
}

float LabelSet::prob_of(ClassId id) const {
  const int i = find(id);
  return i < 0 ? 0.0f : probs[i];
}

bool LabelSet::push(ClassId id, float p) {
  if (n >= kMaxLabels) return false;
  ids[n] = id;
  probs[n] = p;
  ++n;
  return true;
}

void LabelSet::normalise(int k) {
  // Merge duplicates first (an input list may name a class twice).
  int m = 0;
  for (int i = 0; i < n; ++i) {
    int j = 0;
    while (j < m && ids[j] != ids[i]) ++j;
    if (j < m) {
      probs[j] += probs[i];
    } else {
      ids[m] = ids[i];
      probs[m] = probs[i];
      ++m;
    }
  }
  std::array<int, kMaxLabels> order{};
  for (int i = 0; i < m; ++i) order[i] = i;
  std::sort(order.begin(), order.begin() + m, [&](int a, int b) {
    return probs[a] != probs[b] ? probs[a] > probs[b] : ids[a] < ids[b];
  });
  LabelSet out;
  for (int i = 0; i < m && out.n < k; ++i)
    if (probs[order[i]] > 0.0f) out.push(ids[order[i]], probs[order[i]]);
  *this = out;
}

bool LabelSet::operator==(const LabelSet& o) const {
  if (n != o.n) return false;
  for (int i = 0; i < n; ++i)
    if (ids[i] != o.ids[i] || probs[i] != o.probs[i]) return false;
  return true;
}

}  // namespace s3m::mapping
