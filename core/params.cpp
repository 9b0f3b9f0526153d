#include "core/params.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace slipfront::core {

std::string format_number(double x, int digits) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

namespace {
void require(bool ok, const char* key, const std::string& reason) {
  if (!ok) throw ParamError(key, reason);
}
bool finite(double x) { return std::isfinite(x); }

constexpr double cap = parameter_cap;
constexpr double int_max = 2147483647.0;

using K = KeyKind;
// One row per key of the continuum and scene part of the schema (apps/config.cpp), in schema order.
const KeyDomain continuum_domains[] = {
    {"scene", K::text, 0, 0, false, false, false, "", "(names the output directory out/<scene>)"},
    {"description", K::text},
    {"models", K::text_list, 0, 0, false, false, false, "continuum|discrete"},
    {"interface.alpha", K::number, 1.0, cap, false, false, false, "", "(the sliding branch is not self-consistent below 1)"},
    {"interface.kappa", K::number, 0.0, cap},
    {"interface.eta", K::number, 0.0, cap},
    {"interface.aging_b", K::number, 0.0, cap, false, false, false, "",
     "(contact aging, docs/model.md §11: area 1 + b ln(1 + age/aging_tau); 0: no aging)"},
    {"interface.aging_tau", K::number, 0.0, cap, true, false, false, "", "(the aging cut-off time)"},
    {"interface.load_x", K::number_list, 0.0, cap, false, false, false, "",
     "(positions of the normal-load table, increasing, docs/model.md §12)"},
    {"interface.load_p", K::number_list, 0.0, cap, false, false, false, "",
     "(the normal load p/p_0 at interface.load_x: compressive, so not negative)"},
    {"interface.load_exponent", K::number, 0.0, cap, false, false, false, "",
     "(m of the resting area (p/p_0)^m; 1: Bowden-Tabor, 0: no load dependence)"},
    {"interface.load_channel", K::choice, 0, 0, false, false, false, "reattachment|instantaneous"},
    {"interface.load_coupling", K::choice, 0, 0, false, false, false, "none|sigma_yy",
     "(the in-plane strip's own normal load p = -sigma_yy(x, 0, t), docs/model.md §12.5)"},
    {"interface.load_relaxation_length", K::number, 0.0, cap, false, false, false, "",
     "(L of the regularised instantaneous channel, docs/model.md §12.7; 0: off)"},
    {"interface.load_relaxation_speed", K::number, 0.0, cap, false, false, false, "",
     "(v* of the regularised instantaneous channel: the relaxation rate is (|v| + v*)/L)"},
    {"bulk.rho", K::number, 0.0, cap, true},
    {"bulk.mu", K::number, 0.0, cap, true},
    {"bulk.length", K::number, 0.0, cap, true},
    {"bulk.height", K::number, 1e-9, cap, false, false, true, "", "(the strip's height H; 0 or absent: the 1D chain)"},
    {"bulk.body", K::choice, 0, 0, false, false, false, "antiplane|inplane", "(the strip's body; absent: antiplane)"},
    {"bulk.poisson", K::number, -1.0, 0.5, true, true, false, "",
     "(Poisson's ratio of the in-plane strip: lambda' = 2 mu' nu / (1 - 2 nu) is finite and positive-definite only "
     "there)"},
    {"bulk.normal_load", K::number, 0.0, cap, false, false, false, "", "(compressive load p on the in-plane strip's top face)"},
    {"drive.loading", K::choice, 0, 0, false, false, false, "edge|homogeneous|imposed_rate|spring_block"},
    {"drive.K", K::number, 0.0, cap, true},
    {"drive.v_d", K::number, 0.0, cap},
    {"drive.sigma_d", K::number, 0.0, cap, true},
    {"drive.nucleation_length", K::number, 0.0, cap},
    {"drive.start", K::choice, 0, 0, false, false, false, "nucleation|steady_front"},
    {"drive.front_x", K::number, 0.0, cap, true, false, false, "", "(the tip at t = 0)"},
    {"drive.kick_dv", K::number, -cap, cap},
    {"drive.kick_length", K::number, 0.0, cap, true},
    {"drive.v", K::number_list, -cap, cap},
    {"drive.switch_times", K::number_list, 0.0, cap},
    {"drive.v_min", K::number, 0.0, cap, true},
    {"drive.v_max", K::number, 0.0, cap, true},
    {"drive.points", K::integer, 2.0, 1e6, false, false, false, "", "(points of a sweep)"},
    {"grid.dx", K::number, 0.0, cap, true},
    {"grid.dy", K::number, 1e-9, cap, false, false, true, "", "(the strip's row spacing; 0 or absent: grid.dx)"},
    {"time.t_end", K::number, 0.0, cap, true},
    {"time.dt", K::number, 0.0, cap, false, false, false, "", "(0: use time.cfl)"},
    {"time.cfl", K::number, 0.0, 1.0, true, false, false, "", "(fraction of the explicit stability limit)"},
    {"time.slip_end", K::number, 0.0, cap},
    {"time.steps", K::integer, 1.0, 1e9, false, false, false, "", "(steps per sweep point or history)"},
    {"time.integrator", K::choice, 0, 0, false, false, false, "explicit|implicit|adaptive"},
    {"time.implicit_tolerance", K::number, 1e-12, cap, false, false, true, "",
     "(stress units; 0: no error control; below 1e-12 the linearisation defect nears the rounding of the stress: "
     "the leap integrator forces steps that fail it and the implicit one halves every step to "
     "time.implicit_max_halvings, docs/robustness.md §3)"},
    {"time.implicit_max_halvings", K::integer, 0.0, 30.0},
    {"time.implicit_resolution_check", K::boolean},
    {"time.stop_at_arrest", K::boolean},
    {"time.rtol", K::number, 0.0, 1.0, true, true},
    {"time.atol", K::number, 0.0, cap, true},
    {"time.dt_max", K::number, 0.0, cap, true},
    {"time.leap_epsilon", K::number, 1e-6, 1.0, false, false, false, "",
     "(relative change of a site's rates per step; below 1e-6 the leap steps, a fraction epsilon of a site's "
     "relaxation time, near the integrator's smallest step 1e-12 and cost more than time.integrator = explicit: "
     "docs/robustness.md §3)"},
    {"time.group_switchings", K::number, 0.0, 1.0, false, false, false, "",
     "(0: every switching ends a step; f: late flips within f of the step's tolerance)"},
    {"measure.A_tip", K::number, 0.0, 1.0, true, true},
    {"measure.A_tip_alt", K::number, 0.0, 1.0, true, true},
    {"measure.v_event", K::number, 0.0, cap, true},
    {"measure.sample_dt", K::number, 0.0, cap, true},
    {"measure.average_from", K::number, 0.0, 1.0, false, true},
    {"measure.batches", K::integer, 2.0, 1e6},
    {"measure.arrest_fraction", K::number, 0.0, 1.0, true, true},
    {"measure.behind_tip_fraction", K::number, 0.0, 1.0, true, false},
    {"measure.behind_near", K::number, 0.0, cap},
    {"measure.behind_far", K::number, 0.0, cap, true},
    {"measure.settle_window", K::number, 0.0, cap, true, false, false, "", "(length units)"},
    {"measure.settle_band", K::number, 0.0, 1.0, true, true},
    {"measure.settle_end_zone", K::number, 0.0, cap, false, false, false, "", "(length units)"},
    {"measure.tip_band", K::number, 0.0, cap, false, false, false, "", "(length units)"},
    {"output.series_dt", K::number, 0.0, cap, false, false, false, "", "(0: every step)"},
    {"output.snapshot_dt", K::number, 0.0, cap, false, false, false, "", "(0: none)"},
    {"output.energy", K::boolean},
    {"output.sequence", K::boolean},
    {"output.ages", K::boolean},
    {"output.compare_dt", K::number, 0.0, cap, false, false, false, "", "(0: no field comparison)"},
    {"output.contact_snapshot_dt", K::number, -cap, cap, false, false, false, "",
     "(< 0: output.snapshot_dt; 0: no contact snapshots)"},
    {"output.deflate", K::integer, 0.0, 9.0, false, false, false, "",
     "(gzip level of the field datasets, with the byte shuffle; 0: no compression)"},
};

std::string lower_bound_text(const KeyDomain& d) {
  return std::string(d.lo_open ? "> " : ">= ") + format_number(d.lo);
}
bool natural_interval(const KeyDomain& d) { return d.hi < cap && d.lo > -cap; }
std::string interval_text(const KeyDomain& d) {
  return std::string("in ") + (d.lo_open ? "(" : "[") + format_number(d.lo) + ", " + format_number(d.hi) +
         (d.hi_open ? ")" : "]");
}
std::string with_why(const KeyDomain& d, std::string text) {
  if (d.why[0] != '\0') text += std::string(" ") + d.why;
  return text;
}
}  // namespace

bool KeyDomain::contains(double x) const {
  if (kind != KeyKind::number && kind != KeyKind::integer && kind != KeyKind::number_list) return true;
  if (std::isnan(x)) return false;
  if (zero_ok && x == 0.0) return true;
  if (!finite(x)) return false;
  if (kind == KeyKind::integer && x != std::trunc(x)) return false;
  const bool above_lo = lo_open ? x > lo : x >= lo;
  const bool below_hi = hi_open ? x < hi : x <= hi;
  return above_lo && below_hi;
}

std::string KeyDomain::describe() const {
  switch (kind) {
    case KeyKind::boolean: return "true or false";
    case KeyKind::text: return "a string";
    case KeyKind::choice:
    case KeyKind::text_list: {
      std::string out = kind == KeyKind::choice ? "one of " : "a list of ";
      for (const char* c = choices; *c; ++c) out += *c == '|' ? std::string(", ") : std::string(1, *c);
      return out;
    }
    default: break;
  }
  std::string text = natural_interval(*this) ? interval_text(*this) : lower_bound_text(*this) + " and <= " + format_number(hi);
  if (zero_ok) text = "0 or " + text;
  return text;
}

std::span<const KeyDomain> key_domains() { return continuum_domains; }

const KeyDomain* find_key_domain(std::span<const KeyDomain> table, std::string_view key) {
  for (const auto& d : table)
    if (key == d.key) return &d;
  return nullptr;
}

void check_in_domain(const KeyDomain& d, double value) {
  if (d.contains(value)) return;
  std::string reason;
  if (d.kind == KeyKind::integer && finite(value) && value != std::trunc(value)) {
    reason = "must be a whole number";
  } else if (!natural_interval(d) && value > d.hi) {  // +inf too
    reason = "must be <= " + format_number(d.hi);
    if (d.hi == cap) reason += " (larger values are outside the scaling of the dimensionless model)";
  } else {
    reason = with_why(d, "must be " + std::string(d.zero_ok ? "0 or " : "") +
                             (natural_interval(d) ? interval_text(d) : lower_bound_text(d)));
  }
  throw ParamError(d.key, reason + ", got " + format_number(value));
}

void check_in_domain(const char* key, double value) {
  const KeyDomain* d = find_key_domain(key_domains(), key);
  if (!d) throw std::logic_error(std::string("check_in_domain: no domain row for ") + key);
  check_in_domain(*d, value);
}

namespace {
// docs/model.md §12.7: the regularisation acts on a load that changes in time under the instantaneous channel only.
void check_load_relaxation(const InterfaceParams& ip) {
  check_in_domain("interface.load_relaxation_length", ip.load_relaxation_length);
  check_in_domain("interface.load_relaxation_speed", ip.load_relaxation_speed);
  if (!ip.relaxes_load()) {
    require(ip.load_relaxation_speed == 0.0, "interface.load_relaxation_speed",
            "given without interface.load_relaxation_length > 0 (the regularisation's length; 0: off)");
    return;
  }
  require(ip.couples_load(), "interface.load_relaxation_length",
          "regularises the coupled load (docs/model.md §12.7): needs interface.load_coupling = \"sigma_yy\" (a "
          "prescribed profile does not change in time)");
  require(ip.instantaneous_load(), "interface.load_relaxation_length",
          "regularises the instantaneous channel (docs/model.md §12.7): needs interface.load_channel = "
          "\"instantaneous\", got '" + ip.load_channel + "' (the re-attachment channel already follows p at unit rate)");
}
}  // namespace

void InterfaceParams::validate() const {
  check_in_domain("interface.alpha", alpha);
  check_in_domain("interface.kappa", kappa);
  check_in_domain("interface.eta", eta);
  check_in_domain("interface.aging_b", aging_b);
  if (ages_contacts()) check_in_domain("interface.aging_tau", aging_tau);
  require(load_coupling == "none" || load_coupling == "sigma_yy", "interface.load_coupling",
          "unknown coupling '" + load_coupling + "' (expected none or sigma_yy)");
  if (load_channel == "reattachment" || load_channel == "instantaneous") check_load_relaxation(*this);
  if (!has_load_profile()) {
    require(load_x.empty(), "interface.load_x", "given without interface.load_p (the load at those positions)");
    if (couples_load()) {
      check_in_domain("interface.load_exponent", load_exponent);
      require(load_channel == "reattachment" || load_channel == "instantaneous", "interface.load_channel",
              "unknown channel '" + load_channel + "' (expected reattachment or instantaneous)");
    }
    return;
  }
  for (const double p : load_p) check_in_domain("interface.load_p", p);
  for (const double x : load_x) check_in_domain("interface.load_x", x);
  require(load_x.size() == load_p.size(), "interface.load_x",
          "must have as many entries as interface.load_p (" + std::to_string(load_p.size()) + "), got " +
              std::to_string(load_x.size()));
  for (std::size_t k = 1; k < load_x.size(); ++k)
    require(load_x[k] > load_x[k - 1], "interface.load_x", "must be increasing");
  check_in_domain("interface.load_exponent", load_exponent);
  require(load_channel == "reattachment" || load_channel == "instantaneous", "interface.load_channel",
          "unknown channel '" + load_channel + "' (expected reattachment or instantaneous)");
}

double InterfaceParams::load_at(double x) const {
  if (load_p.empty()) return 1.0;
  if (!(x > load_x.front())) return load_p.front();
  if (!(x < load_x.back())) return load_p.back();
  std::size_t k = 1;
  while (load_x[k] < x) ++k;  // load_x[k − 1] < x ≤ load_x[k]
  const double t = (x - load_x[k - 1]) / (load_x[k] - load_x[k - 1]);
  return load_p[k - 1] + t * (load_p[k] - load_p[k - 1]);
}

double InterfaceParams::resting_area_at(double x) const {
  if (load_p.empty() || load_exponent == 0.0) return 1.0;
  return std::pow(load_at(x), load_exponent);
}

void BulkParams::validate(bool one_dimensional) const {
  check_in_domain("bulk.rho", rho);
  if (one_dimensional) {
    check_in_domain("bulk.mu", mu);
    check_in_domain("bulk.length", length);
    if (body() != BodyKind::chain) check_in_domain("bulk.height", height);
  } else {
    require(body() == BodyKind::chain, "bulk.height",
            "a 0D scene (drive.loading = spring_block or imposed_rate) has no body to give a height to");
  }
  if (!body_name.empty()) {
    require(body_name == "antiplane" || body_name == "inplane", "bulk.body",
            "unknown body '" + body_name + "' (expected antiplane or inplane)");
    require(one_dimensional, "bulk.body",
            "a 0D scene (drive.loading = spring_block or imposed_rate) has no body to choose");
    require(height != 0.0, "bulk.body", "chooses the strip's body: give bulk.height too (or drop bulk.body: the 1D chain)");
  }
  if (body() == BodyKind::inplane) {
    check_in_domain("bulk.poisson", poisson);
    check_in_domain("bulk.normal_load", normal_load);
  }
}

const char* to_string(Loading l) {
  switch (l) {
    case Loading::edge: return "edge";
    case Loading::homogeneous: return "homogeneous";
    case Loading::imposed_rate: return "imposed_rate";
    case Loading::spring_block: return "spring_block";
  }
  return "?";
}

Loading loading_from_string(const std::string& s) {
  if (s == "edge") return Loading::edge;
  if (s == "homogeneous") return Loading::homogeneous;
  if (s == "imposed_rate") return Loading::imposed_rate;
  if (s == "spring_block") return Loading::spring_block;
  throw ParamError("drive.loading",
                   "unknown loading '" + s + "' (expected edge, homogeneous, imposed_rate or spring_block)");
}

const char* to_string(Integrator i) {
  switch (i) {
    case Integrator::central_difference: return "explicit";
    case Integrator::implicit_trapezoidal: return "implicit";
    case Integrator::adaptive_rosenbrock: return "adaptive";
  }
  return "?";
}

Integrator integrator_from_string(const std::string& s) {
  if (s == "explicit") return Integrator::central_difference;
  if (s == "implicit") return Integrator::implicit_trapezoidal;
  if (s == "adaptive") return Integrator::adaptive_rosenbrock;
  throw ParamError("time.integrator", "unknown integrator '" + s + "' (expected explicit, implicit or adaptive)");
}

bool is_one_dimensional(Loading l) { return l == Loading::edge || l == Loading::homogeneous; }

void DriveParams::validate() const {
  switch (loading) {
    case Loading::edge:
    case Loading::spring_block:
      check_in_domain("drive.K", K);
      check_in_domain("drive.v_d", v_d);
      break;
    case Loading::homogeneous:
      check_in_domain("drive.sigma_d", sigma_d);
      check_in_domain("drive.nucleation_length", nucleation_length);
      require(start == "nucleation" || start == "steady_front", "drive.start",
              "unknown start '" + start + "' (expected nucleation or steady_front)");
      check_in_domain("drive.front_x", front_x);
      check_in_domain("drive.kick_dv", kick_dv);
      check_in_domain("drive.kick_length", kick_length);
      break;
    case Loading::imposed_rate:
      if (sweep_points > 0) {
        check_in_domain("drive.v_min", v_min);
        check_in_domain("drive.v_max", v_max);
        require(v_max > v_min, "drive.v_max", "must be > drive.v_min (" + format_number(v_min) + "), got " + format_number(v_max));
        check_in_domain("drive.points", sweep_points);
      } else {
        require(!v.empty(), "drive.v", "needs at least one slip rate");
        require(v.size() == v_times.size(), "drive.switch_times",
                "must have as many entries as drive.v (" + std::to_string(v.size()) + ")");
        for (std::size_t k = 0; k < v.size(); ++k) {
          check_in_domain("drive.v", v[k]);
          check_in_domain("drive.switch_times", v_times[k]);
          if (k > 0) require(v_times[k] > v_times[k - 1], "drive.switch_times", "must be increasing");
        }
        require(v_times.front() == 0.0, "drive.switch_times", "the first switch time must be 0");
      }
      break;
  }
}

void GridParams::validate(const BulkParams& bulk, bool one_dimensional) const {
  if (!one_dimensional) return;
  check_in_domain("grid.dx", dx);
  require(bulk.length >= dx, "bulk.length",
          "must be >= grid.dx (" + format_number(dx) + "), got " + format_number(bulk.length));
  const double n = bulk.length / dx;
  require(std::abs(n - std::round(n)) < 1e-9 * std::max(1.0, n), "grid.dx",
          "bulk.length / grid.dx must be a whole number of cells, got " + format_number(n));
  if (bulk.body() == BodyKind::chain) {
    require(dy == 0.0, "grid.dy", "is the row spacing of the strip: give bulk.height too (or drop grid.dy)");
    require(n <= 5e7, "grid.dx",
            "gives " + format_number(n + 1) + " nodes; more than 5e7 nodes would not fit in memory (24 GiB)");
    return;
  }
  // The strip (docs/model.md §9): rows of spacing dy = grid.dy (absent: grid.dx) must tile the height.
  if (dy != 0.0) check_in_domain("grid.dy", dy);
  const double h = row_spacing(), rows = bulk.height / h;
  require(rows >= 1.0 - 1e-9, "grid.dy",
          "must be <= bulk.height (" + format_number(bulk.height) + "): the strip needs at least one row of cells, got " +
              format_number(h) + (dy == 0.0 ? " (grid.dx, as grid.dy is absent)" : ""));
  require(std::abs(rows - std::round(rows)) < 1e-9 * std::max(1.0, rows), "grid.dy",
          "bulk.height / grid.dy must be a whole number of rows, got " + format_number(rows) +
              (dy == 0.0 ? " (grid.dy absent: grid.dx is used)" : ""));
  const double nodes = (n + 1) * (std::round(rows) + 1);
  require(nodes <= 5e7, dy == 0.0 ? "grid.dx" : "grid.dy",
          "gives " + format_number(nodes) + " strip nodes; more than 5e7 nodes would not fit in memory (24 GiB)");
}

void TimeParams::validate(Loading l) const {
  check_in_domain("time.t_end", t_end);
  check_in_domain("time.dt", dt);
  if (dt == 0.0 && l != Loading::imposed_rate) check_in_domain("time.cfl", cfl);
  if (integrator == Integrator::implicit_trapezoidal) {
    require(l == Loading::edge || l == Loading::homogeneous || l == Loading::spring_block, "time.integrator",
            "the implicit integrator is for bulk scenes (edge, homogeneous, spring_block)");
    require(dt > 0.0, "time.dt",
            "required with time.integrator = implicit (no stability limit: choose the step by accuracy, "
            "e.g. 0.02 for fig1; docs/numerics.md)");
  }
  if (integrator == Integrator::implicit_trapezoidal) {
    check_in_domain("time.implicit_tolerance", implicit_tolerance);
    check_in_domain("time.implicit_max_halvings", implicit_max_halvings);
  }
  if (integrator == Integrator::adaptive_rosenbrock) {
    require(l == Loading::edge || l == Loading::homogeneous || l == Loading::spring_block, "time.integrator",
            "the adaptive integrator is for bulk scenes (edge, homogeneous, spring_block)");
    check_in_domain("time.rtol", rtol);
    check_in_domain("time.atol", atol);
    check_in_domain("time.dt_max", dt_max);
    check_in_domain("time.leap_epsilon", leap_epsilon);
    check_in_domain("time.implicit_tolerance", implicit_tolerance);
    check_in_domain("time.group_switchings", group_switchings);
  }
  if (l == Loading::imposed_rate) {
    check_in_domain("time.slip_end", slip_end);
    check_in_domain("time.steps", steps);
  }
}

void MeasureParams::validate() const {
  check_in_domain("measure.A_tip", A_tip);
  check_in_domain("measure.A_tip_alt", A_tip_alt);
  check_in_domain("measure.v_event", v_event);
  check_in_domain("measure.sample_dt", sample_dt);
  check_in_domain("measure.average_from", average_from);
  check_in_domain("measure.batches", batches);
  check_in_domain("measure.arrest_fraction", arrest_fraction);
  check_in_domain("measure.behind_tip_fraction", behind_tip_fraction);
  check_in_domain("measure.behind_near", behind_near);
  check_in_domain("measure.behind_far", behind_far);
  require(behind_far > behind_near, "measure.behind_far", "must be > measure.behind_near (" + format_number(behind_near) + ")");
  check_in_domain("measure.tip_band", tip_band);
  check_in_domain("measure.settle_window", settle_window);
  check_in_domain("measure.settle_band", settle_band);
  check_in_domain("measure.settle_end_zone", settle_end_zone);
}

void OutputParams::validate() const {
  check_in_domain("output.series_dt", series_dt);
  check_in_domain("output.snapshot_dt", snapshot_dt);
  check_in_domain("output.compare_dt", compare_dt);
  check_in_domain("output.contact_snapshot_dt", contact_snapshot_dt);
  check_in_domain("output.deflate", deflate);
}

}  // namespace slipfront::core
