#include "continuum/params.hpp"

#include <cmath>
#include <cstdio>

namespace slipfront::continuum {

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
}  // namespace

void InterfaceParams::validate() const {
  require(finite(alpha) && alpha >= 1.0, "interface.alpha",
          "must be >= 1 (the sliding branch is not self-consistent below 1), got " + format_number(alpha));
  require(finite(kappa) && kappa >= 0.0, "interface.kappa", "must be >= 0, got " + format_number(kappa));
  require(finite(eta) && eta >= 0.0, "interface.eta", "must be >= 0, got " + format_number(eta));
}

void BulkParams::validate(bool one_dimensional) const {
  require(finite(rho) && rho > 0.0, "bulk.rho", "must be > 0, got " + format_number(rho));
  if (one_dimensional) {
    require(finite(mu) && mu > 0.0, "bulk.mu", "must be > 0, got " + format_number(mu));
    require(finite(length) && length > 0.0, "bulk.length", "must be > 0, got " + format_number(length));
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
      require(finite(K) && K > 0.0, "drive.K", "must be > 0, got " + format_number(K));
      require(finite(v_d) && v_d >= 0.0, "drive.v_d", "must be >= 0, got " + format_number(v_d));
      break;
    case Loading::homogeneous:
      require(finite(sigma_d) && sigma_d > 0.0, "drive.sigma_d", "must be > 0, got " + format_number(sigma_d));
      require(finite(nucleation_length) && nucleation_length >= 0.0, "drive.nucleation_length",
              "must be >= 0, got " + format_number(nucleation_length));
      break;
    case Loading::imposed_rate:
      if (sweep_points > 0) {
        require(finite(v_min) && v_min > 0.0, "drive.v_min", "must be > 0");
        require(finite(v_max) && v_max > v_min, "drive.v_max", "must be > drive.v_min");
        require(sweep_points >= 2, "drive.points", "a sweep needs at least 2 points");
      } else {
        require(!v.empty(), "drive.v", "needs at least one slip rate");
        require(v.size() == v_times.size(), "drive.switch_times",
                "must have as many entries as drive.v (" + std::to_string(v.size()) + ")");
        require(v_times.front() == 0.0, "drive.switch_times", "the first switch time must be 0");
        for (std::size_t k = 0; k < v.size(); ++k) {
          require(finite(v[k]), "drive.v", "must be finite");
          if (k > 0) require(v_times[k] > v_times[k - 1], "drive.switch_times", "must be increasing");
        }
      }
      break;
  }
}

void GridParams::validate(const BulkParams& bulk, bool one_dimensional) const {
  if (!one_dimensional) return;
  require(finite(dx) && dx > 0.0, "grid.dx", "must be > 0, got " + format_number(dx));
  require(bulk.length >= dx, "bulk.length",
          "must be >= grid.dx (" + format_number(dx) + "), got " + format_number(bulk.length));
  const double n = bulk.length / dx;
  require(n <= 5e7, "grid.dx",
          "gives " + format_number(n + 1) + " nodes; more than 5e7 nodes would not fit in memory (24 GiB)");
  require(std::abs(n - std::round(n)) < 1e-9 * std::max(1.0, n), "grid.dx",
          "bulk.length / grid.dx must be a whole number of cells, got " + format_number(n));
}

void TimeParams::validate(Loading l) const {
  require(finite(t_end) && t_end > 0.0, "time.t_end", "must be > 0, got " + format_number(t_end));
  require(finite(dt) && dt >= 0.0, "time.dt", "must be >= 0 (0: use time.cfl), got " + format_number(dt));
  if (dt == 0.0 && l != Loading::imposed_rate)
    require(finite(cfl) && cfl > 0.0 && cfl <= 1.0, "time.cfl",
            "must be in (0, 1] (fraction of the explicit stability limit), got " + format_number(cfl));
  if (integrator == Integrator::implicit_trapezoidal) {
    require(l == Loading::edge || l == Loading::homogeneous || l == Loading::spring_block, "time.integrator",
            "the implicit integrator is for bulk scenes (edge, homogeneous, spring_block)");
    require(dt > 0.0, "time.dt",
            "required with time.integrator = implicit (no stability limit: choose the step by accuracy, "
            "e.g. 0.02 for fig1; docs/numerics.md)");
  }
  if (integrator == Integrator::adaptive_rosenbrock) {
    require(l == Loading::edge || l == Loading::homogeneous || l == Loading::spring_block, "time.integrator",
            "the adaptive integrator is for bulk scenes (edge, homogeneous, spring_block)");
    require(finite(rtol) && rtol > 0.0 && rtol < 1.0, "time.rtol", "must be in (0, 1), got " + format_number(rtol));
    require(finite(atol) && atol > 0.0, "time.atol", "must be > 0, got " + format_number(atol));
    require(finite(dt_max) && dt_max > 0.0, "time.dt_max", "must be > 0, got " + format_number(dt_max));
  }
  if (l == Loading::imposed_rate) {
    require(finite(slip_end) && slip_end >= 0.0, "time.slip_end", "must be >= 0");
    require(steps >= 1, "time.steps", "must be >= 1");
  }
}

void MeasureParams::validate() const {
  require(A_tip > 0.0 && A_tip < 1.0, "measure.A_tip", "must be in (0, 1)");
  require(A_tip_alt > 0.0 && A_tip_alt < 1.0, "measure.A_tip_alt", "must be in (0, 1)");
  require(finite(v_event) && v_event > 0.0, "measure.v_event", "must be > 0");
  require(finite(sample_dt) && sample_dt > 0.0, "measure.sample_dt", "must be > 0");
  require(average_from >= 0.0 && average_from < 1.0, "measure.average_from", "must be in [0, 1)");
  require(batches >= 2, "measure.batches", "must be >= 2");
  require(arrest_fraction > 0.0 && arrest_fraction < 1.0, "measure.arrest_fraction", "must be in (0, 1)");
  require(behind_tip_fraction > 0.0 && behind_tip_fraction <= 1.0, "measure.behind_tip_fraction", "must be in (0, 1]");
  require(finite(behind_gap) && behind_gap >= 0.0, "measure.behind_gap", "must be >= 0");
  require(finite(tip_band) && tip_band >= 0.0, "measure.tip_band", "must be >= 0 (length units)");
}

void OutputParams::validate() const {
  require(finite(series_dt) && series_dt >= 0.0, "output.series_dt", "must be >= 0");
  require(finite(snapshot_dt) && snapshot_dt >= 0.0, "output.snapshot_dt", "must be >= 0");
  require(finite(compare_dt) && compare_dt >= 0.0, "output.compare_dt", "must be >= 0 (0: no field comparison)");
  require(finite(contact_snapshot_dt), "output.contact_snapshot_dt",
          "must be a number (< 0: output.snapshot_dt; 0: no contact snapshots)");
}

}  // namespace slipfront::continuum
