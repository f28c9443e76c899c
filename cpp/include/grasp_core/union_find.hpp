// Union-find over int indices kept in a plain vector (a parent per element).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace grasp_core {

/// Root of x, halving the path on the way.
inline int find_root(std::vector<int>& parent, int x) {
  while (parent[static_cast<std::size_t>(x)] != x) {
    parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    x = parent[static_cast<std::size_t>(x)];
  }
  return x;
}

/// Joins the sets of a and b; the lower root index becomes the root (deterministic).
inline void unite(std::vector<int>& parent, int a, int b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a == b) return;
  if (a < b) std::swap(a, b);
  parent[static_cast<std::size_t>(a)] = b;
}

}  // namespace grasp_core
