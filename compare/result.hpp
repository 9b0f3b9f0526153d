#pragma once
// What one model's run produces, in memory, for the writer (apps/h5out) to lay out (docs/model.md §5).
#include <map>
#include <string>
#include <vector>

#include "compare/measure.hpp"

namespace slipfront::compare {

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
  std::string status = "complete";  ///< complete | interrupted | failed
  std::string message;              ///< why, when not complete
  std::vector<double> x;            ///< node positions [nx] (0D: {0})
  Columns series;                   ///< each [nt]: t, drive_force, tip_x, tip_x_alt, max_v, ...
  std::vector<double> snapshot_t;   ///< [ns]
  Columns snapshots;                ///< each flat [ns * nx] row-major: A, sigma_bar, v, u
  Events events;                    ///< measured on the A_tip front (docs/model.md §3 default 0.5)
  Events events_alt;                ///< the same measured on the A_tip_alt front (0.9)
  Columns cycles;                   ///< spring block stick–slip cycles: t_start, F_peak, F_residual
  Columns friction_law;             ///< imposed-rate sweep: v, sigma, sigma_stderr, A, sigma_closed_form
  std::map<std::string, double> scalars;       ///< dt, steps, stable_dt, v_m_fit, ... (attributes of /<model>)
  std::map<std::string, std::string> labels;   ///< string attributes of /<model> (representation, ...)
  Columns contacts;                            ///< discrete, agent: /<model>/contacts/<name> [n]
  std::map<std::string, Table2D> contacts_2d;  ///< discrete, agent: /<model>/contacts/<name> [rows, cols]
  double wall_seconds = 0.0;
  template <class Ar>
  void serialize(Ar& ar) {
    ar(model, status, message, x, series, snapshot_t, snapshots, events, events_alt, cycles, friction_law, scalars,
       labels, contacts, contacts_2d, wall_seconds);
  }
};

}  // namespace slipfront::compare
