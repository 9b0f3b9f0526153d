#pragma once
// The vocabulary of contact statistics shared by the laws that record them (discrete/: the agent), the
// prediction made from a model's fields (compare/contacts.hpp) and the runner that tells both where the
// front is (docs/model.md §7.2): the classes (region × phase) and the plain tables handed to the writer.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace slipfront::core {

/// Where the sites are relative to the front, and the phase of the run (docs/model.md §7.2): sites
/// [0, behind_end) are behind the front, [behind_end, tip_end) in the tip band, [tip_end, n) ahead (the
/// default: no front); phase 0 before yield, 1 slow front, 2 transient, 3 after arrest (to the next
/// instability), and next_event (4): from the next instability on — its contacts are not classed (no row:
/// recorders skip them; per-site totals and snapshot times go on).
struct FrontClasses {
  static constexpr std::size_t regions = 3, phases = 4, count = regions * phases;
  static constexpr std::size_t next_event = phases;
  std::size_t behind_end = 0, tip_end = 0;
  std::size_t phase = 0;
  bool classed() const { return phase < phases; }
  std::size_t region_of(std::size_t site) const { return site < behind_end ? 0 : (site < tip_end ? 1 : 2); }
  /// Row of the class tables: 3 · phase + region.
  std::size_t class_of(std::size_t site) const { return regions * phase + region_of(site); }
};
inline const char* region_name(std::size_t r) {
  static const char* names[] = {"behind", "tip", "ahead"};
  return r < 3 ? names[r] : "?";
}
inline const char* phase_name(std::size_t p) {
  static const char* names[] = {"before_yield", "slow_front", "transient", "after_arrest", "next_event"};
  return p < 5 ? names[p] : "?";
}

/// Plain tables for the writer: 1D columns and row-major 2D tables [data.size()/cols, cols].
struct ContactTables {
  struct Table {
    std::size_t cols = 0;
    std::vector<double> data;
  };
  std::map<std::string, std::vector<double>> columns;
  std::map<std::string, Table> tables;
};

}  // namespace slipfront::core
