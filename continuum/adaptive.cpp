#include "continuum/adaptive.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace slipfront::continuum {
namespace {
// Shampine & Reichelt, "The MATLAB ODE suite" (SIAM J. Sci. Comput. 18, 1997), ode23s:
//   W = I − h d J,  d = 1/(2 + √2),  e32 = 6 + √2
//   k1 = W⁻¹ (f(t, y) + h d f_t)
//   k2 = W⁻¹ (f(t + h/2, y + h k1/2) − k1) + k1
//   y' = y + h k2                                   (order 2, L-stable)
//   k3 = W⁻¹ (f(t + h, y') − e32 (k2 − f1) − 2 (k1 − f0) + h d f_t)
//   error ≈ h/6 (k1 − 2 k2 + k3)                    (order 3 estimate of the local error)
//   y(t + θh) ≈ y + h (θ(1 − θ) k1 + θ(θ − 2d) k2)/(1 − 2d)    (dense output, order 2)
constexpr double kD = AdaptiveSimulation::kGamma;  // 1/(2 + √2) = 1 − 1/√2
constexpr double kE32 = 7.41421356237309504880;  // 6 + √2
constexpr double kInv12d = AdaptiveSimulation::kDenseScale;

// PI step-size controller (Gustafsson), local error ∝ h³.
constexpr double kSafety = 0.9, kBeta1 = 0.7 / 3.0, kBeta2 = 0.4 / 3.0, kGrowMax = 5.0, kShrinkMin = 0.2;
}  // namespace

void AdaptiveOptions::validate() const {
  auto bad = [](const char* key, const std::string& why) { throw ParamError(std::string("time.") + key, why); };
  if (!(rtol > 0.0 && rtol < 1.0)) bad("rtol", "must be in (0, 1), got " + format_number(rtol));
  if (!(atol > 0.0)) bad("atol", "must be > 0, got " + format_number(atol));
  if (!(dt_max > 0.0)) bad("dt_max", "must be > 0, got " + format_number(dt_max));
  if (!(dt_initial > 0.0)) bad("dt_initial", "must be > 0, got " + format_number(dt_initial));
  if (!(dt_min > 0.0 && dt_min <= dt_initial)) bad("dt_min", "must be in (0, dt_initial], got " + format_number(dt_min));
  if (!(switch_band >= 0.0 && switch_band < 1e-3)) bad("switch_band", "must be in [0, 1e-3), got " + format_number(switch_band));
  if (!(event_window >= 0.0)) bad("event_window", "must be >= 0, got " + format_number(event_window));
}

AdaptiveSimulation::AdaptiveSimulation(Bulk bulk, FrictionLaw law, double eta, AdaptiveOptions opt)
    : bulk_(std::move(bulk)), law_(std::move(law)), eta_(eta), opt_(opt), n_(bulk_.nodes()),
      h_next_(opt.dt_initial), last_dt_(opt.dt_initial) {
  if (law_.size() != n_) throw std::invalid_argument("AdaptiveSimulation: law and bulk sizes differ");
  opt_.validate();
  const std::size_t m = 4 * n_;
  for (auto* v : {&y_, &y_prev_, &ynew_, &f0_, &f1_, &f2_, &k1_, &k2_, &k3_, &k1_prev_, &k2_prev_}) v->assign(m, 0.0);
  for (auto* v : {&tmp_, &inv_a1_, &q_area_, &inv_s1_, &c_alpha_v_, &q_sigma_, &d_coef_, &thomas_c_, &thomas_inv_})
    v->assign(n_, 0.0);
  theta_.assign(n_, 0);
  theta_prev_.assign(n_, 0);
  load_law_state();
}

void AdaptiveSimulation::set_initial(std::size_t i, double u, double v) {
  y_[i] = u;
  y_[n_ + i] = v;
  max_v_ = std::max(max_v_, std::abs(v));
  f0_valid_ = false;
}

void AdaptiveSimulation::load_law_state() {
  const auto a = law_.contact_area(), sb = law_.sigma_bar();
  std::copy(a.begin(), a.end(), y_.begin() + 2 * n_);
  std::copy(sb.begin(), sb.end(), y_.begin() + 3 * n_);
}

void AdaptiveSimulation::store_law_state() {
  for (std::size_t i = 0; i < n_; ++i) law_.set_site(i, y_[2 * n_ + i], y_[3 * n_ + i]);
}

// Θ from the initial state (MODEL §1: Θ = 1 iff |σ|/A > 1); then e_i < 0 at every site (a stuck
// site on the surface is below it by the band), the invariant that every step starts from.
void AdaptiveSimulation::start() {
  load_law_state();
  const double eta = law_.params().eta;
  for (std::size_t i = 0; i < n_; ++i)
    theta_[i] = contact_stress(y_[3 * n_ + i] + eta * y_[n_ + i], y_[2 * n_ + i]) > 1.0 ? 1 : 0;
  theta_prev_ = theta_;
  f0_valid_ = false;
  started_ = true;
}

// e_i > 0 means site i has crossed its switching surface: Θ = 0 and |σ| > A (1 + band), or Θ = 1 and
// |σ| < A (1 − band).
double AdaptiveSimulation::switch_function(std::size_t i, double v, double area, double sb) const {
  const double s = std::abs(sb + law_.params().eta * v), b = opt_.switch_band * area;
  return theta_[i] ? (area - b) - s : s - (area + b);
}

// MODEL §1 per node, Θ frozen (see the header).
void AdaptiveSimulation::rhs(double t, const std::vector<double>& y, std::vector<double>& f) {
  ++stats_.rhs;
  const std::size_t n = n_;
  const double* u = y.data();
  const double* v = u + n;
  const double* a = v + n;
  const double* s = a + n;
  double* fu = f.data();
  double* fv = fu + n;
  double* fa = fv + n;
  double* fs = fa + n;
  const double inv_rho = 1.0 / bulk_.rho(), k = bulk_.stiffness(), sd = bulk_.uniform_stress();
  const double alpha = law_.params().alpha, kappa = law_.params().kappa, eta = eta_;
  const double f_drive = bulk_.drive_force(t, u[0]);
  if (n == 1) {
    fv[0] = (f_drive / bulk_.node_weight(0) + sd - s[0] - eta * v[0]) * inv_rho;
  } else {
    const double inv_w_end = 1.0 / bulk_.node_weight(0), kw = k / bulk_.node_weight(1);
    fv[0] = ((k * (u[1] - u[0]) + f_drive) * inv_w_end + sd - s[0] - eta * v[0]) * inv_rho;
    for (std::size_t i = 1; i + 1 < n; ++i)
      fv[i] = (kw * (u[i + 1] - 2.0 * u[i] + u[i - 1]) + sd - s[i] - eta * v[i]) * inv_rho;
    fv[n - 1] = (k * (u[n - 2] - u[n - 1]) * inv_w_end + sd - s[n - 1] - eta * v[n - 1]) * inv_rho;
  }
  const std::uint8_t* th = theta_.data();
  for (std::size_t i = 0; i < n; ++i) {
    const double vi = v[i], ai = a[i], si = s[i], speed = th[i] ? std::abs(vi) : 0.0;
    fu[i] = vi;
    fa[i] = 1.0 - ai - kappa * ai * speed;
    fs[i] = alpha * ai * vi - si * speed;
  }
}

void AdaptiveSimulation::rhs_site(std::size_t i, const std::vector<double>& y, std::vector<double>& f) const {
  const double vi = y[n_ + i], ai = y[2 * n_ + i], si = y[3 * n_ + i];
  const double speed = theta_[i] ? std::abs(vi) : 0.0;
  f[2 * n_ + i] = 1.0 - ai - law_.params().kappa * ai * speed;
  f[3 * n_ + i] = law_.params().alpha * ai * vi - si * speed;
}

// W = I − c J(y). Per node, the rows of A and σ̄ give
//   x_A = p_A + q_A x_v,  x_σ = p_σ + q_σ x_v,  and the u row x_v = (x_u − b_u)/c;
// the v row (times ρ w_i / c) is then a symmetric tridiagonal equation for x_u:
//   (ρ w_i D_i / c²) x_u,i − (E x_u)_i = w_i ((ρ/c) b_v − p_σ) + (ρ w_i D_i / c²) b_u,
//   D_i = 1 + cη/ρ + (c/ρ) q_σ,   E = elastic stiffness (+ the drive spring −K on node 0).
void AdaptiveSimulation::factor(double c, const std::vector<double>& y) {
  ++stats_.factorizations;
  c_ = c;
  const std::size_t n = n_;
  const double rho = bulk_.rho(), k = bulk_.stiffness(), K = bulk_.spring_K();
  const double alpha = law_.params().alpha, kappa = law_.params().kappa;
  const double* v = y.data() + n;
  const double* a = v + n;
  const double* s = a + n;
  const double base = 1.0 + c * eta_ / rho, c_rho = c / rho, rho_c2 = rho / (c * c);
  const double off = -k;
  const double stuck_ia1 = 1.0 / (1.0 + c);  // Θ = 0: the A row relaxes at rate 1, σ̄ not at all
  for (std::size_t i = 0; i < n; ++i) {
    const double vi = v[i], ai = a[i], si = s[i];
    const double cav = c * alpha * vi;
    double ia1, qa, is1, qs;
    if (!theta_[i]) {  // the general expressions below with Θ = 0, without their two divisions
      ia1 = stuck_ia1;
      qa = 0.0;
      is1 = 1.0;
      qs = c * (alpha * ai);
    } else {
      const double sg = vi >= 0.0 ? 1.0 : -1.0, speed = std::abs(vi);
      ia1 = 1.0 / (1.0 + c * (1.0 + kappa * speed));
      qa = -c * kappa * ai * sg * ia1;
      is1 = 1.0 / (1.0 + c * speed);
      qs = (cav * qa + c * (alpha * ai - si * sg)) * is1;
    }
    const double w = bulk_.node_weight(i);
    const double dc = rho_c2 * w * (base + c_rho * qs);
    inv_a1_[i] = ia1;
    q_area_[i] = qa;
    inv_s1_[i] = is1;
    c_alpha_v_[i] = cav;
    q_sigma_[i] = qs;
    d_coef_[i] = dc;
    const double neighbours = n == 1 ? 0.0 : (i == 0 || i + 1 == n) ? 1.0 : 2.0;
    const double diag = dc + k * neighbours + (i == 0 ? K : 0.0);
    const double m = i == 0 ? diag : diag - off * thomas_c_[i - 1];
    thomas_inv_[i] = 1.0 / m;
    thomas_c_[i] = off / m;
  }
}

void AdaptiveSimulation::solve(std::vector<double>& x) {
  ++stats_.solves;
  const std::size_t n = n_;
  double* xu = x.data();
  double* xv = xu + n;
  double* xa = xv + n;
  double* xs = xa + n;
  const double c = c_, rho_c = bulk_.rho() / c, inv_c = 1.0 / c, off = -bulk_.stiffness();
  double* d = tmp_.data();
  double prev = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double pa = xa[i] * inv_a1_[i];
    const double ps = (xs[i] + c_alpha_v_[i] * pa) * inv_s1_[i];
    xa[i] = pa;
    xs[i] = ps;
    const double r = bulk_.node_weight(i) * (rho_c * xv[i] - ps) + d_coef_[i] * xu[i];
    prev = (r - off * prev) * thomas_inv_[i];  // forward sweep
    d[i] = prev;
  }
  double next = 0.0;
  for (std::size_t i = n; i-- > 0;) {
    const double ui = d[i] - thomas_c_[i] * next;
    next = ui;
    const double vi = (ui - xu[i]) * inv_c;
    xu[i] = ui;
    xv[i] = vi;
    xa[i] += q_area_[i] * vi;
    xs[i] += q_sigma_[i] * vi;
  }
}

double AdaptiveSimulation::attempt(double h) {
  const std::size_t m = 4 * n_;
  if (!f0_valid_) {
    rhs(t_, y_, f0_);
    f0_valid_ = true;
  }
  factor(kD * h, y_);
  // h d ∂f/∂t: only the drive spring depends on t explicitly (v row of node 0).
  const double hdT = bulk_.has_drive_spring()
                         ? kD * h * bulk_.spring_K() * bulk_.driver_velocity() / (bulk_.rho() * bulk_.node_weight(0))
                         : 0.0;
  for (std::size_t j = 0; j < m; ++j) k1_[j] = f0_[j];
  k1_[n_] += hdT;
  solve(k1_);
  for (std::size_t j = 0; j < m; ++j) ynew_[j] = y_[j] + 0.5 * h * k1_[j];
  rhs(t_ + 0.5 * h, ynew_, f1_);
  for (std::size_t j = 0; j < m; ++j) k2_[j] = f1_[j] - k1_[j];
  solve(k2_);
  for (std::size_t j = 0; j < m; ++j) {
    k2_[j] += k1_[j];
    ynew_[j] = y_[j] + h * k2_[j];
  }
  rhs(t_ + h, ynew_, f2_);
  for (std::size_t j = 0; j < m; ++j) k3_[j] = f2_[j] - kE32 * (k2_[j] - f1_[j]) - 2.0 * (k1_[j] - f0_[j]);
  k3_[n_] += hdT;
  solve(k3_);
  return error_norm(h);
}

// Weighted norm of the local error estimate h/6 (k1 − 2 k2 + k3), see ErrorNorm.
double AdaptiveSimulation::error_norm(double h) const {
  const double rtol = opt_.rtol, atol = opt_.atol, h6 = h / 6.0;
  double norm = 0.0, probe = 0.0;  // probe: a NaN or infinity anywhere (std::max would drop a NaN)
  for (std::size_t j = 0; j < ynew_.size(); ++j) probe += ynew_[j] + k3_[j];
  if (!std::isfinite(probe)) return std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < 4; ++f) {
    const std::size_t j0 = f * n_, j1 = j0 + n_;
    const double *y = y_.data(), *yn = ynew_.data(), *k1 = k1_.data(), *k2 = k2_.data(), *k3 = k3_.data();
    if (opt_.norm == ErrorNorm::field) {  // one weight per field: atol + rtol · max over the grid
      double scale = 0.0, emax = 0.0;
      for (std::size_t j = j0; j < j1; ++j) {
        scale = std::max(scale, std::max(std::abs(y[j]), std::abs(yn[j])));
        emax = std::max(emax, std::abs(k1[j] - 2.0 * k2[j] + k3[j]));
      }
      norm = std::max(norm, h6 * emax / (atol + rtol * scale));
    } else if (opt_.norm == ErrorNorm::local) {
      for (std::size_t j = j0; j < j1; ++j)
        norm = std::max(norm, std::abs(h6 * (k1[j] - 2.0 * k2[j] + k3[j])) /
                                  (atol + rtol * std::max(std::abs(y[j]), std::abs(yn[j]))));
    } else {
      for (std::size_t j = j0; j < j1; ++j) {
        const double e = h6 * (k1[j] - 2.0 * k2[j] + k3[j]) / (atol + rtol * std::max(std::abs(y[j]), std::abs(yn[j])));
        norm += e * e;
      }
    }
  }
  if (opt_.norm == ErrorNorm::rms) norm = std::sqrt(norm / static_cast<double>(4 * n_));
  return std::isfinite(norm) ? norm : std::numeric_limits<double>::infinity();
}

// θ ∈ (0, 1] at which e_i first exceeds 0 on the dense output of the trial step (k1_, k2_, h) from
// y_ (where e_i < 0) to ynew_ (where e_i > 0): Illinois regula falsi, upper end of the bracket.
double AdaptiveSimulation::event_fraction(std::size_t i, double h) const {
  const std::size_t iv = n_ + i, ia = 2 * n_ + i, is = 3 * n_ + i;
  auto e = [&](double th) {
    const double b1 = th * (1.0 - th) * kInv12d * h, b2 = th * (th - 2.0 * kD) * kInv12d * h;
    return switch_function(i, y_[iv] + b1 * k1_[iv] + b2 * k2_[iv], y_[ia] + b1 * k1_[ia] + b2 * k2_[ia],
                           y_[is] + b1 * k1_[is] + b2 * k2_[is]);
  };
  double lo = 0.0, hi = 1.0, elo = e(0.0), ehi = e(1.0);
  if (!(elo < 0.0)) return 0.0;  // not expected (e_i < 0 at every step start): switch at once
  const double tol = 1e-13 * std::max(1.0, std::abs(t_)) / h;
  // Illinois regula falsi; a bisection whenever the bracket fails to halve over two iterations.
  int side = 0;
  double width = hi - lo;
  for (int it = 0; it < 200 && hi - lo > tol; ++it) {
    double th = (lo * ehi - hi * elo) / (ehi - elo);
    if (it % 2 == 1) {
      if (hi - lo > 0.5 * width) th = 0.5 * (lo + hi);
      width = hi - lo;
    }
    if (!(th > lo && th < hi)) th = 0.5 * (lo + hi);
    const double et = e(th);
    if (et > 0.0) {
      hi = th;
      ehi = et;
      if (side == 1) elo *= 0.5;
      side = 1;
    } else {
      lo = th;
      elo = et;
      if (side == -1) ehi *= 0.5;
      side = -1;
    }
  }
  return hi;
}

// At a step end: flip Θ of every site whose |σ|/A has crossed 1 (e_i > −band·A/2; after the flip
// e_i < −band·A, the invariant of every step start). Only A' and σ̄' of a flipped site change.
bool AdaptiveSimulation::flip_crossed(const std::vector<double>& y) {
  bool any = false;
  for (std::size_t i = 0; i < n_; ++i) {
    const double v = y[n_ + i], a = y[2 * n_ + i], sb = y[3 * n_ + i];
    if (switch_function(i, v, a, sb) > -0.5 * opt_.switch_band * a) {
      theta_[i] = static_cast<std::uint8_t>(1 - theta_[i]);
      ++stats_.switchings;
      if (f0_valid_) rhs_site(i, y, f0_);
      any = true;
    }
  }
  return any;
}

// One accepted step, in named stages (docs/performance.md §2):
//   1. trial    error-controlled Rosenbrock step from t (rejections shrink h), Θ frozen
//   2. events   earliest crossing of a switching surface on the step's dense output
//   3. shorten  the step ends at that switching (on the dense output, or recomputed)
//   4. accept   advance t, keep the dense output, propose the next h (PI, from the trial's error)
//   5. switch   flip Θ of every site that has crossed by the new t
void AdaptiveSimulation::step() {
  if (!started_) start();
  double h = std::min(h_next_, opt_.dt_max);
  const double h_wanted = h;
  if (t_stop_ > t_ && h >= t_stop_ - t_) h = t_stop_ - t_;
  bool rejected = false;
  const double err = trial_step(h, rejected);
  const double h_trial = h, frac = first_switching(h);
  double h_dense = h_trial;  // the step of the dense-output polynomial of this step
  bool f_end_valid = true;
  if (frac < 1.0) {
    ++stats_.event_steps;
    h *= frac;
    if (opt_.event_end == EventEnd::retake && frac > 0.0) {
      attempt(h);  // recompute the step to end at the switching (its error is smaller still)
      h_dense = h;
    } else {
      end_on_dense_output(frac, h_trial);  // order 2, like the step itself; no extra work
      f_end_valid = false;
    }
  }
  const bool at_stop = accept(h, h_dense, f_end_valid);
  propose_next(at_stop && !rejected ? std::max(h_trial, h_wanted) : h_trial, err, rejected);
  flip_crossed(y_);
  store_law_state();
}

// Stage 1: attempt steps from (t_, y_) until the error test passes; h is the accepted trial size.
double AdaptiveSimulation::trial_step(double& h, bool& rejected) {
  for (;;) {
    if (h < opt_.dt_min) {
      std::size_t bad = 0;
      for (std::size_t j = 0; j < ynew_.size(); ++j)
        if (!std::isfinite(ynew_[j])) {
          bad = j % n_;
          break;
        }
      throw NumericalError(stats_.accepted, t_, bad, "adaptive step below dt_min (" + format_number(h) + ")");
    }
    const double err = attempt(h);
    if (err <= 1.0) return err;
    ++stats_.rejected;
    rejected = true;
    h *= std::isfinite(err) ? std::clamp(kSafety * std::pow(err, -1.0 / 3.0), 0.1, 0.5) : 0.25;
  }
}

// Stage 2: fraction θ ∈ [0, 1) of the trial step at which the first site crosses its switching
// surface (2 if none does); with event_window > 0, the last crossing within the window instead.
double AdaptiveSimulation::first_switching(double h) {
  const double* v = ynew_.data() + n_;
  const double* a = v + n_;
  const double* s = a + n_;
  crossings_.clear();
  for (std::size_t i = 0; i < n_; ++i)
    if (switch_function(i, v[i], a[i], s[i]) > 0.0) crossings_.push_back(event_fraction(i, h));
  if (crossings_.empty()) return 2.0;
  double frac = *std::min_element(crossings_.begin(), crossings_.end());
  if (opt_.event_window > 0.0) {
    const double limit = frac + opt_.event_window / h;
    for (double c : crossings_)
      if (c <= limit) frac = std::max(frac, c);
  }
  return frac;
}

// Stage 3 (interpolate): the end state is the dense output of the trial step at θ = frac.
void AdaptiveSimulation::end_on_dense_output(double frac, double h) {
  const double b1 = frac * (1.0 - frac) * kInv12d * h, b2 = frac * (frac - 2.0 * kD) * kInv12d * h;
  for (std::size_t j = 0; j < ynew_.size(); ++j) ynew_[j] = y_[j] + b1 * k1_[j] + b2 * k2_[j];
}

// Stage 4: the step [t_, t_ + h] is taken; h_dense is the step of its dense-output polynomial.
// Returns whether it ended on the stop time.
bool AdaptiveSimulation::accept(double h, double h_dense, bool f_end_valid) {
  std::swap(y_prev_, y_);
  std::swap(y_, ynew_);
  std::swap(f0_, f2_);  // FSAL: f at the new state, unless the step ended on the dense output
  std::swap(k1_prev_, k1_);
  std::swap(k2_prev_, k2_);
  f0_valid_ = f_end_valid;
  t_prev_ = t_;
  const bool at_stop = t_stop_ > t_ && std::abs(t_ + h - t_stop_) <= 1e-13 * std::max(1.0, std::abs(t_stop_));
  t_ = at_stop ? t_stop_ : t_ + h;
  h_prev_ = h_dense;
  last_dt_ = h;
  ++stats_.accepted;
  theta_prev_ = theta_;
  yielded_ = std::find(theta_.begin(), theta_.end(), std::uint8_t{1}) != theta_.end();
  double vmax = 0.0;
  for (std::size_t i = 0; i < n_; ++i) vmax = std::max({vmax, std::abs(y_prev_[n_ + i]), std::abs(y_[n_ + i])});
  max_v_ = vmax;
  return at_stop;
}

// PI controller on the trial step's error. h is the trial size (an event shortening the step does
// not shrink the next one; neither does the stop time); after a rejection the step does not grow.
void AdaptiveSimulation::propose_next(double h, double err, bool rejected) {
  const double e = std::max(err, 1e-10);
  const double grow = std::clamp(kSafety * std::pow(e, -kBeta1) * std::pow(err_prev_, kBeta2), kShrinkMin,
                                 rejected ? 1.0 : kGrowMax);
  err_prev_ = e;
  h_next_ = std::min(h * grow, opt_.dt_max);
}

void AdaptiveSimulation::dense_state(double t, Field f, std::span<double> out) const {
  const std::size_t off = static_cast<std::size_t>(f) * n_;
  if (stats_.accepted == 0 || h_prev_ <= 0.0) {
    for (std::size_t i = 0; i < n_; ++i) out[i] = y_[off + i];
    return;
  }
  const double th = std::clamp((t - t_prev_) / h_prev_, 0.0, 1.0);
  const double b1 = th * (1.0 - th) * kInv12d * h_prev_, b2 = th * (th - 2.0 * kD) * kInv12d * h_prev_;
  for (std::size_t i = 0; i < n_; ++i)
    out[i] = y_prev_[off + i] + b1 * k1_prev_[off + i] + b2 * k2_prev_[off + i];
}


}  // namespace slipfront::continuum
