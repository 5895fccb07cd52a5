#pragma once
/// \file
/// Sorting of the per-slot keys that match faces and edges of a hex complex.
///
/// A complex of h hexes has 6h face slots and 12h edge slots; matching them sorts those keys.
/// Every key starts with its smallest node id, so a counting sort on that id (one bucket per
/// node, each holding the few dozen slots of the faces or edges whose smallest node it is)
/// followed by a sort inside each bucket gives the same order as sorting everything, in
/// linear time instead of n log n.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace stcweave::stc {

/// Sorts `entries` by `less`, a strict weak order whose first criterion is `node(e)`, a node
/// id of the entry (the smallest node of a face or edge key, the corner node of a corner):
/// `node(a) < node(b)` implies `less(a, b)`. The result is the one `std::sort(entries, less)`
/// gives when no two entries are equivalent without being equal, which is how every caller
/// uses it (keys completed by a slot number, or plain values). A negative node id or one far beyond
/// the number of entries (not an id: a complex that has not been range-checked) falls back to
/// `std::sort`.
template <class T, class Node, class Less>
void sort_by_smallest_node(std::vector<T>& entries, Node node, Less less) {
  // Buckets are worth it when node ids are dense: at most a few per entry.
  const auto limit = static_cast<std::int64_t>(4 * entries.size() + 64);
  std::int64_t top = -1;
  for (const T& e : entries) {
    const auto v = static_cast<std::int64_t>(node(e));
    if (v < 0 || v > limit) {
      std::sort(entries.begin(), entries.end(), less);
      return;
    }
    top = std::max(top, v);
  }
  const auto buckets = static_cast<std::size_t>(top + 1);
  std::vector<std::size_t> start(buckets + 1, 0);
  for (const T& e : entries) ++start[static_cast<std::size_t>(node(e)) + 1];
  for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
  std::vector<T> sorted(entries.size());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const T& e : entries) sorted[fill[static_cast<std::size_t>(node(e))]++] = e;
  for (std::size_t b = 0; b < buckets; ++b) {
    std::sort(sorted.begin() + static_cast<std::ptrdiff_t>(start[b]),
              sorted.begin() + static_cast<std::ptrdiff_t>(start[b + 1]), less);
  }
  entries.swap(sorted);
}

/// `sort_by_smallest_node` with `operator<` as the order.
template <class T, class Node>
void sort_by_smallest_node(std::vector<T>& entries, Node node) {
  sort_by_smallest_node(entries, node, [](const T& a, const T& b) { return a < b; });
}

}  // namespace stcweave::stc
