// The peer integrator of the work-precision study: SUNDIALS CVODE (6.x) on the method-of-lines ODE of
// docs/model.md §1 (core/bulk.hpp grid), written independently of core/adaptive.cpp.
//   unknowns interleaved per node: y[4i + 0..3] = u_i, v_i, A_i, σ̄_i
//   the v row of node i couples u_{i−1}, u_i, u_{i+1}: band widths mu = 3, ml = 5
//   BDF orders 1–5, Newton with the banded difference-quotient Jacobian (mu + ml + 1 = 9 right-hand
//   sides per Jacobian) and SUNLinSol_Band.
// Θ: `roots = false` evaluates Θ = θ(|σ̄ + ηv|/A − 1) inside the right-hand side (a discontinuous
// RHS: CVODE's error test finds each switching by failing); `roots = true` freezes Θ per site, asks
// CVODE to locate the zeros of g_i = |σ̄_i + η v_i| − A_i (one root function per site, direction set
// from Θ_i), flips Θ_i there and restarts the integrator (CVodeReInit) from the located state.
#include "bench/cvode_fig1.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>

#include <stdexcept>

namespace slipfront::bench {

namespace {

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed with flag " + std::to_string(flag));
}

class CvodePeer {
 public:
  CvodePeer(const compare::Scene& s, const core::Bulk& bulk, const InitialState& init, const CvodeOptions& opt)
      : bulk_(bulk), ip_(s.interface), opt_(opt), n_(bulk.nodes()), theta_(n_, 0), rootsfound_(n_, 0),
        rootdir_(n_, 0) {
    check(SUNContext_Create(nullptr, &ctx_), "SUNContext_Create");
    const auto m = static_cast<sunindextype>(4 * n_);
    y_ = N_VNew_Serial(m, ctx_);
    dky_ = N_VNew_Serial(m, ctx_);
    double* y = N_VGetArrayPointer(y_);
    for (std::size_t i = 0; i < n_; ++i) {
      y[4 * i] = init.u[i];
      y[4 * i + 1] = init.v[i];
      y[4 * i + 2] = init.A[i];
      y[4 * i + 3] = init.sb[i];
      theta_[i] = core::contact_stress(init.sb[i] + ip_.eta * init.v[i], init.A[i]) > 1.0 ? 1 : 0;
    }
    mem_ = CVodeCreate(CV_BDF, ctx_);
    if (!mem_) throw std::runtime_error("CVODE: CVodeCreate failed");
    check(CVodeInit(mem_, &CvodePeer::rhs, 0.0, y_), "CVodeInit");
    check(CVodeSetUserData(mem_, this), "CVodeSetUserData");
    check(CVodeSStolerances(mem_, opt.rtol, opt.atol), "CVodeSStolerances");
    A_ = SUNBandMatrix(m, 3, 5, ctx_);
    LS_ = SUNLinSol_Band(y_, A_, ctx_);
    check(CVodeSetLinearSolver(mem_, LS_, A_), "CVodeSetLinearSolver");
    check(CVodeSetMaxNumSteps(mem_, opt.max_steps), "CVodeSetMaxNumSteps");
    check(CVodeSetMaxStep(mem_, opt.dt_max), "CVodeSetMaxStep");
    check(CVodeSetStopTime(mem_, s.time.t_end), "CVodeSetStopTime");
    check(CVodeSetMaxErrTestFails(mem_, 20), "CVodeSetMaxErrTestFails");
    check(CVodeSetMaxOrd(mem_, opt.max_order), "CVodeSetMaxOrd");
    check(CVodeSetStabLimDet(mem_, opt.stability_detection ? SUNTRUE : SUNFALSE), "CVodeSetStabLimDet");
    check(CVodeSetMaxConvFails(mem_, 50), "CVodeSetMaxConvFails");
    if (opt.roots) {
      check(CVodeRootInit(mem_, static_cast<int>(n_), &CvodePeer::roots), "CVodeRootInit");
      set_root_directions();
    }
  }
  ~CvodePeer() {
    CVodeFree(&mem_);
    SUNLinSolFree(LS_);
    SUNMatDestroy(A_);
    N_VDestroy(y_);
    N_VDestroy(dky_);
    SUNContext_Free(&ctx_);
  }
  CvodePeer(const CvodePeer&) = delete;
  CvodePeer& operator=(const CvodePeer&) = delete;

  void step() {
    if (pending_reinit_) {  // after a root: Θ flipped, restart from the located state
      add_counters();
      check(CVodeReInit(mem_, t_, y_), "CVodeReInit");
      set_root_directions();
      pending_reinit_ = false;
    }
    t_prev_ = t_;
    theta_step_ = theta_;
    const int flag = CVode(mem_, 1e300, y_, &t_, CV_ONE_STEP);
    if (flag < 0) throw core::NumericalError(steps(), t_, 0, "CVODE flag " + std::to_string(flag));
    if (flag == CV_ROOT_RETURN) {
      check(CVodeGetRootInfo(mem_, rootsfound_.data()), "CVodeGetRootInfo");
      for (std::size_t i = 0; i < n_; ++i)
        if (rootsfound_[i] != 0) {
          theta_[i] = static_cast<std::uint8_t>(1 - theta_[i]);
          ++switchings_;
        }
      pending_reinit_ = true;
    }
    yielded_ = false;
    const double* y = N_VGetArrayPointer(y_);
    for (std::size_t i = 0; i < n_ && !yielded_; ++i)
      yielded_ = opt_.roots ? theta_step_[i] != 0
                            : core::contact_stress(y[4 * i + 3] + ip_.eta * y[4 * i + 1], y[4 * i + 2]) > 1.0;
  }

  double time() const { return t_; }
  double previous_time() const { return t_prev_; }
  bool yielded() const { return yielded_; }
  void dense_state(double t, core::Field f, std::span<double> out) const {
    const double tc = std::clamp(t, t_prev_, t_);
    if (CVodeGetDky(mem_, tc, 0, dky_) < 0) throw std::runtime_error("CVODE: CVodeGetDky failed");
    const double* d = N_VGetArrayPointer(dky_);
    const auto k = static_cast<std::size_t>(f);
    for (std::size_t i = 0; i < n_; ++i) out[i] = d[4 * i + k];
  }
  std::span<const double> field(core::Field f, std::vector<double>& buf) const {
    buf.resize(n_);
    const double* y = N_VGetArrayPointer(y_);
    for (std::size_t i = 0; i < n_; ++i) buf[i] = y[4 * i + static_cast<std::size_t>(f)];
    return buf;
  }

  std::int64_t steps() const { return acc_steps_ + current(CVodeGetNumSteps); }
  std::int64_t rejected() const { return acc_fails_ + current(CVodeGetNumErrTestFails); }
  std::int64_t rhs_evals() const { return acc_rhs_ + current(CVodeGetNumRhsEvals) + current(CVodeGetNumLinRhsEvals); }
  std::int64_t switchings() const { return switchings_; }

 private:
  std::int64_t current(int (*get)(void*, long*)) const {
    long v = 0;
    get(mem_, &v);
    return v;
  }
  void add_counters() {  // CVodeReInit resets CVODE's counters
    acc_steps_ += current(CVodeGetNumSteps);
    acc_fails_ += current(CVodeGetNumErrTestFails);
    acc_rhs_ += current(CVodeGetNumRhsEvals) + current(CVodeGetNumLinRhsEvals);
  }
  void set_root_directions() {
    // Θ_i = 0: only an increasing g_i (onset of sliding) is a switching; Θ_i = 1: a decreasing one.
    for (std::size_t i = 0; i < n_; ++i) rootdir_[i] = theta_[i] ? -1 : 1;
    check(CVodeSetRootDirection(mem_, rootdir_.data()), "CVodeSetRootDirection");
  }

  // docs/model.md §1 on the grid of core/bulk.hpp (see core/adaptive.hpp for the equations).
  static int rhs(sunrealtype t, N_Vector yv, N_Vector fv, void* user) {
    const auto& P = *static_cast<const CvodePeer*>(user);
    const double* y = N_VGetArrayPointer(yv);
    double* f = N_VGetArrayPointer(fv);
    const std::size_t n = P.n_;
    const double inv_rho = 1.0 / P.bulk_.rho(), k = P.bulk_.stiffness(), sd = P.bulk_.uniform_stress();
    const double alpha = P.ip_.alpha, kappa = P.ip_.kappa, eta = P.ip_.eta;
    for (std::size_t i = 0; i < n; ++i) {
      const double u = y[4 * i], v = y[4 * i + 1], a = y[4 * i + 2], sb = y[4 * i + 3];
      double force = 0.0;  // elastic + drive, per node
      if (i > 0) force += k * (y[4 * (i - 1)] - u);
      if (i + 1 < n) force += k * (y[4 * (i + 1)] - u);
      if (i == 0) force += P.bulk_.drive_force(t, u);
      const bool sliding = P.opt_.roots ? P.theta_[i] != 0 : core::contact_stress(sb + eta * v, a) > 1.0;
      const double speed = sliding ? std::abs(v) : 0.0;
      f[4 * i] = v;
      f[4 * i + 1] = (force / P.bulk_.node_weight(i) + sd - sb - eta * v) * inv_rho;
      f[4 * i + 2] = 1.0 - a - kappa * a * speed;
      f[4 * i + 3] = alpha * a * v - sb * speed;
    }
    return 0;
  }
  static int roots(sunrealtype, N_Vector yv, sunrealtype* g, void* user) {
    const auto& P = *static_cast<const CvodePeer*>(user);
    const double* y = N_VGetArrayPointer(yv);
    for (std::size_t i = 0; i < P.n_; ++i) g[i] = std::abs(y[4 * i + 3] + P.ip_.eta * y[4 * i + 1]) - y[4 * i + 2];
    return 0;
  }

  const core::Bulk& bulk_;
  core::InterfaceParams ip_;
  CvodeOptions opt_;
  std::size_t n_;
  SUNContext ctx_ = nullptr;
  void* mem_ = nullptr;
  N_Vector y_ = nullptr, dky_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver LS_ = nullptr;
  double t_ = 0.0, t_prev_ = 0.0;
  bool yielded_ = false, pending_reinit_ = false;
  std::vector<std::uint8_t> theta_, theta_step_;
  std::vector<int> rootsfound_, rootdir_;
  std::int64_t acc_steps_ = 0, acc_fails_ = 0, acc_rhs_ = 0, switchings_ = 0;
};

}  // namespace

RunRecord run_cvode(const compare::Scene& s, const CvodeOptions& opt, const std::vector<double>& snap_times) {
  const auto wall0 = std::chrono::steady_clock::now();
  const core::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const auto init = initial_state(s, bulk);
  RunRecord rec;
  rec.integrator = opt.roots ? "cvode_roots" : "cvode";
  rec.setting = opt.rtol;
  CvodePeer peer(s, bulk, init, opt);
  DenseObserver obs(s, bulk.x(), snap_times);
  obs.start(init.A, init.v);
  try {
    while (peer.time() < s.time.t_end * (1.0 - 1e-15)) {
      peer.step();
      obs.after_step(peer);
    }
  } catch (const std::exception& e) {
    rec.status = "failed";
    rec.message = e.what();
  }
  rec.events = obs.finish(s.drive.loading == core::Loading::homogeneous);
  rec.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  rec.wall_observer = obs.seconds();
  rec.steps = peer.steps();
  rec.rejected = peer.rejected();
  rec.rhs = peer.rhs_evals();
  rec.switchings = peer.switchings();
  rec.snap_t = obs.snap_t;
  rec.snap_A = obs.snap_A;
  rec.snap_sb = obs.snap_sb;
  return rec;
}

}  // namespace slipfront::bench
