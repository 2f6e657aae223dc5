// Traversal statistics: TraversalStats counts, NoStats compiles to nothing so the fast path pays no cost.
#pragma once

#include <cstdint>

namespace rayaccel {

struct TraversalStats {
  std::uint64_t nodes_visited = 0;      ///< interior and leaf nodes (or cells) entered
  std::uint64_t primitives_tested = 0;  ///< ray/primitive tests run

  void visit_node(std::uint64_t n = 1) { nodes_visited += n; }
  void test_primitive(std::uint64_t n = 1) { primitives_tested += n; }
  TraversalStats& operator+=(const TraversalStats& o) {
    nodes_visited += o.nodes_visited;
    primitives_tested += o.primitives_tested;
    return *this;
  }
};

/// Stand-in used when statistics are off: every call is an empty inline function.
struct NoStats {
  constexpr void visit_node(std::uint64_t = 1) const {}
  constexpr void test_primitive(std::uint64_t = 1) const {}
};

}  // namespace rayaccel
