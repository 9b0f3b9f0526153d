#pragma once
// What one model's run produces, in memory, for the writer (apps/h5out) to lay out (docs/model.md §5).
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "compare/measure.hpp"
#include "core/archive.hpp"

namespace slipfront::compare {

/// How a run ended (docs/output.md: /meta status and /<model> status), ordered by severity: a file's
/// status is the worst of its parts.
enum class RunStatus { complete, interrupted, failed };
/// The name written to files and printed: "complete", "interrupted", "failed".
constexpr const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::interrupted: return "interrupted";
    case RunStatus::failed: return "failed";
    case RunStatus::complete: break;
  }
  return "complete";
}
/// The status named `name` (as to_string writes it); throws std::invalid_argument for any other text.
inline RunStatus run_status(std::string_view name) {
  for (const RunStatus s : {RunStatus::complete, RunStatus::interrupted, RunStatus::failed})
    if (name == to_string(s)) return s;
  throw std::invalid_argument("unknown run status '" + std::string(name) + "'");
}
/// The more severe of two statuses.
constexpr RunStatus worst(RunStatus a, RunStatus b) { return a < b ? b : a; }

using Columns = std::map<std::string, std::vector<double>>;

/// A row-major 2D table [data.size() / cols, cols].
struct Table2D {
  std::size_t cols = 0;
  std::vector<double> data;
  template <class Ar>
  void serialize(Ar& ar) {
    ar(cols, data);
  }
};

struct ModelResult {
  std::string model;                ///< "continuum", "discrete"
  RunStatus status = RunStatus::complete;
  std::string message;              ///< why, when not complete
  std::vector<double> x;            ///< node positions [nx] (0D: {0})
  Columns series;                   ///< each [nt]: t, drive_force, tip_x, tip_x_alt, max_v, ...
  std::vector<double> snapshot_t;   ///< [ns]
  Columns snapshots;                ///< each flat [ns * nx] row-major: A, sigma_bar, v, u
  /// The strip's body snapshots (docs/output.md /<model>/bulk/, output.bulk_dt): the kept nodes' positions
  /// and, per snapshot, u, tau_xz, tau_yz each flat [nb * nyk * nxk] (snapshot, row, column; row-major).
  std::vector<double> bulk_t;       ///< [nb]
  std::vector<double> bulk_x;       ///< [nxk] x of the kept columns
  std::vector<double> bulk_y;       ///< [nyk] y of the kept rows (0: the interface; the last: the top, H)
  Columns bulk;                     ///< u, tau_xz, tau_yz
  Events events;                    ///< measured on the A_tip front (docs/model.md §3 default 0.5)
  Events events_alt;                ///< the same measured on the A_tip_alt front (0.9)
  Columns cycles;                   ///< spring block stick–slip cycles: t_start, F_peak, F_residual
  /// output.sequence: the slip events of an edge-loaded run (compare::slip_sequence), computed by finish() from the
  /// series (in a checkpoint for the models that had finished: checkpoint format 3).
  Columns sequence;
  Columns friction_law;             ///< imposed-rate sweep: v, sigma, sigma_stderr, A, sigma_closed_form
  std::map<std::string, double> scalars;       ///< dt, steps, stable_dt, v_m_fit, ... (attributes of /<model>)
  std::map<std::string, std::string> labels;   ///< string attributes of /<model> (representation, ...)
  Columns contacts;                            ///< discrete, agent: /<model>/contacts/<name> [n]
  std::map<std::string, Table2D> contacts_2d;  ///< discrete, agent: /<model>/contacts/<name> [rows, cols]
  double wall_seconds = 0.0;
  template <class Ar>
  void serialize(Ar& ar) {
    // the status as its name (checkpoints of earlier versions stored the string)
    std::string status_name = to_string(status);
    ar(model, status_name);
    if (ar.loading()) {
      try {
        status = run_status(status_name);
      } catch (const std::invalid_argument& e) {
        throw core::ArchiveError(std::string("checkpoint: ") + e.what());
      }
    }
    ar(message, x, series, snapshot_t, snapshots, bulk_t, bulk_x, bulk_y, bulk, events, events_alt, cycles,
       sequence, friction_law, scalars, labels, contacts, contacts_2d, wall_seconds);
  }
};

/// The comparison layer's metrics of one scene run (compare/alongside.hpp), each with its definition.
struct Comparison {
  /// The model the discrete model is compared with: mean_field when the scene lists it (docs/model.md §2.2),
  /// else continuum (/compare attribute `reference`).
  std::string reference = "continuum";
  Columns fields;                                   ///< t, A_distance, sigma_bar_distance, v_distance, u_distance
  Columns friction_law;                             ///< v, rel_diff (imposed-rate sweeps)
  Columns contacts;                                 ///< goodness of fit of the contact statistics, one row per statistic and class
  std::map<std::string, double> metrics;            ///< scalar metrics
  std::map<std::string, std::string> definitions;   ///< metric or "fields/<col>" -> definition
  bool empty() const { return fields.empty() && friction_law.empty() && contacts.empty() && metrics.empty(); }
};

struct SceneResult {
  std::vector<ModelResult> models;
  Comparison comparison;  ///< empty unless the scene runs discrete and a reference (continuum or mean_field)
};

}  // namespace slipfront::compare
